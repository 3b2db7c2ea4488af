"""Why a jog cannot go further: "joint limit", or a collision in the words every tab uses
(kinematics/collision_words.py): "Collision detected: the arm would touch 'Box 1'".

Asked when a jog finds no progress possible from where the arm is (its target stops short of the obstacle
by a few samples): the samples just beyond the arm say what is there.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from pendant.jog.arm import JogArm
from pendant.jog.targets import (
    JOINT_SAMPLE_RAD,
    LINEAR_SAMPLE_M,
    MAX_JOINT_JUMP_RAD,
    ROTATION_SAMPLE_RAD,
    SAFETY_BACKOFF_SAMPLES,
    JogFrame,
    JogRequest,
    displaced,
)
from pendant.kinematics.collision_words import pose_words
from pendant.kinematics.transforms import inverse

# The names of the obstacles the arm or its tool touches at q ([]: none, or no cell known).
Touching = Callable[[np.ndarray], list[str]]

MSG_JOINT_LIMIT = "joint limit"
MSG_REACH = "the edge of the arm's reach"
MSG_SINGULAR = "a singular pose (the joints would jump)"
MSG_NO_FURTHER = "cannot move further that way"
PROBE_SAMPLES = SAFETY_BACKOFF_SAMPLES + 2  # the target backs off this many samples from the obstacle


def touch_cause(arm: JogArm, q: np.ndarray, touching: Touching) -> str:
    """What the arm would hit at `q`, named as the Target tab names it: its own links, an obstacle, the
    floor (`arm` may be the cell-aware arm: its colliding pairs are the arm model's own)."""
    return pose_words(arm.colliding_pairs(q), touching(q))


def why_blocked(
    arm: JogArm,
    q: np.ndarray,
    request: JogRequest,
    touching: Touching,
    T_base_zero: np.ndarray | None = None,
    T_flange_tool: np.ndarray | None = None,
) -> str:
    """What stops `request` just beyond `q` (Cartesian jogs need the zero point and the tool)."""
    if request.frame is JogFrame.JOINT:
        for k in range(1, PROBE_SAMPLES + 1):
            sample = q.copy()
            sample[request.axis] += request.direction * JOINT_SAMPLE_RAD * k
            if not arm.within_limits(sample):
                return MSG_JOINT_LIMIT
            if arm.in_collision(sample):
                return touch_cause(arm, sample, touching)
        return MSG_NO_FURTHER
    assert T_base_zero is not None and T_flange_tool is not None
    T_zero_tool = inverse(T_base_zero) @ arm.fk(q) @ T_flange_tool
    sample_size = ROTATION_SAMPLE_RAD if request.is_rotation else LINEAR_SAMPLE_M
    q_prev = q
    for k in range(1, PROBE_SAMPLES + 1):
        T = displaced(T_zero_tool, request, request.direction * sample_size * k)
        q_k = arm.ik(T_base_zero @ T @ inverse(T_flange_tool), q_prev)
        if q_k is None:
            return MSG_REACH
        if np.max(np.abs(q_k - q_prev)) > MAX_JOINT_JUMP_RAD:
            return MSG_SINGULAR
        if arm.in_collision(q_k):
            return touch_cause(arm, q_k, touching)
        q_prev = q_k
    return MSG_NO_FURTHER
