"""Every browser's panels draw ghosts of the arm from one parse of its URDF (issue 37), not one parse each:
under 100 browsers coming and going the parses were among the panel builds' largest costs. A real page on
loopback; two browsers' panels built on the server's GUI."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
import yourdfpy

from pendant.sim import SimController
from pendant.ui.scene import shared_urdf
from tests.support.pages import headless_session, pendant_page


def test_two_browsers_panels_parse_the_urdf_at_most_once(
    sim: SimController, monkeypatch: pytest.MonkeyPatch
) -> None:
    with pendant_page(sim, sim.arm) as page:
        shared_urdf.parsed.cache_clear()
        loads: list[Any] = []
        load = yourdfpy.URDF.load

        def counting(*args: Any, **kwargs: Any) -> Any:
            loads.append(args[0] if args else kwargs)
            return load(*args, **kwargs)

        monkeypatch.setattr(yourdfpy.URDF, "load", counting)
        headless_session(page)
        second = headless_session(page)  # on the same (server's) GUI: its ghosts replace the first's
        second.target_panel.set_joint_target(np.radians([-30.0, -60.0, 60.0, -90.0, -90.0, 0.0]))
        assert len(loads) <= 1, f"the URDF was parsed {len(loads)} times for two browsers"
