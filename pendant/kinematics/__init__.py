"""Kinematics of the PULSE arms: numpy in, numpy out, radians and metres (see `ArmModel`)."""

from __future__ import annotations

from pendant.kinematics.arm_model import IK_POS_TOL_M, IK_ROT_TOL_RAD, ArmModel

__all__ = ["IK_POS_TOL_M", "IK_ROT_TOL_RAD", "ArmModel"]
