"""Fixtures any test directory may use; tests/conftest.py registers this module as a plugin."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from pendant.api import create_app
from pendant.controller import Controller
from pendant.remote import RemoteController
from pendant.sim import SimController
from pendant.ui.app import PendantUI
from pendant.ui.page.session import ClientSession

from .doubles import OPERATOR, VIEWER
from .launchers import Launcher
from .pages import headless_session, new_page


@pytest.fixture
def pendant_ui(sim: SimController) -> Iterator[PendantUI]:
    """A page on the `sim` fixture (fake clock): browser OPERATOR has control, VIEWER only watches."""
    page = new_page(sim, sim.arm)
    page.desk.join(OPERATOR)
    page.desk.join(VIEWER)
    page.refresh()
    yield page
    page.stop()


@pytest.fixture
def ui(pendant_ui: PendantUI) -> ClientSession:
    """The panels one browser would get, built on the server's GUI so no browser is needed."""
    return headless_session(pendant_ui)


@pytest.fixture
def remote(sim: SimController) -> Iterator[RemoteController]:
    """RemoteController -> TestClient -> create_app(sim): the simulator on the fake clock, over HTTP."""
    with TestClient(create_app(sim)) as client:
        yield RemoteController("http://testserver", client=client)


@pytest.fixture(params=["sim", "remote"])
def controller(request: pytest.FixtureRequest, sim: SimController) -> Controller:
    """The contract suites' two Controllers: the simulator in-process, and RemoteController over the
    simulator's REST API. A test using it must pass for both, down to the controller's messages."""
    if request.param == "sim":
        return sim
    remote: RemoteController = request.getfixturevalue("remote")
    return remote


@pytest.fixture
def launch(tmp_path: Path) -> Iterator[Launcher]:
    """`launch(args, name="pendant")` starts `python -m pendant ARGS...`, its output in tmp_path/NAME.log;
    every process started is killed at teardown."""
    launcher = Launcher(tmp_path)
    yield launcher
    launcher.close()
