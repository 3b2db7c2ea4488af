"""The program in 3D: a marker and a name at every move target, the path as the plan runs it (loops drawn
once, both branches of an If, a pallet's first pass), every pallet's grid of cells, and each recorded path
as a polyline through its waypoints (dots; a marker at its end).

The path comes from the same plan the runner executes (pendant.program.plan), so relative moves and pallet
cells are drawn where the arm will go. Called programs are not opened for drawing.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field

import numpy as np
import viser

from pendant.controller.types import MotionType
from pendant.kinematics import ArmModel
from pendant.program import PlanError, Program, compile_program
from pendant.program.plan import Branch, Loop, MoveGroup, Node, Pallet, Target
from pendant.ui.kit.gui_target import GuiTarget
from pendant.ui.program.label_layout import ScreenLabels

MARKER_RADIUS_M = 0.012
CELL_RADIUS_M = 0.006
MARKER_RGB = (40, 110, 230)
SELECTED_RGB = (250, 160, 20)
CURRENT_RGB = (30, 180, 80)
CELL_RGB = (120, 120, 120)
PATH_JOINT_RGB = (40, 110, 230)
PATH_LINEAR_RGB = (200, 60, 160)
PATH_THICKNESS_PX = 2.5
RECORDED_RGB = (230, 120, 20)
RECORDED_POINT_M = 0.006
# A JOINT leg is a curve for the TCP: draw it through this many joint-space samples.
JOINT_LEG_SAMPLES = 16
ROOT = "/program"
# Markers closer than this share one name label, a line per step (issue 33: a pick-and-place returns to the
# same waypoints, and their names were drawn on top of one another: "3.2P02").
LABEL_SHARE_M = 0.05
LABEL_ABOVE_M = 2.0 * MARKER_RADIUS_M  # a name's bottom, over its marker


def label_groups(markers: list[tuple[Target, np.ndarray]]) -> list[tuple[int, str]]:
    """One label per group of markers within LABEL_SHARE_M of the group's first: (that marker's index, the
    text). Moves to one waypoint share a line ("2, 4. P2"); other names stack, a line each, in step order."""
    groups: list[tuple[int, np.ndarray, dict[str, list[int]]]] = []
    for k, (target, point) in enumerate(markers):
        near = next((g for g in groups if float(np.linalg.norm(g[1] - point)) < LABEL_SHARE_M), None)
        if near is None:
            near = (k, point, {})
            groups.append(near)
        steps = near[2].setdefault(target.name, [])
        if target.line + 1 not in steps:
            steps.append(target.line + 1)
    return [
        (k, "\n".join(f"{', '.join(map(str, steps))}. {name}" for name, steps in names.items()))
        for k, _, names in groups
    ]


@dataclass
class _Drawing:
    """What the walk over the plan collects: marker places, path pieces per motion type, pallet cells."""

    markers: list[tuple[Target, np.ndarray]] = field(default_factory=list)
    pieces: dict[MotionType, list[np.ndarray]] = field(
        default_factory=lambda: {MotionType.JOINT: [], MotionType.LINEAR: []}
    )
    cells: list[np.ndarray] = field(default_factory=list)
    recorded: list[np.ndarray] = field(default_factory=list)  # recorded paths' segments
    recorded_points: list[np.ndarray] = field(default_factory=list)


class ProgramScene:
    """Scene nodes under /program on one target (a browser, or every browser for a ViserServer)."""

    def __init__(self, target: GuiTarget, arm: ArmModel | None) -> None:
        self._target = target
        self._arm = arm
        self._nodes: list[viser.SceneNodeHandle] = []
        self._markers: list[tuple[viser.IcosphereHandle, int]] = []  # (marker, step line)
        self._shown: tuple[Program, int | None, int | None] | None = None
        self.labels: list[str] = []  # the waypoint name labels drawn now
        self.on_screen = ScreenLabels(target)  # ... and as this browser's view shows them (none overlap)

    @property
    def nodes(self) -> tuple[viser.SceneNodeHandle, ...]:
        """The scene nodes it draws now."""
        return tuple(self._nodes)

    @property
    def markers(self) -> tuple[tuple[viser.IcosphereHandle, int], ...]:
        """The waypoint markers drawn now, each with the step line it belongs to."""
        return tuple(self._markers)

    def show(self, program: Program, selected: int | None = None, current: int | None = None) -> None:
        """Draw `program` (the moves of the `selected` and `current` lines highlighted) and its path."""
        if self._shown == (program, selected, current):
            return
        if self._shown is None or self._shown[0] != program:
            self._rebuild(program)
        self._shown = (program, selected, current)
        for marker, line in self._markers:
            marker.color = (
                CURRENT_RGB if line == current else SELECTED_RGB if line == selected else MARKER_RGB
            )

    def close(self) -> None:
        self.on_screen.replace([])  # first: no layout touches a label once it is going
        for node in self._nodes:
            node.remove()
        self._nodes.clear()
        self._markers.clear()
        self.labels = []
        self._shown = None

    def _rebuild(self, program: Program) -> None:
        self.close()
        try:
            plan = compile_program(program, lambda _name: Program())
        except PlanError:
            return
        drawing = _Drawing()
        self._walk(plan, drawing, None)
        scene = self._target.scene
        labels = dict(label_groups(drawing.markers))
        drawn: list[tuple[viser.LabelHandle, np.ndarray, str]] = []
        for k, (target, point) in enumerate(drawing.markers):
            marker = scene.add_icosphere(
                f"{ROOT}/waypoint_{k}",
                radius=MARKER_RADIUS_M,
                color=MARKER_RGB,
                position=point,
                cast_shadow=False,
                receive_shadow=False,
            )
            if k in labels:
                above = np.array([0.0, 0.0, LABEL_ABOVE_M])
                label = scene.add_label(
                    f"{ROOT}/waypoint_{k}/name", labels[k], position=above, anchor="bottom-center"
                )  # removed with its marker
                self.labels.append(labels[k])
                drawn.append((label, point + above, labels[k]))
            self._markers.append((marker, target.line))
            self._nodes.append(marker)
        self.on_screen.replace(drawn)
        if drawing.cells:
            self._nodes.append(
                scene.add_point_cloud(
                    f"{ROOT}/pallet_cells",
                    np.asarray(drawing.cells),
                    CELL_RGB,
                    point_size=2 * CELL_RADIUS_M,
                    point_shape="circle",
                    precision="float32",
                )
            )
        if drawing.recorded:
            self._nodes.append(
                scene.add_line_segments(
                    f"{ROOT}/recorded_paths",
                    np.asarray(drawing.recorded),
                    RECORDED_RGB,
                    thickness=PATH_THICKNESS_PX,
                    thickness_units="screen",
                )
            )
            self._nodes.append(
                scene.add_point_cloud(
                    f"{ROOT}/recorded_waypoints",
                    np.asarray(drawing.recorded_points),
                    RECORDED_RGB,
                    point_size=RECORDED_POINT_M,
                    point_shape="circle",
                    precision="float32",
                )
            )
        for motion, pieces in drawing.pieces.items():
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

    def _walk(
        self, nodes: tuple[Node, ...], drawing: _Drawing, pen: tuple[np.ndarray | None, np.ndarray] | None
    ) -> tuple[np.ndarray | None, np.ndarray] | None:
        """Draw `nodes` from `pen` (joint angles or None, TCP point); returns where the pen ends."""
        for node in nodes:
            match node:
                case MoveGroup() if node.path:
                    pen = self._recorded(node, drawing, pen)
                case MoveGroup():
                    for target in node.targets:
                        q, point = self._place(target)
                        drawing.markers.append((target, point))
                        if pen is not None:
                            drawing.pieces[node.motion].extend(
                                self._leg(pen[0], q, pen[1], point, node.motion)
                            )
                        pen = (q, point)
                case Loop():
                    pen = self._walk(node.body, drawing, pen)
                case Branch():
                    self._walk(node.otherwise, drawing, pen)
                    pen = self._walk(node.then, drawing, pen)
                case Pallet():
                    drawing.cells.extend(np.array([c.point.x, c.point.y, c.point.z]) for c in node.cells)
                    pen = self._walk(node.pass_nodes(0), drawing, pen)
        return pen

    def _recorded(
        self, node: MoveGroup, drawing: _Drawing, pen: tuple[np.ndarray | None, np.ndarray] | None
    ) -> tuple[np.ndarray | None, np.ndarray]:
        """A recorded path: straight segments through its waypoints, one marker (and name) at its end."""
        points = [self._place(target)[1] for target in node.targets]
        if pen is not None:
            points.insert(0, pen[1])
        drawing.recorded.extend(np.stack([a, b]) for a, b in itertools.pairwise(points))
        drawing.recorded_points.extend(points)
        drawing.markers.append((node.targets[-1], points[-1]))
        return None, points[-1]

    def _place(self, target: Target) -> tuple[np.ndarray | None, np.ndarray]:
        """Joint angles (radians, None for a TCP target) and where the marker goes: the flange by FK (as
        the scene's TCP frame) for angle targets, else the target's point."""
        if target.pose is not None:
            q = np.radians(np.asarray(target.pose.angles, dtype=float))
            if self._arm is not None:
                return q, self._arm.fk(q)[:3, 3]
        assert target.position is not None
        p = target.position.point
        return (None if target.pose is None else np.radians(target.pose.angles)), np.array([p.x, p.y, p.z])

    def _leg(
        self, q0: np.ndarray | None, q1: np.ndarray | None, p0: np.ndarray, p1: np.ndarray, motion: MotionType
    ) -> list[np.ndarray]:
        if motion is MotionType.LINEAR or self._arm is None or q0 is None or q1 is None:
            return [np.stack([p0, p1])]
        samples = [self._arm.fk(q0 + t * (q1 - q0))[:3, 3] for t in np.linspace(0.0, 1.0, JOINT_LEG_SAMPLES)]
        return [np.stack([a, b]) for a, b in itertools.pairwise(samples)]
