"""Program fixtures: a runner on the simulator's fake clock, waypoints taught by moving the simulator, and
the Program tab on a real viser server (`setup`)."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from pathlib import Path

import pytest
import viser

from pendant.program import ProgramRunner, ProgramStore, ProgramWorkspace, Waypoint
from pendant.sim import FakeClock, SimController
from pendant.ui.kit.commands import CommandRunner
from pendant.ui.program.panel import ProgramPanel
from tests.support.ports import free_port
from tests.support.programs import POLL_S, POSE_A_DEG, POSE_B_DEG, POSE_C_DEG, teach


@pytest.fixture
def waypoints(sim: SimController, clock: FakeClock) -> dict[str, Waypoint]:
    """Waypoints A, B, C taught on the simulator, which is then back at its power-on state."""
    taught = {
        name: teach(sim, clock, pose, name)
        for name, pose in (("A", POSE_A_DEG), ("B", POSE_B_DEG), ("C", POSE_C_DEG))
    }
    sim.reset()
    return taught


@pytest.fixture
def runner(sim: SimController, clock: FakeClock) -> ProgramRunner:
    """A runner whose sleeps advance the fake clock: a whole program runs in milliseconds."""
    return ProgramRunner(sim, sleep=clock.advance, now=clock.now, poll_s=POLL_S)


@pytest.fixture
def make_workspace(tmp_path: Path, runner: ProgramRunner) -> Callable[[], ProgramWorkspace]:
    """A workspace on a programs folder in tmp_path; call again to simulate a restart of the pendant."""
    return lambda: ProgramWorkspace(ProgramStore(tmp_path / "programs"), runner)


@pytest.fixture
def server() -> Iterator[viser.ViserServer]:
    """A real viser server on a free loopback port, for a panel built without a PendantUI."""
    server = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)
    yield server
    server.stop()


@pytest.fixture
def setup(
    server: viser.ViserServer, sim: SimController, clock: FakeClock, tmp_path: Path
) -> Iterator[tuple[ProgramPanel, ProgramWorkspace]]:
    """The Program tab on `server`, its runner on the fake clock: (panel, workspace)."""
    runner = CommandRunner(sim)
    workspace = ProgramWorkspace(
        ProgramStore(tmp_path / "programs"), ProgramRunner(sim, sleep=clock.advance, now=clock.now)
    )
    panel = ProgramPanel(server, workspace, runner, arm=sim.arm)
    yield panel, workspace
    panel.close()
    runner.shutdown()
