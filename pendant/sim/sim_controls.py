"""The simulator's own controls (mixed into SimController), beyond what a real controller offers: what a
sensor wired to an input, a hand on the relaxed arm, or a fault would do to it (the /sim/ paths, tests)."""

from __future__ import annotations

import threading

import numpy as np

from pendant.controller.errors import MSG_UNREACHABLE_POSE, Collision, PreconditionFailed, Unreachable
from pendant.controller.types import Pose, SignalLevel
from pendant.kinematics.contact import FLOOR
from pendant.sim.host import SimHost
from pendant.sim.states import FAULT_FAILURES, Fault, Mode

MSG_HAND_INTO_CELL = "Collision detected: at that pose the arm or its tool would be inside {what}"
MSG_HAND_NEEDS_RELAX = "The arm can be moved by hand only in ZERO_GRAVITY: relax it first (PUT /relax)"
OVERHEAT_STATOR_C = 110.0  # PUT /sim/fault/overheat

_DEAD = (Mode.EMERGENCY, Mode.NO_RESPONSE, Mode.ERROR)  # a protective stop cannot change these


class SimOnlyControls:
    """Drive an input, move the relaxed arm by hand, inject a fault, overheat the motors."""

    _lock: threading.RLock

    def set_input(self: SimHost, port: int, level: SignalLevel) -> None:
        """Drive a digital input (what a sensor wired to the control box would do). An input reaching the
        level bound with PUT /stop/bind/{port}/... makes a protective stop."""
        with self._lock:
            was = self._io.input(port)
            self._io.set_input(port, level)
            bound = self._stop_bindings.get(port)
            if bound is not None and level == bound and was != level and self._mode not in _DEAD:
                self._protective_stop(f"Protective stop: digital input {port} went {bound.value}")

    def move_by_hand(self: SimHost, pose: Pose) -> None:
        """Put the relaxed arm in `pose` as a hand would. Only in ZERO_GRAVITY; limits and collisions hold."""
        with self._lock:
            self.check_alive()
            if self._mode is not Mode.ZERO_GRAVITY:
                raise PreconditionFailed(MSG_HAND_NEEDS_RELAX)
            q = np.radians(pose.angles)
            if not self.arm.within_limits(q):
                raise Unreachable(MSG_UNREACHABLE_POSE)
            if self.arm.in_collision(q):
                raise Collision()
            # A test hook that silently puts the arm inside the cell is a trap; out of a contact it may go.
            worse = self._environment.move_check(self._motions.q_now(self._now()), q)
            if worse is not None:
                what = "the floor (with its tool)" if worse.obstacle is FLOOR else repr(worse.obstacle)
                raise Collision(MSG_HAND_INTO_CELL.format(what=what))
            self._motions.place(q, self._now())

    def inject_fault(self: SimHost, fault: Fault) -> None:
        """Make the controller fail: the arm stops dead where it is and the queue empties (see Fault)."""
        with self._lock:
            fault = Fault(fault)
            self._motions.stop(self._now())
            self._mode = Mode(fault.value)
            self._failures.record(*FAULT_FAILURES[fault])

    def overheat(self: SimHost, stator_c: float = OVERHEAT_STATOR_C) -> None:
        """The stator windings are suddenly this hot (a fault to test alarms on); they cool from there."""
        with self._lock:
            self._motions.integrate_thermal(self._now())
            self._motions.servos.stator_c[:] = stator_c
