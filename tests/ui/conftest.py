"""A pendant page on the simulator's fake clock, and one browser's panels built on the server's own GUI."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from pendant.sim import SimController
from pendant.ui.app import PendantUI
from pendant.ui.page.session import ClientSession
from tests.api.server import free_port

from .doubles import OPERATOR, VIEWER


@pytest.fixture
def pendant_ui(sim: SimController) -> Iterator[PendantUI]:
    """Browser OPERATOR has control, VIEWER only watches."""
    page = PendantUI(sim, sim.arm, host="127.0.0.1", port=free_port(), mode_line="Simulator · pulse75")
    page.desk.join(OPERATOR)
    page.desk.join(VIEWER)
    page.refresh()
    yield page
    page.stop()


@pytest.fixture
def ui(pendant_ui: PendantUI) -> ClientSession:
    """The panels one browser would get, built on the server's GUI so no browser is needed."""
    session = pendant_ui.open_session(pendant_ui.server)
    with pendant_ui._sessions_lock:
        pendant_ui.sessions[-1] = session
    return session
