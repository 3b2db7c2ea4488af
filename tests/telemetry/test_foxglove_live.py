"""The live view in Foxglove, over real WebSockets on a real `pendant --foxglove-port`: connected as Foxglove
connects (subprotocol, advertise, subscribe), it carries the recordings' channels with the same schemas, and
/joints and /tf follow a move as it happens."""

from __future__ import annotations

import json
import socket
import subprocess
import time
from pathlib import Path

import httpx
import jsonschema
import pytest

from pendant.controller.cell_types import BoxObstacle
from pendant.controller.types import Point, Position, Rotation
from pendant.eventlog import EventKind, EventLog
from pendant.sim import SimController
from pendant.telemetry import ArmState, LiveView, Telemetry, arm_drawing
from tests.support import preloaded
from tests.support.foxglove_client import FoxgloveClient, Received
from tests.support.launchers import child_env, pendant_command, pendant_process
from tests.support.mcap_reading import read_mcap
from tests.support.ports import free_port
from tests.support.waiting import SAFETY_NET_S, wait_idle

START_DEG = [0.0, -90.0, 0.0, -90.0, 0.0, 0.0]
TARGET_DEG = [40.0, -90.0, 0.0, -90.0, 0.0, 0.0]
SPEED = 20  # percent: a move of a few seconds, so many samples fall inside it
ANGLE_TOL_DEG = 0.5
SETTLE_S = 1.0  # after the arm is idle: the samples that show it at rest
SAMPLE_TIMEOUT_S = 60.0


def at_rest(foxglove: FoxgloveClient) -> list[Received]:
    """SETTLE_S of messages, longer if no /joints sample came in it (a pendant starved of CPU, at nice 19 on
    a loaded machine, may send none for a second): what shows the arm at rest before and after the move."""
    received: list[Received] = []
    deadline = time.monotonic() + SAMPLE_TIMEOUT_S
    while not any(m.topic == "/joints" for m in received):
        assert time.monotonic() < deadline, "no /joints message came"
        received += foxglove.messages(SETTLE_S)
    return received


def _joints(messages: list[Received], schema: dict[str, object]) -> list[list[float]]:
    angles = []
    for message in messages:
        decoded = json.loads(message.payload)
        jsonschema.validate(decoded, schema)
        angles.append(decoded["position_deg"])
    return angles


def test_foxglove_sees_the_recordings_channels_and_follows_a_move_live(tmp_path: Path) -> None:
    port = free_port()
    with pendant_process("--data", str(tmp_path), "--foxglove-port", str(port)) as (process, base):
        api = httpx.Client(base_url=base, timeout=SAFETY_NET_S)
        assert api.put(f"/pose?speed={SPEED}", json={"angles": START_DEG}).status_code == 200
        wait_idle(api)
        # A recording made meanwhile: the live channels are the file's, schema for schema.
        assert api.post("/pendant/recordings", json={"name": "beside"}).status_code == 201
        with FoxgloveClient(f"ws://127.0.0.1:{port}") as foxglove:
            foxglove.wait_for_channels("/joints", "/tf", "/tcp", "/motors", "/io", "/events", "/arm", "/cell")
            assert foxglove.ws.subprotocol == "foxglove.sdk.v1", "the SDK's name of foxglove.websocket.v1"
            assert foxglove.server_info["name"] == "PULSE pendant"
            joints_schema = foxglove.json_schema("/joints")
            for broken in ({}, {"name": [], "position_deg": [], "velocity_rpm": [], "extra": 1}):
                with pytest.raises(jsonschema.ValidationError):
                    jsonschema.validate(broken, joints_schema)
            foxglove.subscribe("/joints", "/tf", "/arm")
            before = at_rest(foxglove)
            assert api.put(f"/pose?speed={SPEED}", json={"angles": TARGET_DEG}).status_code == 200
            during: list[Received] = []
            while api.get("/status/motion").text.strip('"') != "IDLE":
                during += foxglove.messages(0.2)
            during += at_rest(foxglove)
            live_schemas = {topic: channel for topic, channel in foxglove.channels.items()}
        assert api.post("/pendant/recordings/beside/stop").status_code == 200
        assert f"Foxglove live view: ws://127.0.0.1:{port}" in _said(process)

    joints = [m for m in before + during if m.topic == "/joints"]
    j1 = [angles[0] for angles in _joints(joints, joints_schema)]
    assert j1, "no /joints message came"
    assert abs(j1[0] - START_DEG[0]) < ANGLE_TOL_DEG and abs(j1[-1] - TARGET_DEG[0]) < ANGLE_TOL_DEG, j1
    on_the_way = [a for a in j1 if START_DEG[0] + 1.0 < a < TARGET_DEG[0] - 1.0]
    assert len(on_the_way) >= 3, f"the move is seen as it happens, not only its end: {j1}"
    assert on_the_way == sorted(on_the_way), "J1 only rises on its way to the target"

    frames = [foxglove.decode_protobuf(m) for m in before + during if m.topic == "/tf"]
    assert frames, "no /tf message came"
    first = {t.child_frame_id: t.rotation for t in frames[0].transforms}
    last = {t.child_frame_id: t.rotation for t in frames[-1].transforms}
    assert first.keys() == last.keys() and len(first) >= 6
    assert first != last, "the links turned in /tf"

    arm = [foxglove.decode_protobuf(m) for m in before if m.topic == "/arm"]
    assert arm and len(arm[0].entities) >= 6, "a client that subscribes gets the arm's meshes at once"

    file_schemas, _ = read_mcap(tmp_path / "recordings" / "pendant-beside.mcap")
    # The file has the channels that got a message (no cell read and no program run here: no /cell, /program).
    assert set(file_schemas) >= {"/joints", "/tf", "/tcp", "/motors", "/io", "/arm"}
    assert set(file_schemas) <= set(live_schemas)
    for topic, expected in file_schemas.items():
        channel = live_schemas[topic]
        if isinstance(expected, dict):
            assert foxglove.json_schema(topic) == expected, topic
        else:
            assert channel.schema_name == expected, topic


