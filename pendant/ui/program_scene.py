"""The program in 3D: a marker and a name at every waypoint, and the planned path as a polyline."""

from __future__ import annotations

import itertools

import numpy as np
import viser

from pendant.controller.types import MotionType
from pendant.kinematics import ArmModel
from pendant.program import MoveStep, Program
from pendant.ui.gui_target import GuiTarget

MARKER_RADIUS_M = 0.012
MARKER_RGB = (40, 110, 230)
SELECTED_RGB = (250, 160, 20)
CURRENT_RGB = (30, 180, 80)
PATH_JOINT_RGB = (40, 110, 230)
PATH_LINEAR_RGB = (200, 60, 160)
PATH_THICKNESS_PX = 2.5
# A JOINT leg is a curve for the TCP: draw it through this many joint-space samples.
JOINT_LEG_SAMPLES = 16
ROOT = "/program"


class ProgramScene:
    """Scene nodes under /program on one target (a browser, or every browser for a ViserServer)."""

    def __init__(self, target: GuiTarget, arm: ArmModel | None) -> None:
        self._target = target
        self._arm = arm
        self._nodes: list[viser.SceneNodeHandle] = []
        self._markers: list[viser.IcosphereHandle] = []
        self._shown: tuple[Program, int | None, int | None] | None = None

    def show(self, program: Program, selected: int | None = None, current: int | None = None) -> None:
        """Draw `program`'s waypoints (the `selected` and `current` steps highlighted) and its path."""
        if self._shown == (program, selected, current):
            return
        if self._shown is None or self._shown[0] != program:
            self._rebuild(program)
        self._shown = (program, selected, current)
        for marker, index in zip(self._markers, _move_indices(program), strict=True):
            marker.color = (
                CURRENT_RGB if index == current else SELECTED_RGB if index == selected else MARKER_RGB
            )

    def close(self) -> None:
        for node in self._nodes:
            node.remove()
        self._nodes.clear()
        self._markers.clear()
        self._shown = None

    def _rebuild(self, program: Program) -> None:
        self.close()
        scene = self._target.scene
        previous_q: np.ndarray | None = None
        previous_point: np.ndarray | None = None
        segments: dict[MotionType, list[np.ndarray]] = {MotionType.JOINT: [], MotionType.LINEAR: []}
        for index in _move_indices(program):
            step = program.steps[index]
            assert isinstance(step, MoveStep)
            q = np.radians(np.asarray(step.waypoint.pose.angles, dtype=float))
            point = self.point_of(step)
            marker = scene.add_icosphere(
                f"{ROOT}/waypoint_{index}",
                radius=MARKER_RADIUS_M,
                color=MARKER_RGB,
                position=point,
                cast_shadow=False,
                receive_shadow=False,
            )
            label = scene.add_label(
                f"{ROOT}/waypoint_{index}/name",
                f"{index + 1}. {step.waypoint.name}",
                position=(0.0, 0.0, 2.0 * MARKER_RADIUS_M),
                anchor="bottom-center",
            )
            del label  # removed with its marker
            self._markers.append(marker)
            self._nodes.append(marker)
            if previous_point is not None:
                segments[step.motion].extend(self._leg(previous_q, q, previous_point, point, step.motion))
            previous_q, previous_point = q, point
        for motion, pieces in segments.items():
            if pieces:
                color = PATH_JOINT_RGB if motion is MotionType.JOINT else PATH_LINEAR_RGB
                self._nodes.append(
                    scene.add_line_segments(
                        f"{ROOT}/path_{motion.value.lower()}",
                        np.asarray(pieces),
                        color,
                        thickness=PATH_THICKNESS_PX,
                        thickness_units="screen",
                    )
                )

    def point_of(self, step: MoveStep) -> np.ndarray:
        """Where the marker goes: the flange by FK (as the scene's TCP frame), else the recorded TCP."""
        if self._arm is not None:
            return self._arm.fk(np.radians(step.waypoint.pose.angles))[:3, 3]
        p = step.waypoint.position.point
        return np.array([p.x, p.y, p.z])

    def _leg(
        self, q0: np.ndarray | None, q1: np.ndarray, p0: np.ndarray, p1: np.ndarray, motion: MotionType
    ) -> list[np.ndarray]:
        if motion is MotionType.LINEAR or self._arm is None or q0 is None:
            return [np.stack([p0, p1])]
        samples = [self._arm.fk(q0 + t * (q1 - q0))[:3, 3] for t in np.linspace(0.0, 1.0, JOINT_LEG_SAMPLES)]
        return [np.stack([a, b]) for a, b in itertools.pairwise(samples)]


def _move_indices(program: Program) -> list[int]:
    return [i for i, step in enumerate(program.steps) if isinstance(step, MoveStep)]
