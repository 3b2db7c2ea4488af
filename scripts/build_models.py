"""Generate the PULSE 75 and PULSE 90 arm models: `urdf/<model>.urdf` and the meshes in `assets/`.

The kinematic skeleton comes from the published DH tables (`pendant.kinematics.dh`) and the joint limits from
`pendant.kinematics.limits`; the shapes (joint housings, link tubes, base, gripper) are trimesh primitives
placed on those axes. The output is reproducible byte for byte: no randomness, fixed ordering, fixed float
formatting. Run `python scripts/build_models.py` (or `make models`) after changing the DH table or the limits;
`--out DIR` writes `DIR/urdf` and `DIR/assets` instead of the checkout (the test compares the two).

Link frames: `link{i}` is DH frame i-1 turned by theta_i about its z; `joint{i+1}` sits at
Tz(d_i) Tx(a_i) Rx(alpha_i) of DH row i; the `tcp` is DH frame 6 turned +90 degrees about z.
"""

from __future__ import annotations

import argparse
import math
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Literal

import numpy as np
import trimesh
from trimesh.visual.material import PBRMaterial
from trimesh.visual.texture import TextureVisuals

REPO_ROOT = Path(__file__).resolve().parent.parent
if str(REPO_ROOT) not in sys.path:  # run as a plain script from a checkout
    sys.path.insert(0, str(REPO_ROOT))

from pendant.kinematics.dh import DH_TABLES, DHTable  # noqa: E402
from pendant.kinematics.limits import (  # noqa: E402
    GRIPPER_STROKE_M,
    JOINT_LOWER_RAD,
    JOINT_MAX_EFFORT_NM,
    JOINT_MAX_SPEED_RAD_S,
    JOINT_UPPER_RAD,
    N_JOINTS,
)

# --- Proportions (metres) -------------------------------------------------------------------------------
# Joint housings of the big joints (J1-J3), the wrist (J4-J6), the link tubes and the base.
R_BIG_HOUSING = 0.06
R_WRIST_HOUSING = 0.045
R_UPPER_ARM_TUBE = 0.045
R_FOREARM_TUBE = 0.042
R_BASE = 0.08
R_BASE_FLANGE = 0.095
R_TOOL_FLANGE = 0.0315  # ISO 9409-1-50: 63 mm flange
CAP_THICKNESS = 0.01  # the dark end cap on the free face of a housing
RING_WIDTH = 0.006  # the dark ring in the gap of a rotating joint
RING_RADIUS_RATIO = 0.94  # rings are a little slimmer than their housing
BASE_FLANGE_TOP = 0.012
BASE_TOP = 0.088
LINK1_BOTTOM = BASE_TOP + 0.008
# Offsets along the parallel J2/J3/J4 axes (positive towards the wrist, i.e. along DH z1): the upper arm tube
# runs beside the shoulder, the forearm tube closer to the base axis; only their difference from d4 matters
# to the kinematics, so these are purely visual (UR-like zig-zag).
UPPER_ARM_OFFSET = 0.135
FOREARM_OFFSET = 0.025
WRIST1_TOP = 0.07  # where the J4 housing of the forearm ends along J4 (the J5 housing starts at d4 - r)
WRIST2_TOP = 0.068  # where the J5 housing of link4 ends along J5
FLANGE_RING_DEPTH = 0.022  # the J6 ring starts this far behind the tool flange face

# The gripper: a dark body on the flange and two fingers sliding along the tcp's y axis.
GRIPPER_ADAPTER_TOP = 0.008
R_GRIPPER_HOUSING = 0.042
GRIPPER_HOUSING_TOP = 0.03  # the round housing, then the rail block the fingers slide in
GRIPPER_BODY_TOP = 0.052
GRIPPER_BODY_HALF = (0.025, 0.06)  # half extents of the rail block in tcp x and y
FINGER_PAD = (0.0015, 0.022)  # thickness and length of the rubber pad on a finger's inner face
FINGER_GAP_CLOSED = 0.004  # half gap between the fingers when closed
FINGER_SIZE = (0.024, 0.012, 0.047)  # x (width), y (thickness), z (length below the body)
FINGER_OVERLAP = 0.004  # fingers start this far inside the body
GRIPPER_SPEED_M_S = 0.05
GRIPPER_FORCE_N = 40.0

