"""Shared fixtures: a simulated controller on a fake clock (tests advance time instead of sleeping)."""

from __future__ import annotations

from pathlib import Path

import pytest

from pendant.cell.file import CELLS_DIR_ENV
from pendant.monitoring import DATA_DIR_ENV
from pendant.program import PROGRAMS_DIR_ENV
from pendant.sim import FakeClock, SimController

# The test kit's fixtures (pendant_ui, ui, remote, controller, launch) for every test directory, and
# `--cpu-report FILE` (each test's CPU seconds), and why each rerun test failed its first time.
pytest_plugins = ["tests.support.fixtures", "tests.support.cpu_report", "tests.support.rerun_report"]


@pytest.fixture(autouse=True)
def programs_folder(tmp_path_factory: pytest.TempPathFactory, monkeypatch: pytest.MonkeyPatch) -> Path:
    """Every test's pendant keeps its programs (and autosave), cells, event log and recordings in fresh
    folders, never the checkout's."""
    folder = tmp_path_factory.mktemp("programs")
    monkeypatch.setenv(PROGRAMS_DIR_ENV, str(folder))
    monkeypatch.setenv(DATA_DIR_ENV, str(tmp_path_factory.mktemp("pendant-data")))  # event log, recordings
    monkeypatch.setenv(CELLS_DIR_ENV, str(tmp_path_factory.mktemp("cells")))
    return folder


@pytest.fixture
def clock() -> FakeClock:
    return FakeClock()


@pytest.fixture
def sim(clock: FakeClock) -> SimController:
    """A PULSE 75 simulator at power-on (home pose, IDLE) on the `clock` fixture."""
    return SimController("pulse75", clock)


@pytest.fixture
def sim90(clock: FakeClock) -> SimController:
    """A PULSE 90 simulator at power-on on the `clock` fixture."""
    return SimController("pulse90", clock)
