"""A stop wins until the operator lets go: every stop source ends the held jog for good (issue 22).

A real SimController on a fake clock; the page's confirmations are `hold` calls every 50 ms. After a stop,
the button stays down (confirmations keep coming) and the arm must stay still; release, then a new press,
moves again.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from pendant.cell.collision_names import name_collision
from pendant.cell.geometry import CellAwareArm, CellModel
from pendant.controller import MotionParams, MotionStatus, Point, Pose, Position, Rotation, SignalLevel
from pendant.controller.cell_types import BoxObstacle
from pendant.controller.stops import StopBus
from pendant.eventlog import EventLog
from pendant.jog import DEADMAN_TIMEOUT_S, JogFrame, Jogger, JogRequest
from pendant.jog.latch import MSG_STOPPED_OUTSIDE, SEND_SETTLE_S
from pendant.jog.targets import JOG_HORIZON_S
from pendant.sim import FakeClock, SimController
from pendant.ui.page.activity import LoggedJogger
from pendant.ui.page.roles import ControlDesk

CONFIRM_PERIOD_S = 0.05  # the page confirms at 20 Hz while the button is held
STILL_TOL_DEG = 1e-6  # the simulator is exact: a stopped arm does not move at all
MOVED_DEG = 0.5  # a jog that goes on moves J1 by more than this in the held time
J1_PLUS = JogRequest(JogFrame.JOINT, 0, +1, speed_percent=20)
BROWSER, OTHER_BROWSER = 1, 2


def j1(sim: SimController) -> float:
    return float(sim.get_pose().angles[0])


def confirm(jogger: Jogger, clock: FakeClock, seconds: float, holder: object = BROWSER) -> list[bool]:
    """The button held for `seconds`: a confirmation every CONFIRM_PERIOD_S, the deadman watched."""
    answers = []
    for _ in range(round(seconds / CONFIRM_PERIOD_S)):
        answers.append(jogger.hold(J1_PLUS, jogger.releases, holder))
        clock.advance(CONFIRM_PERIOD_S)
        jogger.check_deadman()
    return answers


def still_while_held(jogger: Jogger, sim: SimController, clock: FakeClock, seconds: float = 1.5) -> None:
    stopped_at = j1(sim)
    assert not any(confirm(jogger, clock, seconds)), "a confirmation after the stop was taken"
    assert abs(j1(sim) - stopped_at) < STILL_TOL_DEG, "a confirmation after the stop restarted the arm"


def moves_after_release_and_press(jogger: Jogger, sim: SimController, clock: FakeClock) -> None:
    jogger.release("released")  # the page's click on release
    before = j1(sim)
    confirm(jogger, clock, 0.5)
    assert j1(sim) > before + MOVED_DEG, "a new press after the release did not jog"


@pytest.fixture
def stops() -> StopBus:
    return StopBus()


@pytest.fixture
def jogger(sim: SimController, clock: FakeClock, stops: StopBus) -> Jogger:
    return Jogger(sim, sim.arm, clock=clock.now, stops=stops)


def test_a_freeze_from_a_page_or_the_api_ends_the_held_jog_until_release(
    sim: SimController, clock: FakeClock, stops: StopBus, jogger: Jogger
) -> None:
    start = j1(sim)
    confirm(jogger, clock, 0.5)
    assert j1(sim) > start + MOVED_DEG
    stops.notify("Freeze by browser #2")  # the page's Freeze / Esc, or PUT /freeze: told, then sent
    sim.freeze()
    still_while_held(jogger, sim, clock)
    assert jogger.latch_cause(BROWSER) == "Freeze by browser #2"
    moves_after_release_and_press(jogger, sim, clock)


def test_a_confirmation_read_before_the_stop_and_handled_after_it_cannot_restart(
    sim: SimController, clock: FakeClock, stops: StopBus, jogger: Jogger
) -> None:
    confirm(jogger, clock, 0.3)
    count = jogger.releases  # read on viser's loop, before the stop
    stops.notify("Freeze from the API (127.0.0.1)")
    sim.freeze()
    assert not jogger.hold(J1_PLUS, count, BROWSER)
    assert sim.get_motion_status() is MotionStatus.IDLE


def test_a_protective_stop_holds_until_recover_and_the_jog_until_release(
    sim: SimController, clock: FakeClock, stops: StopBus, jogger: Jogger
) -> None:
    confirm(jogger, clock, 0.3)
    stops.notify("Protective stop from the API (127.0.0.1)")
    sim.stop()
    still_while_held(jogger, sim, clock)
    sim.freeze()  # Freeze does not leave a protective stop
    assert sim.get_motion_status() is MotionStatus.ERROR
    assert sim.recover().value == "SUCCESS"
    still_while_held(jogger, sim, clock)  # recovered, but the button was never let go
    moves_after_release_and_press(jogger, sim, clock)


def test_the_deadman_stop_holds_when_confirmations_come_back(
    sim: SimController, clock: FakeClock, jogger: Jogger
) -> None:
    confirm(jogger, clock, 0.3)
    clock.advance(DEADMAN_TIMEOUT_S * 2)  # the page hung
    assert jogger.check_deadman()
    assert (jogger.latch_cause(BROWSER) or "").startswith("deadman")
    still_while_held(jogger, sim, clock)  # it runs again, the button still down: no restart
    moves_after_release_and_press(jogger, sim, clock)


def test_a_confirmation_heard_on_arrival_keeps_only_the_running_jog_alive(
    sim: SimController, clock: FakeClock, jogger: Jogger
) -> None:
    # viser's loop hears each confirmation (still_held) before a worker thread asks the controller (hold):
    # with the workers late (many browsers), the arrivals alone keep the operator's running jog alive...
    confirm(jogger, clock, 0.3)
    for _ in range(10):  # 0.5 s, more than twice the deadman
        jogger.still_held(jogger.releases, BROWSER)
        clock.advance(CONFIRM_PERIOD_S)
        assert not jogger.check_deadman()
    # ...but not another browser's, and never after a stop: nothing moves again until a new press.
    for _ in range(5):
        jogger.still_held(jogger.releases, OTHER_BROWSER)
        clock.advance(CONFIRM_PERIOD_S)
    assert jogger.check_deadman()
    stopped_at = j1(sim)
    for _ in range(10):
        jogger.still_held(jogger.releases, BROWSER)
        clock.advance(CONFIRM_PERIOD_S)
        jogger.check_deadman()
    assert abs(j1(sim) - stopped_at) < STILL_TOL_DEG
    assert (jogger.latch_cause(BROWSER) or "").startswith("deadman")
    moves_after_release_and_press(jogger, sim, clock)


API_STOPS = ["Freeze from the API (127.0.0.1)", "Protective stop from the API (127.0.0.1)"]


@pytest.mark.parametrize("stop", API_STOPS)
def test_an_api_stop_amid_confirmations_holds_until_the_operator_acts(
    sim: SimController, clock: FakeClock, stops: StopBus, jogger: Jogger, stop: str
) -> None:
    # PUT /freeze or POST /stop while J1+ is held: the arrivals heard on viser's loop (still_held) and the
    # workers' holds that follow keep coming, and the arm stays still until release and a new press (after
    # Recover, for a protective stop).
    confirm(jogger, clock, 0.3)
    count = jogger.releases  # an arrival read before the stop, handled after it
    stops.notify(stop)
    sim.stop() if stop.startswith("Protective") else sim.freeze()
    stopped_at = j1(sim)
    for _ in range(20):
        jogger.still_held(count, BROWSER)
        jogger.still_held(jogger.releases, BROWSER)
        assert not jogger.hold(J1_PLUS, jogger.releases, BROWSER)
        clock.advance(CONFIRM_PERIOD_S)
        jogger.check_deadman()
    assert abs(j1(sim) - stopped_at) < STILL_TOL_DEG
    assert jogger.latch_cause(BROWSER) == stop
    if stop.startswith("Protective"):
        assert sim.get_motion_status() is MotionStatus.ERROR  # still stopped: only Recover leaves it
        assert sim.recover().value == "SUCCESS"
    moves_after_release_and_press(jogger, sim, clock)


@pytest.mark.parametrize("how", ["freeze", "input"])
def test_a_stop_the_pendant_did_not_hear_of_is_seen_and_holds(
    sim: SimController, clock: FakeClock, how: str
) -> None:
    jogger = Jogger(sim, sim.arm, clock=clock.now)  # no bus: a real controller's own stops
    confirm(jogger, clock, 0.5)
    if how == "freeze":
        sim.freeze()  # another client of the controller
        cause = MSG_STOPPED_OUTSIDE
    else:
        sim.bind_stop(1, SignalLevel.HIGH)
        sim.set_input(1, SignalLevel.HIGH)  # a light curtain wired to the control box
        cause = "the controller stopped it (ERROR)"
    still_while_held(jogger, sim, clock)
    assert jogger.latch_cause(BROWSER) == cause


def test_a_jog_held_past_its_horizon_goes_on(sim: SimController, clock: FakeClock, jogger: Jogger) -> None:
    """The end of a continuous jog's plan is not a stop: the next piece follows while the button is held."""
    start = j1(sim)
    confirm(jogger, clock, JOG_HORIZON_S * 1.5)
    assert jogger.latch_cause(BROWSER) is None
    assert sim.get_motion_status() is MotionStatus.RUNNING
    moved = j1(sim) - start
    speed_deg_s = moved / (JOG_HORIZON_S * 1.5)
    assert moved > speed_deg_s * JOG_HORIZON_S * 1.2  # well past where the first piece ended


