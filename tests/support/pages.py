"""A pendant page (PendantUI) on a free loopback port, built the way the tests need it, and one browser's
panels built on the server's own GUI, so no browser is needed."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator
from concurrent.futures import Future
from typing import Any

import viser

from pendant.controller import Controller
from pendant.kinematics import ArmModel
from pendant.ui.app import PendantUI
from pendant.ui.page.session import ClientSession

from .ports import LOOPBACK, free_port

SIM_MODE_LINE = "Simulator · pulse75"


def new_page(
    controller: Controller,
    arm: ArmModel,
    *,
    mode_line: str = SIM_MODE_LINE,
    port: int | None = None,
    **options: Any,
) -> PendantUI:
    """A PendantUI on loopback (a free port unless `port` is given); `options`: PendantUI's keywords
    (token, remote, origins, clock, events, metrics, programs_dir, ...). The caller stops it."""
    return PendantUI(
        controller,
        arm,
        host=LOOPBACK,
        port=free_port() if port is None else port,
        mode_line=mode_line,
        **options,
    )


@contextlib.contextmanager
def pendant_page(controller: Controller, arm: ArmModel, **options: Any) -> Iterator[PendantUI]:
    """new_page(), stopped on exit."""
    page = new_page(controller, arm, **options)
    try:
        yield page
    finally:
        page.stop()


def headless_session(page: PendantUI) -> ClientSession:
    """The panels one browser would get, built on the server's GUI and counted as the page's browser."""
    session = page.open_session(page.server)
    with page.browsers.lock:
        page.sessions[-1] = session
    return session


def button(ui: ClientSession, label: str) -> viser.GuiButtonHandle:
    """The Jog tab's button of that label (J1+, X-, ...)."""
    (found,) = (b for b in ui.jog.buttons.values() if b.label == label)
    return found


def sent(future: Future[object] | None) -> Future[object]:
    """The command a panel handed to the runner; None means the panel refused it (a failed test here)."""
    assert future is not None, "the panel refused the command"
    return future
