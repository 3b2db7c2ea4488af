"""The embedded PULSE controller simulator: trajectories on a clock, states, IO, gripper, motors, faults."""

from pendant.sim.clock import Clock, FakeClock, MonotonicClock, ScaledClock
from pendant.sim.controller import (
    DEFAULT_BASE,
    DEFAULT_TOOL,
    HOME_POSE_DEG,
    PACK_POSE_DEG,
    Fault,
    SimController,
)

__all__ = [
    "DEFAULT_BASE",
    "DEFAULT_TOOL",
    "HOME_POSE_DEG",
    "PACK_POSE_DEG",
    "Clock",
    "FakeClock",
    "Fault",
    "MonotonicClock",
    "ScaledClock",
    "SimController",
]
