"""Commands on /metrics by endpoint and answer, on a real `pendant --no-ui`."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import httpx

from pendant.controller.operations import OPERATIONS
from tests.support.launchers import running_pendant
from tests.support.metrics import Samples, scrape, values
from tests.support.waiting import SAFETY_NET_S

REACHABLE_POSE = {"angles": [10.0, -90.0, 90.0, -90.0, -90.0, 0.0]}


def put(base_url: str, path: str, **kwargs: Any) -> int:  # httpx.put's keywords (json=, content=)
    return httpx.put(f"{base_url}{path}", timeout=SAFETY_NET_S, **kwargs).status_code


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
        if labels["source"] == "api" and value > 0
    }
    assert counts == {
        ("PUT /pose", "200"): 1.0,
        ("PUT /pose", "400"): 1.0,
        ("PUT /pose", "401"): 1.0,
        ("PUT /signal/output/{port}/high", "200"): 1.0,
    }
    refused = {
        (labels["endpoint"], labels["status"])
        for labels, value in samples["pendant_command_refusals_total"]
        if value > 0
    }
    assert refused == {("PUT /pose", "400"), ("PUT /pose", "401")}
    assert values(samples, "pendant_motion_failures_total") == [0.0, 0.0, 0.0, 0.0], (
        "a malformed or unauthorised move is no motion failure (each source counted from 0)"
    )
    assert values(samples, "pulse_digital_output")[0] == 1.0, "DO1 went HIGH"


def series(samples: Samples, name: str) -> dict[tuple[str, str, str], float]:
    return {
        (labels["source"], labels["endpoint"], labels["status"]): value for labels, value in samples[name]
    }


def test_every_command_series_exists_at_zero_before_the_first_command(tmp_path: Path) -> None:
    """rate() and increase() need a sample before the first event: a fresh pendant shows every operation of
    the table, and the pendant's own routes, at 0 for every answer."""
    with running_pendant("--data", str(tmp_path)) as base:
        samples = scrape(base)
        commands = series(samples, "pendant_commands_total")
        refusals = series(samples, "pendant_command_refusals_total")
    kinds = {labels["kind"] for labels, _ in samples["pendant_events_total"]}
    assert kinds == {"state", "error", "command", "refused", "control"}, "each event kind, from 0"
    for op in OPERATIONS:
        if op.method == "GET":
            continue
        endpoint = f"{op.method} {op.path}"
        for status in ("200", "400", "401", "403", "409", "412", "500", "503"):
            assert commands.get(("api", endpoint, status)) == 0.0, (endpoint, status)
        assert refusals.get(("api", endpoint, "400")) == 0.0, endpoint
    assert commands.get(("api", "POST /pendant/plan", "200")) == 0.0, "the pendant's own routes too"
    assert ("api", "PUT /pose", "200") not in refusals, "an accepted answer is no refusal"


def test_obstacle_names_make_no_new_series(tmp_path: Path) -> None:
    """100 distinct `DELETE /environment/<name>`: counted under the route template, the series unchanged."""
    with running_pendant("--data", str(tmp_path)) as base:
        before = series(scrape(base), "pendant_commands_total")
        statuses = {
            httpx.delete(f"{base}/environment/box-{i}", timeout=SAFETY_NET_S).status_code for i in range(100)
        }
        httpx.put(f"{base}/no/such/{'x' * 40}", timeout=SAFETY_NET_S)
        after = series(scrape(base), "pendant_commands_total")
    assert len(statuses) == 1, statuses
    assert set(after) == set(before), f"new series: {set(after) - set(before)}"
    assert after[("api", "DELETE /environment/{obstacle}", str(statuses.pop()))] == 100.0
    assert after[("api", "other", "404")] == 1.0, "a path of no route is counted as other"
