"""The Dashboard's Replay headless: a kept recording played back as a ghost arm at the slider's time, with the
events and a jump to each stop or error; replay moves nothing and anybody watching may use it. And the page's
recordings carry the arm (its /tf frames), the cell and the program, and are finished when the page stops."""

from __future__ import annotations

import time
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

from pendant.controller import MotionParams, Pose
from pendant.eventlog import EventKind, EventLog
from pendant.sim import FakeClock, SimController
from pendant.telemetry.repair import finished
from pendant.ui.app import PendantUI
from pendant.ui.dashboard.replay import JUMP_PROMPT
from pendant.ui.page.session import ClientSession
from tests.support.dashboard import MOVE, SAMPLE_PERIOD_S, sample
from tests.support.doubles import OPERATOR, VIEWER, FakeBrowser, fire
from tests.support.mcap_reading import read_mcap
from tests.support.pages import new_page
from tests.support.recordings import damaged_inside, make_recording
from tests.support.waiting import SAFETY_NET_S, wait_until

N_SAMPLES = 20
FAULT_AT = 8  # the sample after which an error is logged
ANGLE_TOL_DEG = 1e-9
PLAY_TIMEOUT_S = SAFETY_NET_S
JOB_TIMEOUT_S = SAFETY_NET_S  # a replay loads on a job thread (kit/jobs.py)


@pytest.fixture
def anchor(clock: FakeClock) -> dict[str, float]:
    """The wall time the page's events are stamped with: real time at the anchor, on by the fake clock."""
    return {"wall": time.time(), "clock": clock.now()}


@pytest.fixture
def pendant_ui(sim: SimController, clock: FakeClock, anchor: dict[str, float]) -> Iterator[PendantUI]:
    """A page whose samples and events are timed by the `clock` fixture."""
    wall = lambda: anchor["wall"] + clock.now() - anchor["clock"]  # noqa: E731
    events = EventLog(now=wall)
    page = new_page(sim, sim.arm, clock=clock.now, events=events)
    # The recording's own wall clock is the events' one: read from time.time() as the recording starts, it
    # put the error late by however long this thread waited for the CPU since the anchor (50 ms fails).
    page.telemetry._wall_now = wall
    page.desk.join(OPERATOR)
    page.desk.join(VIEWER)
    page.refresh()
    yield page
    page.stop()


def record(
    ui: ClientSession, pendant_ui: PendantUI, sim: SimController, clock: FakeClock, anchor: dict[str, float]
) -> list[list[float]]:
    """A recording of the arm moving, with an error logged part-way; the joints as sampled."""
    anchor.update(wall=time.time(), clock=clock.now())  # the recording's wall clock starts now too
    fire(ui.dashboard.record_start, FakeBrowser(OPERATOR))
    sim.set_pose(MOVE, MotionParams(speed=30.0))
    readings = sample(pendant_ui, clock, FAULT_AT)
    pendant_ui.events.record(EventKind.ERROR, "controller", "Protective stop: collision")
    readings += sample(pendant_ui, clock, N_SAMPLES - FAULT_AT)
    fire(ui.dashboard.record_stop, FakeBrowser(OPERATOR))
    return [[m.angle for m in motors] for motors in readings]


def test_the_ghost_shows_the_recorded_arm_at_the_slider_time_and_nothing_moves(
    ui: ClientSession, pendant_ui: PendantUI, sim: SimController, clock: FakeClock, anchor: dict[str, float]
) -> None:
    recorded = record(ui, pendant_ui, sim, clock, anchor)
    clock.advance(30.0)  # the live arm finishes its move and rests
    live = sim.get_pose().angles
    commands_before = [e for e in pendant_ui.events.recent() if e.kind is EventKind.COMMAND]
    replay = ui.dashboard.replay
    viewer = FakeBrowser(VIEWER)
    fire(replay.start, viewer)  # a viewer may replay: it commands nothing
    wait_until(
        lambda: replay.replay is not None or bool(viewer.notifications), JOB_TIMEOUT_S, "the replay to load"
    )
    assert replay.replay is not None and replay.ghost is not None, viewer.notifications
    assert replay.replay.duration_s == pytest.approx((N_SAMPLES - 1) * SAMPLE_PERIOD_S)
    for i in (2, 15):  # the slider's time is seconds since the first sample
        fire(replay.time, viewer, value=i * SAMPLE_PERIOD_S + SAMPLE_PERIOD_S / 2)
        assert replay.ghost.q is not None
        np.testing.assert_allclose(np.degrees(replay.ghost.q), recorded[i], atol=ANGLE_TOL_DEG)
        shown = "Protective stop" in replay.log.content
        assert shown == (i >= FAULT_AT), f"at sample {i}, the error is {'' if shown else 'not '}listed"
    assert recorded[2] != recorded[15]

    label = next(option for option in replay.jump.options if "Protective stop" in option)
    assert replay.jump.options[0] == JUMP_PROMPT
    fire(replay.jump, viewer, value=label)
    at_fault = (FAULT_AT - 1) * SAMPLE_PERIOD_S  # logged after the FAULT_AT-th sample
    assert float(replay.time.value) == pytest.approx(at_fault, abs=SAMPLE_PERIOD_S / 2)
    assert "Protective stop: collision" in replay.log.content

    fire(replay.time, viewer, value=0.0)
    fire(replay.play, viewer)
    wait_until(lambda: float(replay.time.value) > 0.3, PLAY_TIMEOUT_S, "the replay to play on")
    fire(replay.pause, viewer)
    np.testing.assert_allclose(sim.get_pose().angles, live, atol=ANGLE_TOL_DEG)
    assert [e for e in pendant_ui.events.recent() if e.kind is EventKind.COMMAND] == commands_before
    fire(replay.close_replay, viewer)
    assert replay.ghost.q is None and replay.time.disabled


