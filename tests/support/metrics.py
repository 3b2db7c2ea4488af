"""Scrape /metrics and read it with prometheus_client's own parser; the site's PromQL from deploy/: the
Grafana dashboard's panels and queries, the alert rules."""

from __future__ import annotations

import json
import re

import httpx
import yaml
from prometheus_client.parser import text_string_to_metric_families

from pendant.paths import deploy_dir
from tests.support.waiting import SAFETY_NET_S

Samples = dict[str, list[tuple[dict[str, str], float]]]


def scrape(base_url: str) -> Samples:
    answer = httpx.get(f"{base_url}/metrics", timeout=SAFETY_NET_S)
    assert answer.status_code == 200, answer.text
    assert answer.headers["content-type"].startswith("text/plain; version=")
    samples: Samples = {}
    for family in text_string_to_metric_families(answer.text):
        for sample in family.samples:
            samples.setdefault(sample.name, []).append((sample.labels, sample.value))
    return samples


def values(samples: Samples, name: str) -> list[float]:
    return [value for _, value in samples.get(name, [])]


def dashboard_queries() -> list[str]:
    """Every PromQL query of the Grafana dashboard, with its arm variable set to all arms."""
    dashboard = json.loads((deploy_dir() / "grafana" / "pulse-dashboard.json").read_text())
    return [
        target["expr"].replace("$instance", ".*")
        for panel in dashboard["panels"]
        for target in panel.get("targets", [])
    ]


# An alert's threshold (`> 80`, `== 0`, `>= 3`): what is left is the quantity the alert watches.
_THRESHOLD = re.compile(r"\s*(==|!=|>=|<=|>|<)\s*-?[0-9.]+")


def dashboard_panels() -> dict[str, str]:
    """Each Grafana panel's title and query, its arm variable set to all arms."""
    dashboard = json.loads((deploy_dir() / "grafana" / "pulse-dashboard.json").read_text())
    return {
        panel["title"]: target["expr"].replace("$instance", ".*")
        for panel in dashboard["panels"]
        for target in panel.get("targets", [])
    }


def alert_expressions() -> dict[str, str]:
    """Each alert rule's name and expression (deploy/prometheus/pulse-alerts.yml)."""
    rules = yaml.safe_load((deploy_dir() / "prometheus" / "pulse-alerts.yml").read_text())
    return {rule["alert"]: rule["expr"] for group in rules["groups"] for rule in group["rules"]}


def watched(expr: str) -> str:
    """An alert's expression without its thresholds: `max(x) > 80` watches `max(x)`."""
    return _THRESHOLD.sub("", expr)
