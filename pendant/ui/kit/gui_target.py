"""Where a panel is built: on one browser's own GUI (a ClientHandle), or on the server's shared GUI."""

from __future__ import annotations

import viser

GuiTarget = viser.ViserServer | viser.ClientHandle
