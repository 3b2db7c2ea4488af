"""The alert rules of docs/monitoring.md, run on what a real `pendant --no-ui` serves at /metrics, with
injected faults: each fires on its own fault and on nothing else."""

from __future__ import annotations

from pathlib import Path

import httpx

from tests.support.launchers import running_pendant

from .promql import firing, scrape, values

REACHABLE_POSE = {"angles": [10.0, -90.0, 90.0, -90.0, -90.0, 0.0]}


def put(base_url: str, path: str, **kwargs: object) -> int:
    return httpx.put(f"{base_url}{path}", timeout=10.0, **kwargs).status_code  # type: ignore[arg-type]


def test_each_rule_fires_on_its_fault_only(tmp_path: Path) -> None:
    with running_pendant("--data", str(tmp_path)) as base:
        baseline = scrape(base)
        assert firing(baseline, baseline) == set()
        assert values(baseline, "pulse_controller_online") == [1.0]
        assert len(values(baseline, "pulse_joint_angle_degrees")) == 6

        assert put(base, "/sim/fault/overheat") == 200
        hot = scrape(base)
        assert firing(hot, baseline) == {"PulseOvertemperature"}
        assert min(values(hot, "pulse_motor_stator_temperature_celsius")) > 80
        assert put(base, "/sim/reset") == 200
        assert firing(scrape(base), baseline) == set(), "cool again after a reset"

        assert put(base, "/sim/fault/error") == 200
        for attempt in range(3):
            assert firing(scrape(base), baseline) == set(), f"{attempt} failures are not yet 'repeated'"
            assert put(base, "/pose?speed=20", json=REACHABLE_POSE) == 500
        failing = scrape(base)
        assert firing(failing, baseline) == {"PulseRepeatedMotionFailures"}
        assert values(failing, "pulse_motion_state").count(1.0) == 1
        assert put(base, "/sim/reset") == 200

        assert put(base, "/sim/fault/no_response") == 200
        silent = scrape(base)
        assert firing(silent, baseline) == {"PulseControllerOffline", "PulseRepeatedMotionFailures"}
        assert values(silent, "pulse_controller_responding") == [0.0]


def test_commands_are_counted_by_endpoint_and_status(tmp_path: Path) -> None:
    with running_pendant("--data", str(tmp_path), "--token", "sesame") as base:
        headers = {"X-Pendant-Token": "sesame"}
        assert put(base, "/pose?speed=20", json=REACHABLE_POSE, headers=headers) == 200
        assert put(base, "/pose?speed=20", json={"angles": [1, 2]}, headers=headers) == 400
        assert put(base, "/signal/output/1/high", headers=headers) == 200
        assert put(base, "/pose?speed=20", json=REACHABLE_POSE) == 401  # no token: refused, still counted
        samples = scrape(base)  # a read: no token needed
    counts = {
        (labels["endpoint"], labels["status"]): value
        for labels, value in samples["pendant_commands_total"]
        if labels["source"] == "api"
    }
    assert counts == {
        ("PUT /pose", "200"): 1.0,
        ("PUT /pose", "400"): 1.0,
        ("PUT /pose", "401"): 1.0,
        ("PUT /signal/output/{n}/high", "200"): 1.0,
    }
    refused = {
        (labels["endpoint"], labels["status"]) for labels, _ in samples["pendant_command_refusals_total"]
    }
    assert refused == {("PUT /pose", "400"), ("PUT /pose", "401")}
    assert values(samples, "pendant_motion_failures_total") == [], (
        "a malformed or unauthorised move is no motion failure"
    )
    assert values(samples, "pulse_digital_output")[0] == 1.0, "DO1 went HIGH"
