"""The simulator's cell, tool and base outlive the pendant, as programs do: real `pendant` processes on one
data folder, stopped with SIGTERM and started again; `--fresh-cell` starts empty; a damaged cell file is
moved aside with a message and the pendant serves."""

from __future__ import annotations

from pathlib import Path

import httpx

from tests.support.launchers import running_pendant
from tests.support.waiting import SAFETY_NET_S

ROTATION = {"roll": 0.0, "pitch": 0.0, "yaw": 0.0}
BOX = {
    "obstacleType": "BOX",
    "name": "table",
    "sides": {"x": 0.8, "y": 1.2, "z": 0.05},
    "centerPosition": {"point": {"x": 0.5, "y": 0.0, "z": -0.03}, "rotation": ROTATION},
}
TOOL = {"name": "gripper", "point": {"x": 0.0, "y": 0.0, "z": 0.1}, "rotation": ROTATION, "radius": 0.02}
BASE = {"point": {"x": 0.1, "y": 0.0, "z": 0.0}, "rotation": ROTATION}


def cell(base: str) -> tuple[list[str], dict[str, object], dict[str, object]]:
    obstacles = [o["name"] for o in httpx.get(f"{base}/environment", timeout=SAFETY_NET_S).json()]
    return (
        obstacles,
        httpx.get(f"{base}/tool", timeout=SAFETY_NET_S).json(),
        httpx.get(f"{base}/base", timeout=SAFETY_NET_S).json(),
    )


def test_the_cell_tool_and_base_are_there_after_a_restart(tmp_path: Path) -> None:
    data = ("--data", str(tmp_path))
    with running_pendant(*data) as base:
        before = cell(base)
        assert before[0] == []
        assert httpx.put(f"{base}/environment", json=BOX, timeout=SAFETY_NET_S).status_code == 200
        assert httpx.post(f"{base}/tool", json=TOOL, timeout=SAFETY_NET_S).status_code == 200
        assert httpx.post(f"{base}/base", json=BASE, timeout=SAFETY_NET_S).status_code == 200
        changed = cell(base)
    with running_pendant(*data) as base:  # the first one got SIGTERM
        assert cell(base) == changed
        assert changed[0] == ["table"] and changed[1]["name"] == "gripper"
    with running_pendant(*data, "--fresh-cell") as base:
        assert cell(base) == before, "--fresh-cell: no obstacle, the default tool and base"


def test_a_damaged_cell_file_is_moved_aside_and_the_pendant_serves(tmp_path: Path) -> None:
    damaged = b'{"schema_version": 1, "obstacles": [{"obstacleType": "BOX", "na'
    (tmp_path / "sim-cell.json").write_bytes(damaged)
    with running_pendant("--data", str(tmp_path)) as base:
        assert httpx.get(f"{base}/environment", timeout=SAFETY_NET_S).json() == []
        errors = httpx.get(f"{base}/pendant/events?kind=error", timeout=SAFETY_NET_S).json()
        assert httpx.put(f"{base}/environment", json=BOX, timeout=SAFETY_NET_S).status_code == 200
    [aside] = tmp_path.glob("sim-cell.json.damaged-*")
    assert aside.read_bytes() == damaged, "the damaged file is kept as it was"
    said = " ".join(event["message"] for event in errors["events"])
    assert f"moved aside to {aside.name}" in said and "not a cell file" in said, errors
    assert "table" in (tmp_path / "sim-cell.json").read_text(), "a new cell is kept from then on"
