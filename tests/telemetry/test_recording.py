"""Telemetry: a CSV recording holds what GET /status/motors said; the history keeps the last 60 s."""

from __future__ import annotations

import csv
import io
from pathlib import Path

import numpy as np
import pytest

from pendant.controller import MotionParams, Pose
from pendant.sim import FakeClock, SimController
from pendant.telemetry import CSV_FIELDS, HISTORY_S, Telemetry, csv_header

SAMPLE_PERIOD_S = 0.1
VALUE_TOL = 1e-9


@pytest.fixture
def telemetry(sim: SimController, clock: FakeClock, tmp_path: Path) -> Telemetry:
    return Telemetry(sim, now=clock.now, recordings_folder=tmp_path)


def test_csv_round_trip_matches_get_motors_during_a_motion(
    telemetry: Telemetry, sim: SimController, clock: FakeClock
) -> None:
    telemetry.start_recording()
    sim.set_pose(Pose(angles=[40.0, -70.0, 30.0, -90.0, -90.0, 20.0]), MotionParams(speed=30.0))
    expected = []
    for _ in range(20):
        clock.advance(SAMPLE_PERIOD_S)
        expected.append(telemetry.sample())
    assert telemetry.stop_recording() == 20
    clock.advance(SAMPLE_PERIOD_S)
    telemetry.sample()  # after stop: not recorded

    rows = list(csv.reader(io.StringIO(telemetry.recorder.to_csv().decode())))
    assert rows[0] == csv_header()
    assert rows[0][1:4] == ["m1_angle", "m1_rotorVelocity", "m1_rmsCurrent"]
    assert len(rows) == 1 + 20
    for i, (row, motors) in enumerate(zip(rows[1:], expected, strict=True)):
        assert float(row[0]) == pytest.approx((i + 1) * SAMPLE_PERIOD_S)
        assert motors is not None
        values = [getattr(m, field) for m in motors for field in CSV_FIELDS]
        np.testing.assert_allclose([float(v) for v in row[1:]], values, rtol=0, atol=VALUE_TOL)
    angles = np.array([[float(r[1 + j * len(CSV_FIELDS)]) for j in range(6)] for r in rows[1:]])
    assert angles[-1, 0] > angles[0, 0] + 1.0, "the recording saw J1 turning"


def test_a_new_recording_starts_empty(telemetry: Telemetry, clock: FakeClock) -> None:
    telemetry.start_recording()
    telemetry.sample()
    telemetry.stop_recording()
    telemetry.start_recording()
    assert telemetry.recorder.row_count == 0
    assert telemetry.recorder.recording


def test_history_keeps_the_last_minute_in_order(
    telemetry: Telemetry, sim: SimController, clock: FakeClock
) -> None:
    sim.set_pose(Pose(angles=[90.0, -90.0, 0.0, -90.0, -90.0, 0.0]), MotionParams(speed=5.0))
    for _ in range(int(2 * HISTORY_S / SAMPLE_PERIOD_S)):
        clock.advance(SAMPLE_PERIOD_S)
        telemetry.sample()
    window = telemetry.history.window()
    assert window.t[0] == pytest.approx(-HISTORY_S)
    assert window.t[-1] == 0.0
    assert np.all(np.diff(window.t) > 0)
    latest = telemetry.latest
    assert latest is not None
    np.testing.assert_allclose(window.angle_deg[-1], [m.angle for m in latest])
    np.testing.assert_allclose(window.current_a[-1], [m.rmsCurrent for m in latest])
    np.testing.assert_allclose(window.stator_c[-1], [m.statorTemperature for m in latest])