def legend(ui: ClientSession) -> str:
    assert ui.ghosts.legend is not None
    return ui.ghosts.legend.content.split('data-ghost-legend="', 1)[1].split('"', 1)[0]


def test_a_replay_takes_the_view_from_the_target_and_clears_itself_when_played_to_the_end(
    ui: ClientSession, pendant_ui: PendantUI, sim: SimController, clock: FakeClock, anchor: dict[str, float]
) -> None:
    record(ui, pendant_ui, sim, clock, anchor)
    clock.advance(30.0)
    target = ui.target_panel
    assert target.set_joint_target(np.radians([20.0, -90.0, 90.0, -90.0, -90.0, 0.0])).ok
    assert legend(ui) == "Ghost: target"
    replay = ui.dashboard.replay
    operator = FakeBrowser(OPERATOR)
    fire(replay.start, operator)

    def shown() -> bool:  # the replay is set before its first frame is drawn (a moment later, under load)
        return replay.ghost is not None and replay.ghost.q is not None

    wait_until(lambda: shown() or bool(operator.notifications), JOB_TIMEOUT_S, "the replay's first frame")
    assert replay.replay is not None and replay.ghost is not None, operator.notifications
    assert replay.ghost.q is not None and target.ghost_shown is None, "one ghost: the replay's"
    assert legend(ui) == "Ghost: replay"

    fire(replay.time, operator, value=replay.replay.duration_s - 0.3)
    fire(replay.play, operator)
    wait_until(lambda: replay.ghost is not None and replay.ghost.q is None, PLAY_TIMEOUT_S, "the end")
    assert legend(ui) == "" and target.ghost_shown is None
    assert "Played to the end" in replay.status.content


def test_a_recording_still_being_written_is_not_replayed(
    ui: ClientSession, pendant_ui: PendantUI, clock: FakeClock
) -> None:
    operator = FakeBrowser(OPERATOR)
    fire(ui.dashboard.record_start, operator)
    sample(pendant_ui, clock, 3)
    fire(ui.dashboard.replay.start, operator)
    wait_until(lambda: bool(operator.notifications), JOB_TIMEOUT_S, "the refusal")
    assert ui.dashboard.replay.replay is None
    assert any("still being recorded: stop the recording first" in n for n in operator.notifications)


def test_the_page_records_the_arm_and_finishes_the_file_when_it_stops(
    ui: ClientSession, pendant_ui: PendantUI, sim: SimController, clock: FakeClock
) -> None:
    fire(ui.dashboard.record_start, FakeBrowser(OPERATOR))
    sim.set_pose(Pose(angles=[10.0, -80.0, 60.0, -90.0, -90.0, 0.0]), MotionParams(speed=30.0))
    sample(pendant_ui, clock, 5)
    path = pendant_ui.telemetry.mcap.path if pendant_ui.telemetry.mcap is not None else None
    assert path is not None and not finished(path)
    pendant_ui.stop()  # what SIGTERM and Ctrl-C lead to
    assert finished(path)
    schemas, messages = read_mcap(path)
    assert {"/tf", "/arm", "/cell"} <= set(schemas), "the page's recordings draw the arm and the cell"
    assert sum(1 for topic, _, _ in messages if topic == "/tf") == 5


@pytest.mark.parametrize("how", ["chunk-length-2^62", "chunk-declares-2^62", "chunk-garbage"])
def test_a_damaged_recording_chosen_for_replay_is_refused_with_its_name_and_why(
    ui: ClientSession, pendant_ui: PendantUI, how: str, tmp_path: Path
) -> None:
    folder = pendant_ui.telemetry.recordings_folder
    folder.mkdir(parents=True, exist_ok=True)
    real = make_recording(tmp_path, 3.0).read_bytes()
    (folder / "pendant-20270101-000000.mcap").write_bytes(damaged_inside(real, how))
    viewer = FakeBrowser(VIEWER)
    fire(ui.dashboard.replay.start, viewer)
    wait_until(lambda: bool(viewer.notifications), JOB_TIMEOUT_S, "the refusal")  # loading is a job
    assert ui.dashboard.replay.replay is None
    assert any(
        "pendant-20270101-000000.mcap cannot be read as a recording" in n for n in viewer.notifications
    ), viewer.notifications
