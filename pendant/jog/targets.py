"""Where a jog goes: the furthest safe target along the jogged axis, found on the pendant's own model.

A continuous jog is one motion command towards a target a few seconds ahead; the deadman freezes it on
release. The target stops short of joint limits, collisions and (for Cartesian jogs) the edge of the
workspace, so the controller accepts it: an obstacle the arm already touches may be backed out of, not
pushed into (the contact rule, kinematics/contact.py, through `arm.blocked_from`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import StrEnum

import numpy as np

from pendant.controller.errors import PreconditionFailed
from pendant.controller.types import SPEED_MAX
from pendant.jog.arm import JogArm
from pendant.kinematics.transforms import inverse, rotvec_to_matrix

JOG_SPEED_MIN = 1.0  # percent: the page's slider starts there (the API takes anything above 0)
# Manual reduced speed (ISO 10218-1): the TCP never exceeds 250 mm/s while jogging.
JOG_TCP_MAX_VELOCITY_M_S = 0.25
JOG_MAX_ROTATION_RAD_S = np.radians(45.0)
# A continuous jog plans this far ahead; when the arm gets there while still held, the next piece follows.
JOG_HORIZON_S = 3.0
JOINT_SAMPLE_RAD = np.radians(1.0)
LINEAR_SAMPLE_M = 0.005
ROTATION_SAMPLE_RAD = np.radians(1.0)
# Between two samples of a Cartesian jog no joint may turn more than this (else the IK branch jumped).
MAX_JOINT_JUMP_RAD = np.radians(10.0)
SAFETY_BACKOFF_SAMPLES = 2


class JogFrame(StrEnum):
    JOINT = "Joint"
    BASE = "Base"
    TOOL = "Tool"


CARTESIAN_AXES = ("X", "Y", "Z", "Roll", "Pitch", "Yaw")
# The largest step the page offers: 10 mm for X Y Z, 10 degrees for joints and rotations. A step is one
# motion without hold-to-run, so anything larger (a modified page sent 500: J1 turned 346 degrees) is refused.
MAX_STEP_M = 0.010
MAX_STEP_RAD = math.radians(10.0)


class JogRefused(PreconditionFailed):
    """A jog request outside what the page offers (forged step, speed, axis); the message says what."""


@dataclass(frozen=True)
class JogRequest:
    """Jog `axis` (joint 0-5, or X Y Z Roll Pitch Yaw as 0-5) in `direction` (+1 or -1).

    `step` is None for a continuous jog, or an increment in metres (X Y Z) or radians (joints, rotations).
    """

    frame: JogFrame
    axis: int
    direction: int
    speed_percent: float
    step: float | None = None

    def __post_init__(self) -> None:
        if not (isinstance(self.axis, int) and 0 <= self.axis < len(CARTESIAN_AXES)):
            raise JogRefused(f"Jog axis must be 0 to {len(CARTESIAN_AXES) - 1}")
        if self.direction not in (-1, 1):
            raise JogRefused("Jog direction must be +1 or -1")
        if not (math.isfinite(self.speed_percent) and JOG_SPEED_MIN <= self.speed_percent <= SPEED_MAX):
            raise JogRefused(f"Jog speed must be {JOG_SPEED_MIN:g} to {SPEED_MAX:g} %")
        if self.step is not None:
            largest = MAX_STEP_RAD if self.is_rotation else MAX_STEP_M
            if not (math.isfinite(self.step) and 0 < self.step <= largest + 1e-12):
                unit = f"{math.degrees(largest):g}°" if self.is_rotation else f"{largest * 1000:g} mm"
                raise JogRefused(f"Jog step must be above 0 and at most {unit}")

    @property
    def is_rotation(self) -> bool:
        return self.frame is JogFrame.JOINT or self.axis >= 3

    def label(self) -> str:
        name = f"J{self.axis + 1}" if self.frame is JogFrame.JOINT else CARTESIAN_AXES[self.axis]
        return f"{name}{'+' if self.direction > 0 else '-'}"


def joint_jog_target(arm: JogArm, q: np.ndarray, request: JogRequest, joint_speed: float) -> np.ndarray:
    """The furthest pose along one joint (within the step or the horizon) that is in limits and collision
    free all the way; `q` itself when no progress is possible."""
    travel = request.step if request.step is not None else joint_speed * JOG_HORIZON_S
    n = max(1, int(np.ceil(travel / JOINT_SAMPLE_RAD)))
    safe_k = n
    blocked = arm.blocked_from(q)
    for k in range(1, n + 1):
        sample = q.copy()
        sample[request.axis] += request.direction * travel * k / n
        if not arm.within_limits(sample) or blocked(sample):
            safe_k = max(0, k - 1 - SAFETY_BACKOFF_SAMPLES)
            break
    target = q.copy()
    target[request.axis] += request.direction * travel * safe_k / n
    return target


def cartesian_jog_path(
    arm: JogArm,
    q: np.ndarray,
    T_base_zero: np.ndarray,
    T_flange_tool: np.ndarray,
    request: JogRequest,
) -> np.ndarray:
    """T_zero_tool of the furthest target along a straight Cartesian jog that IK follows continuously,
    inside the limits and without collision; the current T_zero_tool when no progress is possible."""
    T_zero_tool = inverse(T_base_zero) @ arm.fk(q) @ T_flange_tool
    speed_fraction = request.speed_percent / 100.0
    if request.is_rotation:
        rate, sample = JOG_MAX_ROTATION_RAD_S * speed_fraction, ROTATION_SAMPLE_RAD
    else:
        rate, sample = JOG_TCP_MAX_VELOCITY_M_S * speed_fraction, LINEAR_SAMPLE_M
    travel = request.step if request.step is not None else rate * JOG_HORIZON_S
    n = max(1, int(np.ceil(travel / sample)))
    T_flange_tool_inv = inverse(T_flange_tool)
    best = T_zero_tool
    q_prev = q
    safe = []
    blocked = arm.blocked_from(q)
    for k in range(1, n + 1):
        T = displaced(T_zero_tool, request, request.direction * travel * k / n)
        q_k = arm.ik(T_base_zero @ T @ T_flange_tool_inv, q_prev)
        if q_k is None or np.max(np.abs(q_k - q_prev)) > MAX_JOINT_JUMP_RAD or blocked(q_k):
            break
        safe.append(T)
        q_prev = q_k
    else:
        return safe[-1] if safe else best
    keep = len(safe) - SAFETY_BACKOFF_SAMPLES
    return safe[keep - 1] if keep > 0 else best


def displaced(T_zero_tool: np.ndarray, request: JogRequest, amount: float) -> np.ndarray:
    """T_zero_tool moved by `amount` along or about the request's axis, in the base or the tool frame."""
    out = T_zero_tool.copy()
    unit = np.zeros(3)
    unit[request.axis % 3] = 1.0
    in_tool = request.frame is JogFrame.TOOL
    if request.axis < 3:
        direction = T_zero_tool[:3, :3] @ unit if in_tool else unit
        out[:3, 3] = T_zero_tool[:3, 3] + amount * direction
    else:
        R = rotvec_to_matrix(unit * amount)
        out[:3, :3] = T_zero_tool[:3, :3] @ R if in_tool else R @ T_zero_tool[:3, :3]
    return out