def test_another_browsers_press_is_not_held_by_this_ones_stop(
    sim: SimController, clock: FakeClock, stops: StopBus, jogger: Jogger
) -> None:
    confirm(jogger, clock, 0.3)
    stops.notify("Freeze by browser #2")
    sim.freeze()
    before = j1(sim)
    confirm(jogger, clock, 0.5, holder=OTHER_BROWSER)
    assert j1(sim) > before + MOVED_DEG


def test_a_stop_while_nothing_is_held_does_not_hold_the_next_press(
    sim: SimController, clock: FakeClock, stops: StopBus, jogger: Jogger
) -> None:
    stops.notify("Freeze by browser #1")
    sim.freeze()
    clock.advance(1.0)
    before = j1(sim)
    confirm(jogger, clock, 0.5)
    assert j1(sim) > before + MOVED_DEG


class LaggingLink:
    """A controller behind a link (proxy mode): GET /status/motion says IDLE for a while after a send."""

    def __init__(self, sim: SimController, clock: FakeClock, lag_s: float) -> None:
        self._sim, self._clock, self._lag_s = sim, clock, lag_s
        self.sent_at = -math.inf
        self.sends = 0

    def __getattr__(self, name: str) -> Any:  # the simulator's: a Controller to the type checker
        return getattr(self._sim, name)

    def set_pose(self, pose: Pose, params: MotionParams) -> None:
        self.sends += 1
        self.sent_at = self._clock.now()
        self._sim.set_pose(pose, params)

    def get_motion_status(self) -> MotionStatus:
        if self._clock.now() - self.sent_at < self._lag_s:
            return MotionStatus.IDLE
        return self._sim.get_motion_status()