def test_a_taken_port_ends_the_start_with_the_reason(tmp_path: Path) -> None:
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        command = pendant_command("--no-ui", "--api-port", str(free_port()), "--foxglove-port", str(port))
        command += ["--data", str(tmp_path)]
        done = preloaded.run(command, env=child_env(), capture_output=True, text=True, timeout=60)
    assert done.returncode == 1, done
    assert f"cannot serve the Foxglove live view on 127.0.0.1:{port}" in done.stderr, done.stderr
    assert "Address already in use" in done.stderr and "Traceback" not in done.stderr, done.stderr


def _said(process: subprocess.Popen[str]) -> str:
    """What the pendant printed so far (its output goes to a file)."""
    assert process.stdout is not None
    process.stdout.seek(0)
    return process.stdout.read()


BOX = BoxObstacle(
    obstacleType="BOX",
    name="fixture",
    sides=Point(x=0.2, y=0.1, z=0.3),
    centerPosition=Position(
        point=Point(x=0.5, y=0.4, z=0.15), rotation=Rotation(roll=0.0, pitch=0.0, yaw=0.0)
    ),
)


def test_a_client_that_comes_later_gets_the_cell_and_the_events(sim: SimController, tmp_path: Path) -> None:
    """The cell is written when it changes: Foxglove connecting afterwards still draws it (sent again at its
    subscription); events logged go to /events as they come."""
    telemetry = Telemetry(sim, recordings_folder=tmp_path, arm=arm_drawing(sim.arm))
    live = LiveView("127.0.0.1", 0)
    telemetry.attach_live(live)
    try:
        telemetry.sample(ArmState(sim.get_position(), obstacles=(BOX,)))  # nobody is connected yet
        with FoxgloveClient(live.url) as foxglove:
            foxglove.wait_for_channels("/cell", "/events")
            foxglove.subscribe("/cell", "/events")
            cells = [m for m in foxglove.messages(SETTLE_S) if m.topic == "/cell"]
            events = EventLog()
            events.on_record(telemetry.log_event)
            events.record(EventKind.COMMAND, "API 127.0.0.1 (curl)", "PUT /freeze")
            logs = [m for m in foxglove.messages(SETTLE_S) if m.topic == "/events"]
            assert cells, "no /cell message at the subscription"
            drawn = foxglove.decode_protobuf(cells[0])
            assert [entity.id for entity in drawn.entities] == ["cell/fixture"]
            assert logs, "no /events message"
            assert "PUT /freeze" in foxglove.decode_protobuf(logs[0]).message
    finally:
        telemetry.stop_live()
