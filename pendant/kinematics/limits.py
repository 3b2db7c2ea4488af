"""Joint limits, speeds and accelerations: the one place they are set.

Rozum does not publish them; these are defaults typical of a 6-axis cobot of this class. The model build
script writes them into the URDFs, and the simulator's motion planner reads them from here.
"""

from __future__ import annotations

import math

import numpy as np

N_JOINTS = 6

JOINT_LOWER_RAD = np.full(N_JOINTS, -2.0 * math.pi)
JOINT_UPPER_RAD = np.full(N_JOINTS, 2.0 * math.pi)

# Per-joint speed at `speed=100` (degrees/s): the big shoulder joints slower than the wrist.
JOINT_MAX_SPEED_RAD_S = np.radians([120.0, 120.0, 150.0, 180.0, 180.0, 180.0])
JOINT_MAX_ACCEL_RAD_S2 = np.radians([300.0, 300.0, 400.0, 500.0, 500.0, 500.0])
# Servo torque ratings used as URDF effort limits (N m).
JOINT_MAX_EFFORT_NM = np.array([150.0, 150.0, 150.0, 28.0, 28.0, 28.0])

# The gripper: each finger slides from closed (0) to open (GRIPPER_STROKE_M) in metres.
GRIPPER_STROKE_M = 0.04
