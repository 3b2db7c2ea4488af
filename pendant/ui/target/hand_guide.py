"""Free drive with the simulator: the operator moves the relaxed arm by hand in the page. Dragging the TCP
gizmo or a joint slider puts the arm there (PUT /sim/pose), as a hand pulling it would, when the target
keeps the joint limits and is clear of itself, the floor and the cell; otherwise the arm stays."""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import Future

import numpy as np
import viser

from pendant.controller import Pose
from pendant.controller.system_types import SystemState
from pendant.sim import SimController
from pendant.ui.kit.commands import CommandRunner


class HandGuide:
    def __init__(
        self, sim: SimController, runner: CommandRunner, system_state: Callable[[], SystemState | None]
    ) -> None:
        self._sim = sim
        self._runner = runner
        self._system_state = system_state

    @property
    def active(self) -> bool:
        """The arm is in free drive (zero gravity), as the controller last reported."""
        return self._system_state() is SystemState.ZERO_GRAVITY

    def move(self, q: np.ndarray, client: viser.ClientHandle | None) -> Future[object]:
        pose = Pose(angles=[float(v) for v in np.degrees(q)])
        return self._runner.submit("Move by hand", lambda _: self._sim.move_by_hand(pose), client)