# Collision cylinders: this much bigger than the visual shape (tighter at the wrist, where links sit close).
BIG_MARGIN = 0.005
WRIST_MARGIN = 0.002

SEGMENTS_BIG = 64
SEGMENTS_WRIST = 48

# Link masses (kg), about 20 kg for the PULSE 75 and 23 kg for the PULSE 90 (longer arm, stronger drives).
LINK_MASSES_KG: dict[str, dict[str, float]] = {
    "pulse75": {
        "base_link": 4.0,
        "link1": 3.8,
        "link2": 5.0,
        "link3": 3.0,
        "link4": 1.5,
        "link5": 1.5,
        "link6": 0.5,
        "gripper_body": 0.45,
        "finger_left": 0.075,
        "finger_right": 0.075,
    },
    "pulse90": {
        "base_link": 4.0,
        "link1": 4.2,
        "link2": 6.6,
        "link3": 4.0,
        "link4": 1.5,
        "link5": 1.5,
        "link6": 0.5,
        "gripper_body": 0.45,
        "finger_left": 0.075,
        "finger_right": 0.075,
    },
}


# --- Colours ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Paint:
    """A PBR material: base colour (0-255 RGB), metalness and roughness."""

    rgb: tuple[int, int, int]
    metallic: float = 0.0
    roughness: float = 0.5


PAINTS: dict[str, Paint] = {
    "white": Paint((238, 240, 242), roughness=0.42),  # link tubes and base
    "housing": Paint((216, 220, 224), roughness=0.45),  # joint housings, a shade greyer
    "cap": Paint((46, 48, 53), roughness=0.55),  # end caps of the housings
    "ring": Paint((26, 27, 30), roughness=0.6),  # the dark rings at the joints
    "metal": Paint((160, 163, 168), metallic=0.7, roughness=0.35),  # tool flange
    "gripper": Paint((40, 42, 46), roughness=0.55),
    "finger": Paint((70, 73, 79), roughness=0.45),
}
PAINT_ORDER = tuple(PAINTS)  # meshes inside a GLB follow this order, for reproducible files


