"""Scrape /metrics with prometheus_client's parser, and evaluate the alert rules of docs/monitoring.md on
the samples.

Only the three expression shapes that page uses are understood (anything else fails the test, so a rule
edited into a shape this cannot judge is noticed); `increase(...[10m])` is the growth since a baseline scrape
taken at the start of the test (well inside ten minutes).
"""

from __future__ import annotations

import re
from pathlib import Path

import httpx
from prometheus_client.parser import text_string_to_metric_families

RULES_PAGE = Path(__file__).resolve().parents[2] / "docs" / "monitoring.md"

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


def readme_rules() -> dict[str, str]:
    """alert name -> expr, from the pulse-alerts.yml block of docs/monitoring.md."""
    rules = dict(re.findall(r"- alert: (\w+)\n\s+expr: (.+)", RULES_PAGE.read_text()))
    assert len(rules) == 3, rules
    return rules


def fires(expr: str, now: Samples, baseline: Samples) -> bool:
    """Does the rule's condition hold on these samples (ignoring `for:`)?"""
    if m := re.fullmatch(r"max by \(instance\) \((\w+)\) > ([\d.]+)", expr):
        return max(values(now, m[1]), default=float("-inf")) > float(m[2])
    if m := re.fullmatch(r"(\w+) == 0 or (\w+) == 0", expr):
        return any(value == 0 for name in (m[1], m[2]) for value in values(now, name))
    if m := re.fullmatch(r"sum by \(instance\) \(increase\((\w+)\[10m\]\)\) >= (\d+)", expr):
        return sum(values(now, m[1])) - sum(values(baseline, m[1])) >= float(m[2])
    raise AssertionError(f"the test cannot evaluate {expr!r}")


def firing(now: Samples, baseline: Samples) -> set[str]:
    return {name for name, expr in readme_rules().items() if fires(expr, now, baseline)}
