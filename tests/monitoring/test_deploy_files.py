"""The site's monitoring files in deploy/, checked by the real tools: promtool (Debian's `prometheus`) and
Alertmanager's own configuration check; the Grafana dashboard's queries parse as PromQL."""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

from pendant.monitoring.fleet import Timings, alert_rules, alertmanager_config, prometheus_config
from pendant.paths import deploy_dir
from tests.support.metrics import dashboard_queries

PROMETHEUS = deploy_dir() / "prometheus"


def run(*command: str | Path, cwd: Path = PROMETHEUS) -> str:
    binary = shutil.which(str(command[0]))
    assert binary is not None, f"{command[0]} is not installed (.ci/run installs it with apt-get)"
    done = subprocess.run(
        [binary, *map(str, command[1:])], cwd=cwd, capture_output=True, text=True, timeout=60
    )
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout + done.stderr


def test_promtool_accepts_the_scrape_configuration_and_the_rules() -> None:
    out = run("promtool", "check", "config", "prometheus.yml")
    assert "SUCCESS: prometheus.yml is valid" in out
    assert "SUCCESS: 4 rules found" in run("promtool", "check", "rules", "pulse-alerts.yml")


def test_every_alert_has_a_promtool_unit_test_and_they_pass() -> None:
    rules = alert_rules(Timings())
    names = {rule["alert"] for group in rules["groups"] for rule in group["rules"]}
    tests = (PROMETHEUS / "pulse-alerts.test.yml").read_text()
    untested = {name for name in names if f"alertname: {name}" not in tests}
    assert not untested, f"alerts without a promtool unit test: {untested}"
    assert "SUCCESS" in run("promtool", "test", "rules", "pulse-alerts.test.yml")


def test_a_broken_rule_is_caught_by_the_unit_tests(tmp_path: Path) -> None:
    """The unit tests can fail: a threshold moved from 80 to 90 °C is noticed."""
    shutil.copy(PROMETHEUS / "pulse-alerts.test.yml", tmp_path)
    rules = (PROMETHEUS / "pulse-alerts.yml").read_text().replace("> 80", "> 90")
    (tmp_path / "pulse-alerts.yml").write_text(rules)
    binary = shutil.which("promtool")
    assert binary is not None
    done = subprocess.run(
        [binary, "test", "rules", "pulse-alerts.test.yml"], cwd=tmp_path, capture_output=True, text=True
    )
    assert done.returncode != 0 and "PulseOvertemperature" in done.stdout + done.stderr


def test_alertmanager_accepts_its_routing(tmp_path: Path) -> None:
    assert "SUCCESS" in run("amtool", "check-config", deploy_dir() / "alertmanager" / "alertmanager.yml")


def test_the_fleets_adapted_copies_still_pass_the_tools(tmp_path: Path) -> None:
    """What `make fleet` and the end-to-end test write is the deploy files with other targets and timings."""
    timings = Timings(scrape_interval="1s", alert_for="2s", group_wait="1s")
    config = prometheus_config(["127.0.0.1:1", "127.0.0.1:2"], "127.0.0.1:3", timings)
    (tmp_path / "prometheus.yml").write_text(json.dumps(config))
    (tmp_path / "pulse-alerts.yml").write_text(json.dumps(alert_rules(timings)))
    (tmp_path / "alertmanager.yml").write_text(
        json.dumps(alertmanager_config("http://127.0.0.1:4/", timings))
    )
    assert "SUCCESS" in run("promtool", "check", "config", "prometheus.yml", cwd=tmp_path)
    assert "SUCCESS" in run("amtool", "check-config", "alertmanager.yml", cwd=tmp_path)


def test_each_dashboard_query_is_valid_promql(tmp_path: Path) -> None:
    queries = dashboard_queries()
    assert len(queries) >= 15
    records = [{"record": f"dashboard:query_{i}", "expr": expr} for i, expr in enumerate(queries)]
    (tmp_path / "queries.yml").write_text(json.dumps({"groups": [{"name": "dashboard", "rules": records}]}))
    assert f"SUCCESS: {len(queries)} rules found" in run(
        "promtool", "check", "rules", "queries.yml", cwd=tmp_path
    )
