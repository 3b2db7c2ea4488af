"""GET /metrics on the proxy in front of a real controller (here the simulator's API over real HTTP): the
arm's readings come through the link, commands are counted, and the link's death shows as the offline
alert's inputs (the alert itself: deploy/prometheus, checked by promtool and tests/monitoring/test_fleet)."""

from __future__ import annotations

import contextlib

import httpx

from pendant.api import create_app
from pendant.config import Settings
from pendant.remote import RemoteController, create_proxy_app
from pendant.sim import SimController
from tests.support.metrics import scrape, values
from tests.support.threads import serve_in_thread

CONNECT_TIMEOUT_S = 0.5
READ_TIMEOUT_S = 1.0


def test_proxy_serves_the_arm_counts_commands_and_reports_the_link_down(sim: SimController) -> None:
    with contextlib.ExitStack() as controller_server, contextlib.ExitStack() as pendant:
        controller_url = controller_server.enter_context(serve_in_thread(create_app(sim)))
        remote = RemoteController(
            controller_url, connect_timeout=CONNECT_TIMEOUT_S, read_timeout=READ_TIMEOUT_S
        )
        pendant.callback(remote.close)
        settings = Settings(
            robot_url=controller_url, connect_timeout=CONNECT_TIMEOUT_S, read_timeout=READ_TIMEOUT_S
        )
        base = pendant.enter_context(
            serve_in_thread(create_proxy_app(controller_url, settings=settings, controller=remote))
        )
        baseline = scrape(base)
        assert values(baseline, "pulse_controller_online") == [1.0]
        info = baseline["pendant_info"][0][0]
        assert info["mode"] == "robot" and info["robot_url"] == controller_url
        assert httpx.put(f"{base}/signal/output/2/high", timeout=30.0).status_code == 200
        after = scrape(base)
        assert [labels["port"] for labels, v in after["pulse_digital_output"] if v == 1.0] == ["2"]
        command = {"source": "api", "endpoint": "PUT /signal/output/{port}/high", "status": "200"}
        assert (command, 1.0) in after["pendant_commands_total"]
        assert values(after, "pulse_controller_responding") == [1.0]

        controller_server.close()  # the controller goes away; the pendant stays
        offline = scrape(base)
    assert values(offline, "pulse_controller_online") == [0.0]
    assert "pulse_joint_angle_degrees" not in offline, "no stale readings of an arm nobody can reach"
    assert values(offline, "pulse_controller_responding") == [], "unknown while the link is down"
