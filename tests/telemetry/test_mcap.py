"""Recordings in MCAP, read back with the official `mcap` reader and its protobuf decoder (what Foxglove and
Lichtblick open): Foxglove's schemas for the arm's frames, meshes, the cell, the TCP's course and the log;
JSON-schema series for the motors as GET /status/motors said, the TCP, IO and the program step; the CSV."""

from __future__ import annotations

import csv
import io
from pathlib import Path
from typing import Any

import pytest

from pendant.controller import MotionParams, Pose, SignalLevel
from pendant.eventlog import EventKind, EventLog
from pendant.sim import FakeClock, SimController
from pendant.telemetry import ArmState, Telemetry, csv_header
from pendant.telemetry.recordings import MAX_KEPT
from tests.support.mcap_reading import read_mcap
from tests.support.recordings import SAMPLE_PERIOD_S, WALL_START

N_SAMPLES = 20
TOPICS = {"/joints", "/tcp", "/motors", "/io", "/events"}  # those a recording without the arm drawn fills


@pytest.fixture
def telemetry(sim: SimController, clock: FakeClock, tmp_path: Path) -> Telemetry:
    return Telemetry(
        sim, now=clock.now, recordings_folder=tmp_path, wall_now=lambda: WALL_START + clock.now()
    )


def test_a_recording_opens_in_an_mcap_reader(
    telemetry: Telemetry, sim: SimController, clock: FakeClock
) -> None:
    events = EventLog(now=lambda: WALL_START + clock.now())
    events.on_record(telemetry.log_event)
    telemetry.start_recording()
    events.record(EventKind.COMMAND, "browser #1 (127.0.0.1)", "Move J")
    sim.set_pose(Pose(angles=[40.0, -70.0, 30.0, -90.0, -90.0, 20.0]), MotionParams(speed=30.0))
    sim.set_output(1, SignalLevel.HIGH)
    expected = []
    for _ in range(N_SAMPLES):
        clock.advance(SAMPLE_PERIOD_S)
        state = ArmState(sim.get_position(), {1: SignalLevel.HIGH, 2: SignalLevel.LOW}, {}, "RUNNING")
        expected.append((sim.get_position(), telemetry.sample(state)))
    assert telemetry.stop_recording() == N_SAMPLES

    [recording] = telemetry.recordings()
    mcap_path, csv_path = recording.files
    assert mcap_path.suffix == ".mcap" and csv_path.suffix == ".csv"
    schemas, messages = read_mcap(mcap_path)
    assert set(schemas) >= TOPICS
    assert "position_deg" in schemas["/joints"]["properties"]

    by_topic: dict[str, list[tuple[int, Any]]] = {topic: [] for topic in TOPICS}
    for topic, time_ns, message in messages:
        by_topic[topic].append((time_ns, message))
    assert [m.message for _, m in by_topic["/events"]] == ["[command] Move J"]
    assert [m.name for _, m in by_topic["/events"]] == ["browser #1 (127.0.0.1)"]
    assert {len(by_topic[t]) for t in ("/joints", "/tcp", "/motors", "/io")} == {N_SAMPLES}
    for i, ((position, motors), (time_ns, joints), (_, tcp), (_, motor_msg), (_, io_msg)) in enumerate(
        zip(
            expected, by_topic["/joints"], by_topic["/tcp"], by_topic["/motors"], by_topic["/io"], strict=True
        )
    ):
        assert time_ns == pytest.approx((WALL_START + (i + 1) * SAMPLE_PERIOD_S) * 1e9, abs=1e3)
        assert motors is not None
        assert joints["position_deg"] == [m.angle for m in motors]
        assert motor_msg["motors"] == [m.model_dump() for m in motors]
        assert tcp["x"] == position.point.x and tcp["yaw"] == position.rotation.yaw
        assert io_msg == {"outputs": [1.0, 0.0], "inputs": [0.0, 0.0, 0.0, 0.0], "motion_status": "RUNNING"}
    first, last = by_topic["/joints"][0][1], by_topic["/joints"][-1][1]
    assert last["position_deg"][0] > first["position_deg"][0] + 1.0, "J1 turning is in the file"

    rows = list(csv.reader(io.StringIO(csv_path.read_text())))
    assert rows[0] == csv_header() and len(rows) == 1 + N_SAMPLES


def test_recordings_are_kept_newest_first_and_bounded(telemetry: Telemetry, clock: FakeClock) -> None:
    for _ in range(MAX_KEPT + 2):
        telemetry.start_recording()
        clock.advance(SAMPLE_PERIOD_S)
        telemetry.sample()
        telemetry.stop_recording()
        clock.advance(1.0)  # a new second: a new name
    kept = telemetry.recordings()
    assert len(kept) == MAX_KEPT
    assert kept[0].stem > kept[-1].stem and all(len(r.files) == 2 for r in kept)
    for recording in kept[:3]:
        _, messages = read_mcap(recording.files[0])
        assert [topic for topic, _, _ in messages if topic == "/joints"] == ["/joints"]
