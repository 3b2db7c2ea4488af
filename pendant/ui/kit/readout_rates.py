"""How often a browser is sent the live readouts while the arm moves: the status block's joints and TCP and
the jog pad's values (the refresh reads the arm at 30 Hz). The one table both panels read.

The operator reads them to jog and teach: 10 Hz. A viewer (a browser without control: a classroom's phones
and laptops) watches the arm itself, drawn at the refresh's full rate for everybody, and reads the numbers
as one reads a multimeter's: 4 Hz. Each browser's readouts are messages of its own (viser's GUI handles are
per browser), and at 10 Hz they were half of what a viewer cost the pendant (issue 37: 60 viewers of a held
jog, 0.0084-0.0099 cores per viewer, 0.0043-0.0057 with no readouts sent at all). A change of anything else
(the motion state, a fault, IO, the tool) is sent at once, to every browser.
"""

from __future__ import annotations

OPERATOR_READOUT_S = 0.1
VIEWER_READOUT_S = 0.25


def readout_period_s(viewer: bool) -> float:
    """At most this often a browser's live readouts are sent while they change."""
    return VIEWER_READOUT_S if viewer else OPERATOR_READOUT_S