def test_a_motion_status_that_lags_the_send_is_neither_a_stop_nor_a_reason_to_send_again(
    sim: SimController, clock: FakeClock
) -> None:
    link = LaggingLink(sim, clock, lag_s=SEND_SETTLE_S * 0.8)
    jogger = Jogger(link, sim.arm, clock=clock.now)
    before = j1(sim)
    confirm(jogger, clock, 1.0)
    assert jogger.latch_cause(BROWSER) is None
    assert link.sends == 1
    assert j1(sim) > before + MOVED_DEG


def box_at(name: str, xyz: tuple[float, float, float]) -> BoxObstacle:
    return BoxObstacle(
        obstacleType="BOX",
        name=name,
        sides=Point(x=0.1, y=0.1, z=0.1),
        centerPosition=Position(
            point=Point(x=xyz[0], y=xyz[1], z=xyz[2]), rotation=Rotation(roll=0, pitch=0, yaw=0)
        ),
    )


def test_a_jog_into_an_obstacle_stops_and_the_event_log_names_it(
    sim: SimController, clock: FakeClock
) -> None:
    # Where the flange gets to with J1 turned 20 degrees from home: the jog runs into it.
    obstacle = box_at("Box 1", (-0.397, -0.273, 0.485))
    sim.add_obstacle(obstacle)
    cell = CellModel(sim.arm, sim.get_obstacles(), sim.get_tool_shape(), sim.get_tool())
    events = EventLog()
    jogger = LoggedJogger(
        sim,
        CellAwareArm(sim.arm, lambda: cell),
        events=events,
        desk=ControlDesk(events),
        touching=cell.touching,
        clock=clock.now,
    )
    start = j1(sim)
    answers = confirm(jogger, clock, 6.0)
    assert answers[0] and not answers[-1], "the jog never stopped at the box"
    assert MOVED_DEG < j1(sim) - start < 20.0  # stopped short of the box, not at the end of the plan
    assert jogger.latch_cause(BROWSER) == "Collision detected: the arm would touch 'Box 1'"
    # The Target tab's check of the pose the jog was heading for says the very same words.
    ahead = np.radians(sim.get_pose().angles) + np.radians([20.0 - (j1(sim) - start), 0, 0, 0, 0, 0])
    assert name_collision(sim.arm, ahead, cell).reason == jogger.latch_cause(BROWSER)
    messages = [event.message for event in events.recent()]
    assert "Jog J1+ stopped: Collision detected: the arm would touch 'Box 1'" in messages
    assert not any("deadman" in message for message in messages)
