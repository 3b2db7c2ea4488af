"""End to end with real processes: three simulated pendants scraped by a real Prometheus (Debian's binary)
with the site's rules from deploy/, alerting through a real Alertmanager to a webhook this test serves.
Timings are shortened in the test's own copy of the configuration (scrape every second, `for:` 2 s)."""

from __future__ import annotations

import time
from collections.abc import Callable
from functools import partial
from typing import TypeVar

import httpx
import pytest

from pendant.monitoring.fleet import Site, Timings, query, running_fleet
from tests.support.metrics import dashboard_queries
from tests.support.waiting import SAFETY_NET_S

T = TypeVar("T")
# alert_for 10 s: behind the timed pass (nice 19) a starved pendant can miss a 1 s scrape or two, and a
# real Prometheus then rightly says it is down (seen: PulsePendantDown on all three at 2 s).
FAST = Timings(scrape_interval="1s", alert_for="10s", group_wait="1s")
SETTLE_S = 60.0  # a generous bound for a loaded 2-core machine; typically a few seconds
REACHABLE_POSE = {"angles": [10.0, -90.0, 90.0, -90.0, -90.0, 0.0]}

pytestmark = pytest.mark.slow  # real Prometheus, Alertmanager and pendant processes


def eventually(probe: Callable[[], T], done: Callable[[T], bool], what: str) -> T:
    deadline = time.monotonic() + SETTLE_S
    while True:
        value = probe()
        if done(value):
            return value
        if time.monotonic() > deadline:
            raise AssertionError(f"{what}: still {value!r} after {SETTLE_S:g} s")
        time.sleep(0.5)


def instance(site: Site, index: int) -> str:
    return site.pendant_apis[index].removeprefix("http://")


def firing_at_webhook(site: Site) -> set[tuple[str, str]]:
    return {
        (str(alert["labels"]["alertname"]), str(alert["labels"]["instance"]))
        for alert in list(site.alerts)
        if alert.get("status") == "firing"
    }


def test_three_pendants_scraped_alerted_and_charted_by_the_real_tools() -> None:
    with running_fleet(3, timings=FAST) as site:
        ups = eventually(
            lambda: {
                r["metric"]["instance"]: r["value"][1] for r in query(site.prometheus, 'up{job="pulse"}')
            },
            lambda found: len(found) == 3 and set(found.values()) == {"1"},
            "every pendant up",
        )
        assert set(ups) == {instance(site, i) for i in range(3)}
        eventually(
            lambda: len(query(site.prometheus, "pulse_joint_angle_degrees")),
            lambda n: n == 18,
            "six joint series per arm",
        )

        # Something for every dashboard panel to show: a command and a refusal on each arm.
        for api in site.pendant_apis:
            assert (
                httpx.put(f"{api}/pose?speed=20", json=REACHABLE_POSE, timeout=SAFETY_NET_S).status_code
                == 200
            )
            assert (
                httpx.put(f"{api}/pose?speed=20", json={"angles": [1, 2]}, timeout=SAFETY_NET_S).status_code
                == 400
            )
        for expr in dashboard_queries():
            eventually(partial(query, site.prometheus, expr), bool, f"dashboard query {expr}")
        assert firing_at_webhook(site) == set(), "a healthy site pages nobody"

        # One fault per arm: each alert must come from its own arm and no other.
        assert (
            httpx.put(f"{site.pendant_apis[0]}/sim/fault/overheat", timeout=SAFETY_NET_S).status_code == 200
        )
        assert (
            httpx.put(f"{site.pendant_apis[1]}/sim/fault/no_response", timeout=SAFETY_NET_S).status_code
            == 200
        )
        third = site.pendant_apis[2]
        assert httpx.put(f"{third}/sim/fault/error", timeout=SAFETY_NET_S).status_code == 200
        for _ in range(3):
            assert (
                httpx.put(f"{third}/pose?speed=20", json=REACHABLE_POSE, timeout=SAFETY_NET_S).status_code
                == 500
            )
        expected = {
            ("PulseOvertemperature", instance(site, 0)),
            ("PulseControllerOffline", instance(site, 1)),
            ("PulseRepeatedMotionFailures", instance(site, 2)),
        }
        eventually(lambda: firing_at_webhook(site), lambda got: expected <= got, "each alert at the webhook")
        time.sleep(3.0)  # a few more evaluations: nothing else arrives
        assert firing_at_webhook(site) == expected
