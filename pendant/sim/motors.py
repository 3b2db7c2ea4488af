"""Servo telemetry: what GET /status/motors reports, from the joint trajectory and a simple servo model.

Currents come from the joint torques (gravity, inertia and friction through `ArmModel.inverse_dynamics`)
divided by gear ratio, torque constant and gearbox efficiency. Temperatures follow a first-order thermal model
driven by the copper losses; it is integrated lazily over the clock time elapsed since the last query, so the
readings are a deterministic function of the motion history.
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Callable

import numpy as np

from pendant.controller.types import MotorStatus

# Harmonic drives: 101:1 in the base, shoulder and elbow, 81:1 in the wrist.
GEAR_RATIO = np.array([101.0, 101.0, 101.0, 81.0, 81.0, 81.0])
TORQUE_CONSTANT_NM_PER_A = np.array([0.11, 0.11, 0.11, 0.06, 0.06, 0.06])
GEAR_EFFICIENCY = 0.85
WINDING_RESISTANCE_OHM = np.array([0.35, 0.35, 0.35, 0.8, 0.8, 0.8])
NO_LOAD_CURRENT_A = 0.01
# Joint friction: Coulomb (N m) and viscous (N m s / rad).
FRICTION_COULOMB_NM = np.array([1.5, 1.5, 1.2, 0.4, 0.4, 0.4])
FRICTION_VISCOUS_NMS = np.array([2.0, 2.0, 1.5, 0.3, 0.3, 0.3])
SUPPLY_VOLTAGE_V = 48.0
SUPPLY_RESISTANCE_OHM = 0.02
# Servo loop: the setpoint runs ahead of the feedback by this lag, and the joint gives a little under load.
TRACKING_LAG_S = 0.0003
COMPLIANCE_DEG_PER_NM = 0.0004
# Thermal model: ambient, stator (winding) and servo (MCU board) time constants and thermal resistances.
AMBIENT_C = 25.0
STATOR_TAU_S = 180.0
STATOR_K_PER_W = 3.0
SERVO_TAU_S = 600.0
SERVO_K_PER_W = 1.0
SERVO_IDLE_RISE_C = 3.0  # the board warms a little just by being powered
SERVO_SWITCHING_OHM = 0.05  # conduction losses in the drive, per A^2
# Integration step while the arm moves (at rest the exact exponential covers any gap in one step).
THERMAL_STEP_S = 0.1
THERMAL_MAX_STEPS = 2000  # per stretch integrated (very slow motions get longer steps)

RPM_PER_RAD_S = 60.0 / (2.0 * math.pi)


def servo_ids(model_name: str) -> list[str]:
    """Six stable alphanumeric servo ids for a model (the real ids are burnt into each servo)."""
    ids = []
    for joint in range(1, 7):
        digest = hashlib.sha256(f"pulse-servo:{model_name}:{joint}".encode()).hexdigest()
        ids.append(_base36(int(digest[:12], 16), 3))
    return ids


def _base36(value: int, width: int) -> str:
    digits = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ"
    out = ""
    for _ in range(width):
        value, r = divmod(value, 36)
        out = digits[r] + out
    return out


class ServoModel:
    """Joint torques -> motor currents, and the thermal state of the six servos."""

    def __init__(
        self, inverse_dynamics: Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray], t0: float
    ):
        self._inverse_dynamics = inverse_dynamics
        self.reset(t0)

    def reset(self, t0: float) -> None:
        self.stator_c = np.full(6, AMBIENT_C)
        self.servo_c = np.full(6, AMBIENT_C)
        self.t = t0

    def joint_torques(self, q: np.ndarray, dq: np.ndarray, ddq: np.ndarray) -> np.ndarray:
        friction = FRICTION_COULOMB_NM * np.tanh(dq / 0.01) + FRICTION_VISCOUS_NMS * dq
        return np.asarray(self._inverse_dynamics(q, dq, ddq)) + friction

    def motor_current(self, torques: np.ndarray) -> np.ndarray:
        """Signed motor (phase amplitude) current in A for joint torques in N m."""
        return torques / (GEAR_RATIO * TORQUE_CONSTANT_NM_PER_A * GEAR_EFFICIENCY)

    def _equilibrium(self, current: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        i_sq = (np.abs(current) + NO_LOAD_CURRENT_A) ** 2
        stator = AMBIENT_C + STATOR_K_PER_W * WINDING_RESISTANCE_OHM * i_sq
        servo = AMBIENT_C + SERVO_IDLE_RISE_C + SERVO_K_PER_W * SERVO_SWITCHING_OHM * i_sq
        return stator, servo

    def heat(self, current: np.ndarray, dt: float) -> None:
        """Advance the temperatures by dt seconds at a constant current (exact for a first-order model)."""
        if dt <= 0.0:
            return
        stator_eq, servo_eq = self._equilibrium(current)
        self.stator_c = stator_eq + (self.stator_c - stator_eq) * math.exp(-dt / STATOR_TAU_S)
        self.servo_c = servo_eq + (self.servo_c - servo_eq) * math.exp(-dt / SERVO_TAU_S)
        self.t += dt

    def heat_along(
        self, state_at: Callable[[float], tuple[np.ndarray, np.ndarray, np.ndarray]], t_end: float
    ) -> None:
        """Advance to t_end through a motion, sampling its current at the middle of each step."""
        span = t_end - self.t
        if span <= 0.0:
            return
        n = min(THERMAL_MAX_STEPS, max(1, math.ceil(span / THERMAL_STEP_S)))
        dt = span / n
        for _ in range(n):
            q, dq, ddq = state_at(self.t + 0.5 * dt)
            self.heat(self.motor_current(self.joint_torques(q, dq, ddq)), dt)
        self.t = t_end

    def status(
        self, q: np.ndarray, dq: np.ndarray, ddq: np.ndarray, powered: bool = True
    ) -> list[MotorStatus]:
        """The six MotorStatus records at this instant (temperatures as last integrated)."""
        torques = self.joint_torques(q, dq, ddq) if powered else np.zeros(6)
        current = self.motor_current(torques)
        phase = np.abs(current) + NO_LOAD_CURRENT_A
        rms = phase / math.sqrt(2.0)
        voltage = SUPPLY_VOLTAGE_V - SUPPLY_RESISTANCE_OHM * float(np.sum(rms))
        angle = np.degrees(q)
        error = np.degrees(dq) * TRACKING_LAG_S + COMPLIANCE_DEG_PER_NM * torques
        rotor = dq * GEAR_RATIO * RPM_PER_RAD_S
        rotor_setpoint = (dq + ddq * TRACKING_LAG_S) * GEAR_RATIO * RPM_PER_RAD_S
        records = []
        for i in range(6):
            records.append(
                MotorStatus(
                    angle=float(angle[i]),
                    rotorVelocity=float(rotor[i]),
                    rmsCurrent=float(rms[i]),
                    voltage=float(voltage),
                    phaseCurrent=float(phase[i]),
                    statorTemperature=float(self.stator_c[i]),
                    servoTemperature=float(self.servo_c[i]),
                    velocityError=float(rotor_setpoint[i] - rotor[i]),
                    velocitySetpoint=float(rotor_setpoint[i]),
                    velocityOutput=float(current[i]),
                    velocityFeedback=float(rotor[i]),
                    positionError=float(error[i]),
                    positionSetpoint=float(angle[i] + error[i]),
                    positionOutput=float(rotor_setpoint[i]),
                    positionFeedback=float(angle[i]),
                )
            )
        return records
