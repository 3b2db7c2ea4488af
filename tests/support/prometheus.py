"""The site's PromQL, read from deploy/: the Grafana dashboard's panels and the alert rules."""

from __future__ import annotations

import json
import re

import yaml

from pendant.paths import deploy_dir

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
