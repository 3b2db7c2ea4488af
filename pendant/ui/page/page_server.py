"""The page's server: viser behind the websocket guard, serving the pendant's own page first."""

from __future__ import annotations

from collections.abc import Callable

import viser

from pendant.access.origin import OriginPolicy
from pendant.ui.kit.viser_broadcast import serialise_broadcasts_once
from pendant.ui.kit.viser_caches import cache_viser_lookups
from pendant.ui.page.client_page import page_first
from pendant.ui.page.ws_guard import guarded_viser_server


def serve_page(
    host: str, port: int, origins: OriginPolicy | None, stop_jog: Callable[[], None]
) -> viser.ViserServer:
    """Listening on `host:port`; `origins` the Host and Origin rules (None: none); a closing page's stop goes
    to `stop_jog`."""
    cache_viser_lookups()  # each browser's panels: icons and property types looked up once, not per browser
    serialise_broadcasts_once()  # the shared scene's messages serialised once for all browsers
    with guarded_viser_server(origins, wrap=lambda inner: page_first(inner, stop_jog)):
        server = viser.ViserServer(host=host, port=port, label="PULSE pendant", verbose=False)
    server.gui.configure_theme(control_width="large", show_logo=False)
    # Docked, not floating over the view: the arm stays in sight on a portrait tablet, and software WebGL
    # draws no pixels the panel would cover.
    server.gui.main_panel.dock_right()
    return server
