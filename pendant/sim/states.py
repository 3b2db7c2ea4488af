"""The simulator's state machine: its modes, the faults it can be told to have, and what each mode allows."""

from __future__ import annotations

from enum import StrEnum

from pendant.controller.errors import MSG_PROTECTIVE_STOP, Emergency, NotResponding, PreconditionFailed
from pendant.controller.system_types import FailureLevel, FailureType, SystemState
from pendant.controller.types import MotionStatus

MSG_TWISTED = (
    "The arm is twisted: untwist it (PUT /relax, turn the joints back by hand), then PUT /untwisting/finish"
)


class Fault(StrEnum):
    """Faults the simulator can be told to have (served under /sim/fault)."""

    ERROR = "ERROR"  # recoverable: the arm freezes in place; PUT /recover clears it
    EMERGENCY = "EMERGENCY"  # fatal: every call answers 503 until reset()
    NO_RESPONSE = "NO_RESPONSE"  # the controller hangs: every call answers 500 until reset()
    MOTION_FAILED = "MOTION_FAILED"  # the running motion fails mid-way: the arm stops, the queue empties
    TWISTED = "TWISTED"  # a cable is wound past its limit: motion refused until PUT /untwisting/finish


class Mode(StrEnum):
    """What the controller is doing, beyond whether the queue runs."""

    ACTIVE = "ACTIVE"  # motors engaged: IDLE or RUNNING, depending on the queue
    ZERO_GRAVITY = "ZERO_GRAVITY"
    MOTION_FAILED = "MOTION_FAILED"
    ERROR = "ERROR"
    EMERGENCY = "EMERGENCY"
    NO_RESPONSE = "NO_RESPONSE"
    STOPPED = "STOPPED"  # protective stop (POST /stop, or a bound input): holds, refuses motion
    TWISTED = "TWISTED"


# What each fault is in GET /status/failure: type, level, message.
FAULT_FAILURES: dict[Fault, tuple[FailureType, FailureLevel, str]] = {
    Fault.ERROR: (
        FailureType.SOFTWARE_ERROR,
        FailureLevel.ERROR,
        "Controller error: the arm stopped and froze",
    ),
    Fault.EMERGENCY: (FailureType.EMCY, FailureLevel.FATAL, "Emergency: the arm is unavailable"),
    Fault.NO_RESPONSE: (FailureType.HARDWARE_ERROR, FailureLevel.FATAL, "The arm does not respond"),
    Fault.MOTION_FAILED: (FailureType.SOFTWARE_ERROR, FailureLevel.ERROR, "Motion failed: the arm stopped"),
    Fault.TWISTED: (FailureType.HARDWARE_ERROR, FailureLevel.ERROR, MSG_TWISTED),
}


def check_alive(mode: Mode) -> None:
    """Raise what every call answers in EMERGENCY (503) or when not responding (500)."""
    if mode is Mode.EMERGENCY:
        raise Emergency()
    if mode is Mode.NO_RESPONSE:
        raise NotResponding()


def check_can_move(mode: Mode) -> None:
    check_alive(mode)
    if mode is Mode.ERROR:
        raise NotResponding()  # the reference's 500 text; GET /status/motion says ERROR
    if mode is Mode.STOPPED:
        raise PreconditionFailed(MSG_PROTECTIVE_STOP)
    if mode is Mode.TWISTED:
        raise PreconditionFailed(MSG_TWISTED)


def motion_status(mode: Mode, running: bool) -> MotionStatus:
    """GET /status/motion: the reference's words (a stop or a twist is 'stopped, recover brings it back')."""
    if mode is Mode.ACTIVE:
        return MotionStatus.RUNNING if running else MotionStatus.IDLE
    if mode in (Mode.STOPPED, Mode.TWISTED):
        return MotionStatus.ERROR
    return MotionStatus(mode.value)


def system_state(mode: Mode, running: bool, jogging: bool) -> SystemState:
    """GET /status (SDK 1.8.4). ERROR is BROKEN (failed, recoverable); a protective stop or a failed motion
    leave the arm ACTIVE (holding, not moving), with the reason in GET /status/failure."""
    if mode is Mode.ACTIVE:
        if jogging:
            return SystemState.JOGGING
        return SystemState.MOTION if running else SystemState.ACTIVE
    return {
        Mode.ZERO_GRAVITY: SystemState.ZERO_GRAVITY,
        Mode.ERROR: SystemState.BROKEN,
        Mode.EMERGENCY: SystemState.EMERGENCY,
        Mode.TWISTED: SystemState.TWISTED,
    }.get(mode, SystemState.ACTIVE)
