"""Commands on /metrics by endpoint and answer, on a real `pendant --no-ui`."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import httpx

from tests.support.launchers import running_pendant
from tests.support.metrics import scrape, values

REACHABLE_POSE = {"angles": [10.0, -90.0, 90.0, -90.0, -90.0, 0.0]}


def put(base_url: str, path: str, **kwargs: Any) -> int:  # httpx.put's keywords (json=, content=)
    return httpx.put(f"{base_url}{path}", timeout=10.0, **kwargs).status_code


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
    assert values(samples, "pendant_motion_failures_total") == [0.0, 0.0, 0.0, 0.0], (
        "a malformed or unauthorised move is no motion failure (each source counted from 0)"
    )
    assert values(samples, "pulse_digital_output")[0] == 1.0, "DO1 went HIGH"
