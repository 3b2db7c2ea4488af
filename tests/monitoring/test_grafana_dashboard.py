"""The site's Grafana dashboard (deploy/grafana) as Grafana's own foundation SDK sees it: at the schema
version the SDK writes (Grafana imports an older one through its migrations, which may change what a panel
shows), and read into the SDK's dashboard model with every panel, its kind and its queries as the file has
them."""

from __future__ import annotations

import json
from typing import Any

from grafana_foundation_sdk.builders.dashboard import Dashboard as DashboardBuilder
from grafana_foundation_sdk.cog.encoder import JSONEncoder
from grafana_foundation_sdk.models.dashboard import Dashboard

from pendant.paths import deploy_dir

DASHBOARD = deploy_dir() / "grafana" / "pulse-dashboard.json"


def _panels(dashboard: dict[str, Any]) -> list[tuple[str, str, list[str]]]:
    """Each panel (rows' own panels included, in order): its type, title and queries."""
    found = []
    for panel in dashboard["panels"]:
        for one in [panel, *panel.get("panels", [])]:
            queries = [target.get("expr", "") for target in one.get("targets", [])]
            found.append((one["type"], one["title"], queries))
    return found


def test_the_dashboard_is_at_the_schema_version_the_foundation_sdk_writes() -> None:
    written = DashboardBuilder("any").build().schema_version
    assert json.loads(DASHBOARD.read_text())["schemaVersion"] == written


def test_the_dashboard_reads_into_the_sdk_model_keeping_every_panel_and_query() -> None:
    raw = json.loads(DASHBOARD.read_text())
    model = Dashboard.from_json(raw)
    again = json.loads(json.dumps(model, cls=JSONEncoder))
    assert again["uid"] == raw["uid"] and again["title"] == raw["title"]
    assert _panels(again) == _panels(raw)
