"""A recording draws the arm in Foxglove's 3D panel: its link frames match the pendant's own forward
kinematics, the links' meshes ride on them, the cell's obstacles and the TCP's course are there, and the
program step running is a series of its own. Read back with the official reader and protobuf decoder."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin
import pytest

from pendant.controller import MotionParams, Pose
from pendant.controller.cell_types import BoxObstacle
from pendant.controller.types import Point, Position, Rotation
from pendant.kinematics import ArmModel
from pendant.sim import FakeClock, SimController
from pendant.telemetry import ArmState, Telemetry, arm_drawing
from tests.support.mcap_reading import read_mcap
from tests.support.recordings import SAMPLE_PERIOD_S, WALL_START

N_SAMPLES = 25
FRAME_TOLERANCE_M = 1e-6
BOX = BoxObstacle(
    obstacleType="BOX",
    name="fixture",
    sides=Point(x=0.2, y=0.1, z=0.3),
    centerPosition=Position(
        point=Point(x=0.5, y=0.4, z=0.15), rotation=Rotation(roll=0.0, pitch=0.0, yaw=0.3)
    ),
)


@pytest.fixture
def arm() -> ArmModel:
    return ArmModel.load("pulse75")


def test_the_recording_draws_the_arm_the_cell_and_the_course(
    sim: SimController, clock: FakeClock, arm: ArmModel, tmp_path: Path
) -> None:
    telemetry = Telemetry(
        sim,
        now=clock.now,
        recordings_folder=tmp_path,
        wall_now=lambda: WALL_START + clock.now(),
        arm=arm_drawing(arm),
    )
    telemetry.start_recording()
    sim.set_pose(Pose(angles=[40.0, -70.0, 30.0, -90.0, -90.0, 20.0]), MotionParams(speed=30.0))
    angles = []
    for i in range(N_SAMPLES):
        clock.advance(SAMPLE_PERIOD_S)
        program = (2, "Move J to P1", "RUNNING") if i < 10 else (3, "Wait 1 s", "RUNNING")
        motors = telemetry.sample(ArmState(sim.get_position(), obstacles=(BOX,), program=program))
        assert motors is not None
        angles.append(np.radians([m.angle for m in motors]))
    telemetry.stop_recording()

    [recording] = telemetry.recordings()
    schemas, messages = read_mcap(recording.files[0])
    assert schemas["/tf"] == "foxglove.FrameTransforms" and schemas["/arm"] == "foxglove.SceneUpdate"
    by_topic: dict[str, list[Any]] = {}
    for topic, _, message in messages:
        by_topic.setdefault(topic, []).append(message)

    [meshes] = by_topic["/arm"]
    links = {entity.frame_id for entity in meshes.entities}
    assert {"base_link", "link1", "link6"} <= links
    for entity in meshes.entities:
        assert entity.frame_locked and entity.models[0].media_type == "model/gltf-binary"
        assert entity.models[0].data[:4] == b"glTF", "the mesh itself is in the file"

    transforms = by_topic["/tf"]
    assert len(transforms) == N_SAMPLES
    for q, message in zip(angles, transforms, strict=True):
        expected = arm.fk_all_links(q)
        frames = {t.child_frame_id: t for t in message.transforms}
        assert set(frames) == set(expected)
        for link, T in expected.items():
            t = frames[link]
            assert t.parent_frame_id == "base"
            got = np.array([t.translation.x, t.translation.y, t.translation.z])
            assert np.allclose(got, T[:3, 3], atol=FRAME_TOLERANCE_M), link
            R = pin.Quaternion(t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z).matrix()
            assert np.allclose(R, T[:3, :3], atol=1e-6), link
    assert not np.allclose(angles[0], angles[-1]), "the arm moved during the recording"

    [cell] = by_topic["/cell"]  # written once: the cell did not change
    [box] = cell.entities
    assert box.id == "cell/fixture"
    size = box.cubes[0].size
    assert (size.x, size.y, size.z) == pytest.approx((0.2, 0.1, 0.3))
    assert box.cubes[0].pose.position.x == pytest.approx(0.5)

    path_points = [
        (p.x, p.y, p.z)
        for update in by_topic["/tcp_path"]
        for entity in update.entities
        for p in entity.lines[0].points
    ]
    tcp = [arm.fk_all_links(q)["tcp"][:3, 3] for q in angles]
    assert len(by_topic["/tcp_path"]) == 2, "a piece per second of 10 samples"
    assert np.allclose(path_points[0], tcp[0]) and np.allclose(path_points[-1], tcp[19])

    steps = [(m["line"], m["step"]) for m in by_topic["/program"]]
    assert steps == [(2, "Move J to P1"), (3, "Wait 1 s")], "written when the step changes"
