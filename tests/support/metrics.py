"""Scrape /metrics and read it with prometheus_client's own parser; the Grafana dashboard's queries."""

from __future__ import annotations

import json

import httpx
from prometheus_client.parser import text_string_to_metric_families

from pendant.paths import deploy_dir

Samples = dict[str, list[tuple[dict[str, str], float]]]


def scrape(base_url: str) -> Samples:
    answer = httpx.get(f"{base_url}/metrics", timeout=10.0)
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
