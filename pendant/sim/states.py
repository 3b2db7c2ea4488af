"""The simulator's state machine: its modes, the faults it can be told to have, and what each mode allows."""

from __future__ import annotations

from enum import StrEnum

from pendant.controller.errors import Emergency, NotResponding


class Fault(StrEnum):
    """Faults the simulator can be told to have (served under /sim/fault)."""

    ERROR = "ERROR"  # recoverable: the arm freezes in place; PUT /recover clears it
    EMERGENCY = "EMERGENCY"  # fatal: every call answers 503 until reset()
    NO_RESPONSE = "NO_RESPONSE"  # the controller hangs: every call answers 500 until reset()
    MOTION_FAILED = "MOTION_FAILED"  # the running motion fails mid-way: the arm stops, the queue empties


class Mode(StrEnum):
    """What the controller is doing, beyond whether the queue runs."""

    ACTIVE = "ACTIVE"  # motors engaged: IDLE or RUNNING, depending on the queue
    ZERO_GRAVITY = "ZERO_GRAVITY"
    MOTION_FAILED = "MOTION_FAILED"
    ERROR = "ERROR"
    EMERGENCY = "EMERGENCY"
    NO_RESPONSE = "NO_RESPONSE"


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
