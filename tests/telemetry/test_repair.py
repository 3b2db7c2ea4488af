"""A recording whose pendant died mid-way (what kill -9 leaves: the chunks flushed so far, and an unfinished
one) is finished on the next start: readable with the official reader up to the last flush, its CSV made."""

from __future__ import annotations

import csv
import io
import shutil
from pathlib import Path

from pendant.controller import MotionParams, Pose
from pendant.sim import FakeClock, SimController
from pendant.telemetry import ArmState, Telemetry, csv_header
from pendant.telemetry.mcap_file import FLUSH_PERIOD_S
from pendant.telemetry.repair import finished, repair_all
from tests.support.mcap_reading import read_mcap
from tests.support.recordings import SAMPLE_PERIOD_S, WALL_START

RECORDED_S = 3.55


def test_an_unfinished_recording_is_finished_up_to_its_last_flush(
    sim: SimController, clock: FakeClock, tmp_path: Path
) -> None:
    live, after_crash = tmp_path / "live", tmp_path / "after-crash"
    after_crash.mkdir()
    telemetry = Telemetry(
        sim, now=clock.now, recordings_folder=live, wall_now=lambda: WALL_START + clock.now()
    )
    telemetry.start_recording()
    sim.set_pose(Pose(angles=[40.0, -70.0, 30.0, -90.0, -90.0, 20.0]), MotionParams(speed=30.0))
    for _ in range(round(RECORDED_S / SAMPLE_PERIOD_S)):
        clock.advance(SAMPLE_PERIOD_S)
        telemetry.sample(ArmState(sim.get_position()))
    [recording] = telemetry.recordings()
    # The bytes on disk while the writer is still open: what a killed process leaves behind.
    crashed = after_crash / recording.files[0].name
    shutil.copy(recording.files[0], crashed)
    assert not finished(crashed)

    notes = repair_all(after_crash)
    assert len(notes) == 1 and crashed.stem in notes[0] and "repaired" in notes[0]
    assert finished(crashed)
    _, messages = read_mcap(crashed)
    joints = [time_ns for topic, time_ns, _ in messages if topic == "/joints"]
    span_s = (joints[-1] - joints[0]) / 1e9
    assert span_s >= RECORDED_S - 2 * FLUSH_PERIOD_S, f"only {span_s:.2f} s survived"
    rows = list(csv.reader(io.StringIO(crashed.with_suffix(".csv").read_text())))
    assert rows[0] == csv_header() and len(rows) - 1 == len(joints)
    assert repair_all(after_crash) == [], "a finished file is left alone"
    telemetry.stop_recording()
    assert finished(recording.files[0])