# --- Geometry helpers -------------------------------------------------------------------------------------
def _rot(axis: Literal["x", "y"], angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    T = np.eye(4)
    if axis == "x":
        T[1:3, 1:3] = [[c, -s], [s, c]]
    else:
        T[0, 0], T[0, 2], T[2, 0], T[2, 2] = c, s, -s, c
    return T


Axis = Literal["x", "-x", "y", "-y", "z", "-z"]


def axis_frame(axis: Axis, origin: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> np.ndarray:
    """T_link_axis: a frame at `origin` whose z axis points along the named axis of the link frame."""
    rotations: dict[str, np.ndarray] = {
        "x": _rot("y", math.pi / 2),
        "-x": _rot("y", -math.pi / 2),
        "y": _rot("x", -math.pi / 2),
        "-y": _rot("x", math.pi / 2),
        "z": np.eye(4),
        "-z": _rot("x", math.pi),
    }
    T = rotations[axis].copy()
    T[:3, 3] = origin
    # Exact zeros and ones keep the output free of 6e-17 noise.
    return np.round(T, 15)


def _translate_z(z: float) -> np.ndarray:
    T = np.eye(4)
    T[2, 3] = z
    return T


@dataclass(frozen=True)
class Solid:
    """A solid cylinder (along its local z, centred) or box (centred) in a link frame."""

    kind: Literal["cylinder", "box"]
    size: tuple[float, ...]  # (radius, length) or (x, y, z) extents
    T_link_solid: np.ndarray

    @property
    def volume(self) -> float:
        if self.kind == "cylinder":
            radius, length = self.size
            return math.pi * radius**2 * length
        return float(np.prod(self.size))

    def inertia_about_centre(self, mass: float) -> np.ndarray:
        """The inertia tensor about the solid's centre, in link axes."""
        if self.kind == "cylinder":
            radius, length = self.size
            side = mass * (3 * radius**2 + length**2) / 12
            I_local = np.diag([side, side, mass * radius**2 / 2])
        else:
            x, y, z = self.size
            I_local = np.diag([y**2 + z**2, x**2 + z**2, x**2 + y**2]) * mass / 12
        R = self.T_link_solid[:3, :3]
        return R @ I_local @ R.T

    def inflated(self, margin: float) -> Solid:
        return Solid(
            self.kind,
            tuple(
                s + (margin if self.kind == "cylinder" and i == 0 else 2 * margin)
                for i, s in enumerate(self.size)
            ),
            self.T_link_solid,
        )


@dataclass
class LinkBody:
    """The shapes of one link, in its URDF frame: coloured visual meshes, collision solids, mass solids."""

    name: str
    wrist: bool  # wrist-sized: finer collision margin, fewer segments
    visuals: dict[str, list[trimesh.Trimesh]] = field(default_factory=dict)
    collisions: list[Solid] = field(default_factory=list)
    mass_solids: list[Solid] = field(default_factory=list)

    def _paint(self, paint: str, mesh: trimesh.Trimesh) -> None:
        self.visuals.setdefault(paint, []).append(mesh)

    def cylinder(
        self,
        T_link_axis: np.ndarray,
        radius: float,
        z0: float,
        z1: float,
        paint: str,
        *,
        chamfer: float = 0.0,
        collide: bool = True,
        weigh: bool = True,
        collide_span: tuple[float, float] | None = None,
        wrist: bool | None = None,
    ) -> None:
        """A cylinder along the z of `T_link_axis` from z0 to z1, with chamfered rims.

        `collide_span` widens the collision cylinder along the axis (to cover caps and rings beside it);
        `wrist` overrides the link's size class for this one shape."""
        wrist = self.wrist if wrist is None else wrist
        segments, margin = (SEGMENTS_WRIST, WRIST_MARGIN) if wrist else (SEGMENTS_BIG, BIG_MARGIN)
        c = min(chamfer, radius / 2, (z1 - z0) / 2)
        profile = [
            (0.0, z0),
            (radius - c, z0),
            (radius, z0 + c),
            (radius, z1 - c),
            (radius - c, z1),
            (0.0, z1),
        ]
        if c == 0.0:
            profile = [profile[0], profile[1], profile[4], profile[5]]
        mesh = trimesh.creation.revolve(np.array(profile), sections=segments)
        mesh.apply_transform(T_link_axis)
        self._paint(paint, mesh)
        solid = Solid("cylinder", (radius, z1 - z0), T_link_axis @ _translate_z((z0 + z1) / 2))
        if weigh:
            self.mass_solids.append(solid)
        if collide:
            lo, hi = collide_span if collide_span is not None else (z0, z1)
            span = Solid("cylinder", (radius, hi - lo), T_link_axis @ _translate_z((lo + hi) / 2))
            self.collisions.append(span.inflated(margin))

    def housing(
        self,
        T_link_axis: np.ndarray,
        radius: float,
        z0: float,
        z1: float,
        *,
        cap_low: bool = False,
        cap_high: bool = False,
        ring_low: bool = False,
        ring_high: bool = False,
        paint: str = "housing",
        wrist: bool | None = None,
    ) -> None:
        """A joint housing along the z of `T_link_axis` with dark end caps on its free faces and dark rings
        on the faces that turn against the neighbouring link."""
        lo = z0 - (CAP_THICKNESS if cap_low else RING_WIDTH if ring_low else 0.0)
        hi = z1 + (CAP_THICKNESS if cap_high else RING_WIDTH if ring_high else 0.0)
        if ring_low:
            self.ring(T_link_axis, radius * RING_RADIUS_RATIO, lo, z0 + 0.001, wrist=wrist)
        if ring_high:
            self.ring(T_link_axis, radius * RING_RADIUS_RATIO, z1 - 0.001, hi, wrist=wrist)
        self.cylinder(T_link_axis, radius, z0, z1, paint, chamfer=0.006, collide_span=(lo, hi), wrist=wrist)
        cap_radius = radius * 0.82
        if cap_low:
            self.cylinder(
                T_link_axis, cap_radius, lo, z0 + 0.001, "cap", chamfer=0.004, collide=False, wrist=wrist
            )
        if cap_high:
            self.cylinder(
                T_link_axis, cap_radius, z1 - 0.001, hi, "cap", chamfer=0.004, collide=False, wrist=wrist
            )

    def ring(
        self,
        T_link_axis: np.ndarray,
        radius: float,
        z0: float,
        z1: float,
        *,
        collide: bool = False,
        wrist: bool | None = None,
    ) -> None:
        """The dark ring in the gap of a rotating joint (by default visual only: a neighbouring housing's
        collision span covers it)."""
        self.cylinder(T_link_axis, radius, z0, z1, "ring", collide=collide, weigh=False, wrist=wrist)

    def box(
        self,
        lo: tuple[float, float, float],
        hi: tuple[float, float, float],
        paint: str,
        *,
        collide: bool = True,
    ) -> None:
        """An axis-aligned box from corner `lo` to corner `hi`."""
        extents = tuple(high - low for low, high in zip(lo, hi, strict=True))
        T = np.eye(4)
        T[:3, 3] = [(low + high) / 2 for low, high in zip(lo, hi, strict=True)]
        self._paint(paint, trimesh.creation.box(extents=extents, transform=T))
        solid = Solid("box", extents, T)
        if collide:
            self.mass_solids.append(solid)
            self.collisions.append(solid.inflated(WRIST_MARGIN if self.wrist else BIG_MARGIN))


# --- The arm's shapes, link by link -----------------------------------------------------------------------
def build_bodies(dh: DHTable) -> list[LinkBody]:
    """The shapes of every link of an arm, each in its own URDF link frame."""
    d1, _, _, d4, d5, d6 = dh.d
    a2, a3 = dh.a[1], dh.a[2]
    wrist_housing_start = d4 - R_WRIST_HOUSING  # along J4, where the J5 housing begins

    base = LinkBody("base_link", wrist=False)
    up = axis_frame("z")
    base.cylinder(up, R_BASE_FLANGE, 0.0, BASE_FLANGE_TOP, "cap", chamfer=0.003)
    base.cylinder(up, R_BASE, BASE_FLANGE_TOP, BASE_TOP, "white", chamfer=0.006)

    # link1: the vertical J1 housing and the horizontal J2 housing on top (J2 axis along DH z1 = -y here).
    link1 = LinkBody("link1", wrist=False)
    link1.ring(up, R_BIG_HOUSING * 0.95, BASE_TOP - 0.002, LINK1_BOTTOM)
    link1.cylinder(
        up, R_BIG_HOUSING, LINK1_BOTTOM, d1, "housing", chamfer=0.006, collide_span=(BASE_TOP - 0.002, d1)
    )
    j2 = axis_frame("-y", (0.0, 0.0, d1))
    shoulder_split = UPPER_ARM_OFFSET - R_UPPER_ARM_TUBE - 0.007 - RING_WIDTH
    link1.housing(j2, R_BIG_HOUSING, -R_BIG_HOUSING - 0.008, shoulder_split, cap_low=True)

    # link2: the upper arm, from the J2 axis (x = 0) to the J3 axis (x = a2), beside the shoulder.
    link2 = LinkBody("link2", wrist=False)
    j2 = axis_frame("z")
    arm_top = UPPER_ARM_OFFSET + R_UPPER_ARM_TUBE + 0.007
    link2.housing(j2, R_BIG_HOUSING, shoulder_split + RING_WIDTH, arm_top, cap_high=True, ring_low=True)
    link2.cylinder(axis_frame("x", (0.0, 0.0, UPPER_ARM_OFFSET)), R_UPPER_ARM_TUBE, a2, 0.0, "white")
    j3 = axis_frame("z", (a2, 0.0, 0.0))
    elbow_split = FOREARM_OFFSET + R_FOREARM_TUBE + 0.004
    link2.housing(j3, R_BIG_HOUSING, elbow_split + RING_WIDTH, arm_top, cap_high=True)

    # link3: the forearm, from the J3 axis (x = 0) to the J4 axis (x = a3), nearer the base axis.
    link3 = LinkBody("link3", wrist=False)
    j3 = axis_frame("z")
    link3.housing(
        j3, R_BIG_HOUSING, FOREARM_OFFSET - R_FOREARM_TUBE - 0.008, elbow_split, cap_low=True, ring_high=True
    )
    link3.cylinder(axis_frame("x", (0.0, 0.0, FOREARM_OFFSET)), R_FOREARM_TUBE, a3, 0.0, "white")
    j4 = axis_frame("z", (a3, 0.0, 0.0))
    link3.housing(
        j4, R_WRIST_HOUSING, FOREARM_OFFSET - R_FOREARM_TUBE - 0.008, WRIST1_TOP, cap_low=True, wrist=True
    )

    # link4: the J5 housing, its axis (DH z4 = -y here) crossing the J4 axis at z = d4.
    link4 = LinkBody("link4", wrist=True)
    link4.ring(axis_frame("z"), R_WRIST_HOUSING * 0.9, WRIST1_TOP, wrist_housing_start + 0.004, collide=True)
    j5 = axis_frame("-y", (0.0, 0.0, d4))
    link4.housing(j5, R_WRIST_HOUSING, -R_WRIST_HOUSING - 0.005, WRIST2_TOP, cap_low=True)

    # link5: along the J5 axis (z here) out to the J6 housing, whose axis (DH z5 = +y here) is at z = d5.
    link5 = LinkBody("link5", wrist=True)
    j5 = axis_frame("z")
    link5.ring(j5, R_WRIST_HOUSING * 0.9, WRIST2_TOP, WRIST2_TOP + RING_WIDTH)
    link5.cylinder(
        j5,
        R_WRIST_HOUSING,
        WRIST2_TOP + RING_WIDTH,
        d5,
        "housing",
        chamfer=0.004,
        collide_span=(WRIST2_TOP, d5),
    )
    j6 = axis_frame("y", (0.0, 0.0, d5))
    link5.housing(j6, R_WRIST_HOUSING, -R_WRIST_HOUSING - 0.005, d6 - FLANGE_RING_DEPTH, cap_low=True)

    # link6: the J6 ring and the tool flange, whose face is at z = d6.
    link6 = LinkBody("link6", wrist=True)
    j6 = axis_frame("z")
    flange_back = d6 - FLANGE_RING_DEPTH
    link6.cylinder(j6, R_WRIST_HOUSING * 0.9, flange_back, d6 - 0.012, "ring")
    link6.cylinder(j6, R_TOOL_FLANGE, d6 - 0.012, d6, "metal", chamfer=0.002)

    # The gripper, in the tcp frame (z out of the flange): an adapter disc and a body, fingers along y.
    gripper = LinkBody("gripper_body", wrist=True)
    gripper.cylinder(axis_frame("z"), R_TOOL_FLANGE, 0.0, GRIPPER_ADAPTER_TOP, "cap", chamfer=0.002)
    gripper.cylinder(
        axis_frame("z"), R_GRIPPER_HOUSING, GRIPPER_ADAPTER_TOP, GRIPPER_HOUSING_TOP, "gripper", chamfer=0.004
    )
    hx, hy = GRIPPER_BODY_HALF
    gripper.box((-hx, -hy, GRIPPER_HOUSING_TOP), (hx, hy, GRIPPER_BODY_TOP), "gripper")

    fingers = []
    for name, sign in (("finger_left", 1.0), ("finger_right", -1.0)):
        finger = LinkBody(name, wrist=True)
        fx, fy, fz = FINGER_SIZE
        inner, outer = sign * FINGER_GAP_CLOSED, sign * (FINGER_GAP_CLOSED + fy)
        finger.box((-fx / 2, min(inner, outer), -FINGER_OVERLAP), (fx / 2, max(inner, outer), fz), "finger")
        # The pad sits inside the collision margin of the finger, so it is visual only.
        pad_thickness, pad_length = FINGER_PAD
        pad_inner = inner - sign * pad_thickness
        finger.box(
            (-fx / 2 + 0.002, min(inner, pad_inner), fz - pad_length),
            (fx / 2 - 0.002, max(inner, pad_inner), fz - 0.002),
            "ring",
            collide=False,
        )
        fingers.append(finger)

    return [base, link1, link2, link3, link4, link5, link6, gripper, *fingers]


# --- Inertia ------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Inertial:
    mass: float
    com: np.ndarray
    inertia: np.ndarray  # about the centre of mass, link axes


def inertial_of(body: LinkBody, mass: float) -> Inertial:
    """Spread `mass` over the body's solids by volume: centre of mass and inertia of the union."""
    volumes = np.array([s.volume for s in body.mass_solids])
    masses = mass * volumes / volumes.sum()
    centres = np.array([s.T_link_solid[:3, 3] for s in body.mass_solids])
    com = masses @ centres / mass
    inertia = np.zeros((3, 3))
    for solid, m, centre in zip(body.mass_solids, masses, centres, strict=True):
        offset = centre - com
        inertia += solid.inertia_about_centre(m) + m * (
            offset @ offset * np.eye(3) - np.outer(offset, offset)
        )
    return Inertial(mass, com, inertia)


# --- Output -------------------------------------------------------------------------------------------------
def _num(x: float) -> str:
    text = f"{x:.12g}"
    return "0" if text in ("-0", "0") else text


def _vec(values) -> str:
    return " ".join(_num(float(v)) for v in values)


def _rpy_of(R: np.ndarray) -> tuple[float, float, float]:
    """Fixed-axis roll, pitch, yaw of a rotation (R = Rz(yaw) Ry(pitch) Rx(roll))."""
    pitch = math.asin(-max(-1.0, min(1.0, R[2, 0])))
    if abs(R[2, 0]) < 1 - 1e-12:
        roll = math.atan2(R[2, 1], R[2, 2])
        yaw = math.atan2(R[1, 0], R[0, 0])
    else:  # gimbal lock: put everything in yaw
        roll = 0.0
        yaw = math.atan2(-R[0, 1], R[1, 1])
    return roll, pitch, yaw


def _origin(T: np.ndarray) -> str:
    return f'<origin xyz="{_vec(T[:3, 3])}" rpy="{_vec(_rpy_of(T[:3, :3]))}"/>'


def mesh_scene(body: LinkBody) -> trimesh.Scene:
    """One mesh per paint, each with its PBR material, in the fixed paint order."""
    scene = trimesh.Scene()
    for paint_name in PAINT_ORDER:
        parts = body.visuals.get(paint_name)
        if not parts:
            continue
        mesh = trimesh.util.concatenate(parts)
        paint = PAINTS[paint_name]
        mesh.visual = TextureVisuals(
            material=PBRMaterial(
                name=paint_name,
                baseColorFactor=[*paint.rgb, 255],
                metallicFactor=paint.metallic,
                roughnessFactor=paint.roughness,
            )
        )
        mesh.metadata = {}
        scene.add_geometry(mesh, geom_name=f"{body.name}_{paint_name}", node_name=f"{body.name}_{paint_name}")
    return scene


def _link_xml(model: str, body: LinkBody, inertial: Inertial) -> str:
    inertia = inertial.inertia
    lines = [f'  <link name="{body.name}">']
    lines += [
        "    <inertial>",
        f'      <origin xyz="{_vec(inertial.com)}" rpy="0 0 0"/>',
        f'      <mass value="{_num(inertial.mass)}"/>',
        f'      <inertia ixx="{_num(inertia[0, 0])}" ixy="{_num(inertia[0, 1])}" ixz="{_num(inertia[0, 2])}" '
        f'iyy="{_num(inertia[1, 1])}" iyz="{_num(inertia[1, 2])}" izz="{_num(inertia[2, 2])}"/>',
        "    </inertial>",
        f'    <visual name="{body.name}_visual">',
        '      <origin xyz="0 0 0" rpy="0 0 0"/>',
        f'      <geometry><mesh filename="../assets/{model}_{body.name}.glb"/></geometry>',
        "    </visual>",
    ]
    for solid in body.collisions:
        if solid.kind == "cylinder":
            radius, length = solid.size
            geometry = f'<cylinder radius="{_num(radius)}" length="{_num(length)}"/>'
        else:
            geometry = f'<box size="{_vec(solid.size)}"/>'
        lines += [
            "    <collision>",
            f"      {_origin(solid.T_link_solid)}",
            f"      <geometry>{geometry}</geometry>",
            "    </collision>",
        ]
    lines.append("  </link>")
    return "\n".join(lines)


def _joint_xml(
    name: str,
    kind: str,
    parent: str,
    child: str,
    xyz: tuple[float, ...],
    rpy: tuple[float, ...],
    *,
    axis: tuple[float, float, float] | None = None,
    limit: tuple[float, float, float, float] | None = None,
    mimic: str | None = None,
) -> str:
    lines = [
        f'  <joint name="{name}" type="{kind}">',
        f'    <parent link="{parent}"/>',
        f'    <child link="{child}"/>',
        f'    <origin xyz="{_vec(xyz)}" rpy="{_vec(rpy)}"/>',
    ]
    if axis is not None:
        lines.append(f'    <axis xyz="{_vec(axis)}"/>')
    if limit is not None:
        lower, upper, effort, velocity = limit
        lines.append(
            f'    <limit lower="{_num(lower)}" upper="{_num(upper)}" effort="{_num(effort)}" '
            f'velocity="{_num(velocity)}"/>'
        )
    if mimic is not None:
        lines.append(f'    <mimic joint="{mimic}" multiplier="1" offset="0"/>')
    lines.append("  </joint>")
    return "\n".join(lines)


def urdf_text(model: str, dh: DHTable, bodies: list[LinkBody]) -> str:
    """The URDF of one arm; meshes are named relative to `urdf/` as `../assets/<model>_<link>.glb`."""
    masses = LINK_MASSES_KG[model]
    title = model.replace("pulse", "PULSE ")
    parts = [
        '<?xml version="1.0"?>',
        f"<!-- {title}: generated by scripts/build_models.py from pendant/kinematics/dh.py and limits.py;"
        " do not edit by hand. -->",
        f'<robot name="{model}">',
    ]
    parts += [_link_xml(model, body, inertial_of(body, masses[body.name])) for body in bodies[:7]]
    parts.append('  <link name="tcp"/>')
    parts += [_link_xml(model, body, inertial_of(body, masses[body.name])) for body in bodies[7:]]

    for i in range(N_JOINTS):
        if i == 0:
            xyz, rpy = (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
            parent = "base_link"
        else:  # Tz(d_i) Tx(a_i) Rx(alpha_i) of DH row i (1-based), i.e. index i - 1
            xyz, rpy = (dh.a[i - 1], 0.0, dh.d[i - 1]), (dh.alpha[i - 1], 0.0, 0.0)
            parent = f"link{i}"
        limit = (
            float(JOINT_LOWER_RAD[i]),
            float(JOINT_UPPER_RAD[i]),
            float(JOINT_MAX_EFFORT_NM[i]),
            float(JOINT_MAX_SPEED_RAD_S[i]),
        )
        parts.append(
            _joint_xml(
                f"joint{i + 1}", "revolute", parent, f"link{i + 1}", xyz, rpy, axis=(0, 0, 1), limit=limit
            )
        )
    parts.append(
        _joint_xml("tcp_joint", "fixed", "link6", "tcp", (0.0, 0.0, dh.d[5]), (0.0, 0.0, dh.tcp_yaw))
    )
    parts.append(
        _joint_xml("gripper_joint", "fixed", "tcp", "gripper_body", (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    )
    finger_origin = (0.0, 0.0, GRIPPER_BODY_TOP)
    finger_limit = (0.0, GRIPPER_STROKE_M, GRIPPER_FORCE_N, GRIPPER_SPEED_M_S)
    parts.append(
        _joint_xml(
            "finger_left_joint",
            "prismatic",
            "gripper_body",
            "finger_left",
            finger_origin,
            (0.0, 0.0, 0.0),
            axis=(0, 1, 0),
            limit=finger_limit,
        )
    )
    parts.append(
        _joint_xml(
            "finger_right_joint",
            "prismatic",
            "gripper_body",
            "finger_right",
            finger_origin,
            (0.0, 0.0, 0.0),
            axis=(0, -1, 0),
            limit=finger_limit,
            mimic="finger_left_joint",
        )
    )
    parts.append("</robot>")
    return "\n".join(parts) + "\n"


def build(out_dir: Path) -> list[Path]:
    """Write `out_dir/urdf/<model>.urdf` and `out_dir/assets/<model>_<link>.glb` for every model."""
    urdf_dir, assets_dir = out_dir / "urdf", out_dir / "assets"
    urdf_dir.mkdir(parents=True, exist_ok=True)
    assets_dir.mkdir(parents=True, exist_ok=True)
    written = []
    for model, dh in sorted(DH_TABLES.items()):
        bodies = build_bodies(dh)
        for body in bodies:
            path = assets_dir / f"{model}_{body.name}.glb"
            path.write_bytes(mesh_scene(body).export(file_type="glb"))
            written.append(path)
        path = urdf_dir / f"{model}.urdf"
        path.write_text(urdf_text(model, dh, bodies))
        written.append(path)
    return written


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=REPO_ROOT, help="folder to write urdf/ and assets/ into")
    args = parser.parse_args(argv)
    for path in build(args.out):
        print(path)


if __name__ == "__main__":
    main()
