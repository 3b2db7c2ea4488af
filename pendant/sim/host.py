"""What the simulator's operation mixins (motion_commands.py, pulse18.py, sim_controls.py) need of the
controller they are mixed into: its shared state and the few methods they call on each other.

The mixins type `self` as this Protocol rather than as SimController, so neither imports controller.py
(which imports them): no import circle, not even for the type checker. SimController satisfies it, which
mypy checks wherever a mixin's method is called on one.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Protocol

import numpy as np

from pendant.controller.types import MotionParams, Pose, Position, SignalLevel, Tool
from pendant.kinematics import ArmModel
from pendant.sim.cell import Frames
from pendant.sim.clock import Clock
from pendant.sim.environment import Environment
from pendant.sim.failures import FailureLog
from pendant.sim.io import IOBoard
from pendant.sim.moves import Start, Step
from pendant.sim.planner import Planner
from pendant.sim.queue import MotionQueue
from pendant.sim.states import Mode


class SimHost(Protocol):
    """The simulator's state under its lock, and the operations the mixins share."""

    model: str
    arm: ArmModel
    _lock: threading.RLock
    _clock: Clock
    _epoch: float | None
    _mode: Mode
    _freezes: int  # freezes and resets so far: a plan made across one is dropped
    _motions: MotionQueue
    _planner: Planner
    _frames: Frames
    _environment: Environment
    _failures: FailureLog
    _gripper_enabled: bool
    _stop_bindings: dict[int, SignalLevel]
    _pack_q: np.ndarray
    _io: IOBoard

    def _now(self) -> float: ...
    def check_alive(self) -> None: ...
    def _position_now(self) -> Position: ...
    def _configurations(self) -> list[np.ndarray]: ...
    def set_tool(self, tool: Tool) -> Tool: ...
    def relax(self) -> None: ...

    # motion_commands.py
    def _start(self) -> Start: ...
    def _starts_at(self, start: Start) -> bool: ...
    def _plan_and_enqueue(
        self, make_plan: Callable[[Start], list[Step] | None], jog: bool = False
    ) -> Position: ...
    def _plan_and_enqueue_now(
        self, make_plan: Callable[[Start], list[Step] | None], jog: bool
    ) -> Position: ...
    def _check_move(self, params: MotionParams, waypoints: list[Pose] | list[Position]) -> None: ...
    def _move_to_poses(self, poses: list[Pose], params: MotionParams) -> None: ...
    def _move_to_positions(self, positions: list[Position], params: MotionParams) -> Position: ...
    def _gripper(self, target: float, timeout_ms: float) -> None: ...
    def run_positions(self, positions: list[Position], params: MotionParams) -> None: ...
    def run_poses(self, poses: list[Pose], params: MotionParams) -> None: ...

    # pulse18.py
    def _protective_stop(self, reason: str) -> None: ...
    def _plan_jog(
        self, start: Start, linear: np.ndarray, turn: np.ndarray, params: MotionParams
    ) -> list[Step]: ...
