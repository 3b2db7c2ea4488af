"""A fresh pendant scraped every second by a real Prometheus (Debian's binary) with the site's files from
deploy/: after one accepted and one refused command, every panel of the Grafana dashboard and every alert
shows what happened. rate() and increase() need a sample before an event: a counter series born with its
first event would leave "Commands per second" and "Refusals per second" empty."""

from __future__ import annotations

import time
from collections.abc import Callable

import httpx
import pytest

from pendant.monitoring.fleet import Site, Timings, query, running_fleet
from tests.support.metrics import alert_expressions, dashboard_panels, watched
from tests.support.waiting import SAFETY_NET_S

FAST = Timings(scrape_interval="1s", alert_for="2s", group_wait="1s")
SETTLE_S = 60.0  # a generous bound for a loaded 2-core machine; typically a few seconds
REACHABLE_POSE = [10.0, -90.0, 90.0, -90.0, -90.0, 0.0]
UNREACHABLE_POSE = [0.0, 0.0, 0.0, 0.0, 0.0, 400.0]  # refused by the controller: 412, a motion failure

pytestmark = pytest.mark.slow  # real Prometheus, Alertmanager and pendant processes

Result = list[dict[str, object]]


def by(result: Result, label: str) -> dict[str, float]:
    return {str(r["metric"].get(label, "")): float(r["value"][1]) for r in result}  # type: ignore[attr-defined,index]


def one(result: Result) -> float:
    assert len(result) == 1, result
    return float(result[0]["value"][1])  # type: ignore[index]


def joints_at(pose: list[float]) -> Callable[[Result], bool]:
    def check(result: Result) -> bool:
        angles = by(result, "joint")
        return len(angles) == 6 and all(abs(angles[f"J{i + 1}"] - a) < 0.5 for i, a in enumerate(pose))

    return check


def six_above(low: float, high: float) -> Callable[[Result], bool]:
    return lambda r: len(r) == 6 and all(low < v < high for v in by(r, "joint").values())


# What each panel reads once the arm has made one move (200) and refused one (412), no page open (--no-ui).
PANELS: dict[str, Callable[[Result], bool]] = {
    "Pendants up": lambda r: one(r) == 1.0,
    "Controllers answering": lambda r: one(r) == 1.0,
    "Arms in an alarm state": lambda r: one(r) == 0.0,  # a healthy arm; an alarm is checked below
    "Hottest stator per arm": lambda r: 10.0 < one(r) < 80.0,
    "Motion failures, last hour, per arm": lambda r: one(r) >= 1.0,
    "Motion state": lambda r: by(r, "state") == {"IDLE": 1.0},
    "Viewers connected": lambda r: one(r) == 0.0,  # no page served
    "Controller latency": lambda r: 0.0 < one(r) < 5.0,
    "Joint angles": joints_at(REACHABLE_POSE),
    "Motor currents (RMS)": lambda r: len(r) == 6 and any(v > 0 for v in by(r, "joint").values()),
    "Stator temperatures": six_above(10.0, 80.0),
    "Servo temperatures": six_above(10.0, 80.0),
    "Commands per second": lambda r: by(r, "source").keys() >= {"api"} and by(r, "source")["api"] > 0,
    "Refusals per second": lambda r: {s for s, v in by(r, "status").items() if v > 0} == {"412"},
    "Motion failures": lambda r: (
        {s for s, v in by(r, "source").items() if v > 0} == {"api"} and by(r, "source")["api"] >= 1.0
    ),
}
# What each alert watches, its threshold removed: on a healthy arm, none fires.
ALERTS: dict[str, Callable[[Result], bool]] = {
    "PulseOvertemperature": lambda r: 10.0 < one(r) < 80.0,
    "PulseControllerOffline": lambda r: one(r) == 1.0,
    "PulseRepeatedMotionFailures": lambda r: 1.0 <= one(r) < 3.0,
    "PulsePendantDown": lambda r: one(r) == 1.0,
}


def present(expected: Callable[[Result], bool]) -> Callable[[Result], bool]:
    """Some result, and the expected one."""
    return lambda result: bool(result) and expected(result)


def settle(site: Site, expr: str, expected: Callable[[Result], bool], what: str) -> None:
    deadline = time.monotonic() + SETTLE_S
    while not expected(result := query(site.prometheus, expr)):
        if time.monotonic() > deadline:
            raise AssertionError(f"{what}: {expr} still reads {result!r} after {SETTLE_S:g} s")
        time.sleep(0.5)


def test_the_first_command_and_refusal_show_on_every_panel_and_alert() -> None:
    panels, alerts = dashboard_panels(), alert_expressions()
    assert set(PANELS) == set(panels), "a panel without an expected value here"
    assert set(ALERTS) == set(alerts), "an alert without an expected value here"
    with running_fleet(1, timings=FAST) as site:
        api = site.pendant_apis[0]
        # Two scrapes of the fresh pendant before anything happens: Prometheus has seen every counter at 0.
        settle(
            site, "count_over_time(pendant_uptime_seconds[1m])", lambda r: bool(r) and one(r) >= 2, "scrapes"
        )
        moved = httpx.put(f"{api}/pose?speed=50", json={"angles": REACHABLE_POSE}, timeout=30)
        assert moved.status_code == 200, moved.text
        refused = httpx.put(f"{api}/pose?speed=50", json={"angles": UNREACHABLE_POSE}, timeout=30)
        assert refused.status_code == 412, refused.text
        for title, expected in PANELS.items():
            settle(site, panels[title], present(expected), title)
        for name, expected in ALERTS.items():
            settle(site, watched(alerts[name]), present(expected), name)
            assert query(site.prometheus, alerts[name]) == [], f"{name} fires on a healthy arm"

        # An alarm: the panel that counts arms in one reads 1.
        assert httpx.put(f"{api}/sim/fault/error", timeout=SAFETY_NET_S).status_code == 200
        settle(site, panels["Arms in an alarm state"], lambda r: bool(r) and one(r) == 1.0, "an arm in ERROR")
