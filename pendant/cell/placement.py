"""Placing an obstacle with a transform gizmo: where the gizmo stands for the Cell tab's fields, and the
fields after the gizmo moved. Base frame; metres for poses, millimetres and degrees in fields (forms.py)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from pendant.cell.forms import ObstacleForm, Vec3
from pendant.kinematics.transforms import inverse, matrix_to_rpy, rpy_to_matrix


def gizmo_pose(form: ObstacleForm) -> np.ndarray:
    """T_base_gizmo: a box's centre and a plane's point in their own orientation; a capsule's midpoint,
    axes along the base's (a turn of the gizmo turns the capsule about its middle)."""
    T = np.eye(4)
    if form.kind == "CAPSULE":
        T[:3, 3] = (np.asarray(form.at_mm) + np.asarray(form.end_mm)) / 2000.0
        return T
    T[:3, :3] = rpy_to_matrix(*(math.radians(v) for v in form.rpy_deg))
    T[:3, 3] = np.asarray(form.at_mm) / 1000.0
    return T


def _vec(v: np.ndarray) -> Vec3:
    return (float(v[0]), float(v[1]), float(v[2]))


def moved_form(form: ObstacleForm, T_from: np.ndarray, T_to: np.ndarray) -> ObstacleForm:
    """The fields once the gizmo went from T_from (where `form` put it) to T_to; sizes and radius kept."""
    if form.kind == "CAPSULE":
        moved = T_to @ inverse(T_from)
        ends = [moved[:3, :3] @ (np.asarray(p) / 1000.0) + moved[:3, 3] for p in (form.at_mm, form.end_mm)]
        return replace(form, at_mm=_vec(ends[0] * 1000.0), end_mm=_vec(ends[1] * 1000.0))
    rpy = np.degrees(matrix_to_rpy(T_to[:3, :3]))
    return replace(form, at_mm=_vec(T_to[:3, 3] * 1000.0), rpy_deg=_vec(rpy))
