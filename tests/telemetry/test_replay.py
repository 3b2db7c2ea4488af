"""A recording read back for replay: the joints at any time are those recorded then, the events and the
program step are on the same time axis, the stops and errors are listed to jump to; a file too big or not a
recording is refused with its name and why."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from pendant.eventlog import EventKind
from pendant.sim import FakeClock, SimController
from pendant.telemetry import ArmState
from pendant.telemetry.replay import ReplayError, load_replay
from tests.support.recordings import SAMPLE_PERIOD_S, recording_arm

N_SAMPLES = 30
STOP_AT = 12  # the sample after which a stop is logged
STEP_TWO_AT = 20  # the program reaches its second step
ANGLE_TOL_DEG = 1e-9  # the file's JSON holds the floats as the controller said them


def record(sim: SimController, clock: FakeClock, folder: Path) -> tuple[Path, list[list[float]]]:
    telemetry, events = recording_arm(sim, clock, folder)
    recorded = []
    for i in range(N_SAMPLES):
        clock.advance(SAMPLE_PERIOD_S)
        if i == STOP_AT:
            events.record(EventKind.COMMAND, "operator", "PUT /freeze -> 200")
        program = (1, "Move J to P1 @ 20%", "running") if i < STEP_TWO_AT else (2, "Set DO1 HIGH", "running")
        motors = telemetry.sample(ArmState(sim.get_position(), program=program))
        assert motors is not None
        recorded.append([m.angle for m in motors])
    telemetry.stop_recording()
    [recording] = telemetry.recordings()
    return next(f for f in recording.files if f.suffix == ".mcap"), recorded


def test_the_replay_holds_the_recorded_joints_events_and_steps(
    sim: SimController, clock: FakeClock, tmp_path: Path
) -> None:
    path, recorded = record(sim, clock, tmp_path)
    replay = load_replay(path)
    assert len(replay.times_s) == N_SAMPLES
    assert replay.duration_s == pytest.approx((N_SAMPLES - 1) * SAMPLE_PERIOD_S)
    assert recorded[5] != recorded[25], "the arm moved while recording"
    for i in (0, 5, 25):
        t = i * SAMPLE_PERIOD_S
        np.testing.assert_allclose(np.degrees(replay.q_at(t + SAMPLE_PERIOD_S / 2)), recorded[i], atol=1e-9)
    step = replay.step_at(STEP_TWO_AT * SAMPLE_PERIOD_S - SAMPLE_PERIOD_S / 2)
    assert step is not None and (step.line, step.step) == (1, "Move J to P1 @ 20%")
    step = replay.step_at(STEP_TWO_AT * SAMPLE_PERIOD_S)
    assert step is not None and (step.line, step.step) == (2, "Set DO1 HIGH")
    [stop] = [event for event in replay.events if event.notable]
    assert "PUT /freeze" in stop.message and stop.who == "operator"
    assert stop.t_s == pytest.approx(STOP_AT * SAMPLE_PERIOD_S, abs=SAMPLE_PERIOD_S)
    assert replay.events_until(stop.t_s - 1e-3, 5) == []
    assert replay.events_until(replay.duration_s, 5) == [stop]


def test_a_file_too_big_or_not_a_recording_is_refused(
    sim: SimController, clock: FakeClock, tmp_path: Path
) -> None:
    path, _ = record(sim, clock, tmp_path)
    with pytest.raises(ReplayError, match=rf"{path.name} is .* MB: replay reads at most"):
        load_replay(path, max_bytes=path.stat().st_size - 1)
    garbage = tmp_path / "pendant-20260101-000000.mcap"
    garbage.write_bytes(b"not an mcap file at all" * 10)
    with pytest.raises(ReplayError, match=r"pendant-20260101-000000\.mcap cannot be read"):
        load_replay(garbage)
