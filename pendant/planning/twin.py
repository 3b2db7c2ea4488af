"""The digital twin: the simulator seeded from the arm in front of you, on a clock that only moves when told.

`read_seed` reads what the twin needs from any Controller with GETs only (a real arm behind the proxy is
never sent anything else); `Twin` is a SimController put in that state, whose clock the pre-flight advances
instead of sleeping, so a minute of program takes milliseconds of planning.
"""

from __future__ import annotations

import dataclasses
import statistics
import time
from dataclasses import dataclass

import numpy as np

from pendant.controller import Controller
from pendant.controller.cell_types import Obstacle, ToolShape
from pendant.controller.errors import ControllerError, Unreachable, Unsupported
from pendant.controller.types import (
    INPUT_PORTS,
    OUTPUT_PORTS,
    MotionParams,
    Pose,
    Position,
    SignalLevel,
    Tool,
)
from pendant.planning.refusal import DiagnosingPlanner, Refusal
from pendant.sim import FakeClock, SimController
from pendant.sim.timeline import Motion

POLL_READ_TRIES = 5


@dataclass(frozen=True)
class TwinSeed:
    """The arm's state a pre-flight starts from: where it is, its tool, zero point, cell and IO."""

    pose: Pose
    tool: Tool
    tool_shape: ToolShape
    base: Position
    obstacles: tuple[Obstacle, ...]
    outputs: dict[int, SignalLevel]
    inputs: dict[int, SignalLevel]
    notes: tuple[str, ...] = ()  # what could not be read (an older firmware without a cell), in words
    # How long the runner's two reads of a poll (motion status, where the arm is) take on this link: a run
    # polls every 50 ms plus this, and so notices the end of each motion that much later.
    poll_reads_s: float = 0.0

    def with_cell(self, obstacles: list[Obstacle], tool_shape: ToolShape | None) -> TwinSeed:
        """The same arm in another cell (a cell file); the tool shape kept when the file has none."""
        shape = self.tool_shape if tool_shape is None else tool_shape
        return dataclasses.replace(self, obstacles=tuple(obstacles), tool_shape=shape)


def read_seed(controller: Controller) -> TwinSeed:
    """The controller's state, read with GET requests only. Raises ControllerError when the arm cannot be
    read at all; a firmware without the cell operations (404) gives an empty cell and a note saying so."""
    notes: list[str] = []
    try:
        obstacles: tuple[Obstacle, ...] = tuple(controller.get_obstacles())
        shape = controller.get_tool_shape()
    except Unsupported:
        obstacles, shape = (), ToolShape(shape=[])
        notes.append("this controller has no cell operations (older firmware): checked without obstacles")
    return TwinSeed(
        poll_reads_s=_poll_reads_s(controller),
        pose=controller.get_pose(),
        tool=controller.get_tool(),
        tool_shape=shape,
        base=controller.get_base(),
        obstacles=obstacles,
        outputs={port: controller.get_output(port) for port in OUTPUT_PORTS},
        inputs={port: controller.get_input(port) for port in INPUT_PORTS},
        notes=tuple(notes),
    )


def _poll_reads_s(controller: Controller) -> float:
    """The median time of a runner's poll reads (GET /status/motion and GET /pose) over a few tries."""
    times = []
    for _ in range(POLL_READ_TRIES):
        started = time.perf_counter()
        controller.get_motion_status()
        controller.get_pose()
        times.append(time.perf_counter() - started)
    return statistics.median(times)


class TwinSetupError(Exception):
    """The seed cannot be put on the simulator (e.g. an obstacle touching the arm where it stands)."""


class Twin(SimController):
    """A SimController on a FakeClock in the seed's state; `advance(dt)` moves its time."""

    def __init__(self, seed: TwinSeed, model: str = "pulse75") -> None:
        self.fake_clock = FakeClock()
        super().__init__(model=model, clock=self.fake_clock)
        self._diagnosing = DiagnosingPlanner(self.arm)
        self._planner = self._diagnosing  # the simulator's planner, remembering why it refused
        self.seed = seed
        try:
            self._put(seed)
        except ControllerError as error:
            raise TwinSetupError(f"the twin cannot take the arm's state: {error.message}") from error

    def _put(self, seed: TwinSeed) -> None:
        # The arm first (obstacles are refused where they would touch it), then the tool, then the cell.
        self.relax()
        self.move_by_hand(seed.pose)
        self.freeze()
        self.set_base(seed.base)
        self.set_tool(seed.tool)
        self.set_tool_shape(seed.tool_shape)
        for obstacle in seed.obstacles:
            self.add_obstacle(obstacle)
        for port, level in seed.outputs.items():
            self.set_output(port, level)
        for port, level in seed.inputs.items():
            self.set_input(port, level)

    @property
    def last_refusal(self) -> Refusal | None:
        """Why the last planned move was refused (None when it was not, or the planner never saw it)."""
        return self._diagnosing.last

    # A pose past a joint limit is refused before the planner sees it: name the joint here.
    def run_poses(self, poses: list[Pose], params: MotionParams) -> None:
        self._diagnosing.last = None
        try:
            super().run_poses(poses, params)
        except Unreachable:
            self._diagnosing.note_limits([np.radians(p.angles) for p in poses])
            raise

    def set_pose(self, pose: Pose, params: MotionParams) -> None:
        self.run_poses([pose], params)

    def advance(self, dt: float) -> None:
        self.fake_clock.advance(max(0.0, dt))

    def now(self) -> float:
        return self.fake_clock.now()

    def running_motion(self) -> Motion | None:
        """The queued command running now (a move or a gripper action), or None at rest."""
        t = self.now()
        for motion in self.queued_motions():
            if motion.t0 <= t < motion.t_end:
                return motion
        return None
