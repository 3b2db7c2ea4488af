"""Absurd but well-formed numbers: refused or absorbed, never an arm that can no longer be read."""

from __future__ import annotations

import pytest
from fastapi.testclient import TestClient

HUGE = 1.7e308
ROTATION = {"roll": 0.3, "pitch": 0.2, "yaw": 0.0}
HUGE_POINT = {"x": HUGE, "y": HUGE, "z": HUGE}


@pytest.mark.parametrize(
    "path, body",
    [
        ("/base", {"point": HUGE_POINT, "rotation": ROTATION}),
        ("/tool", {"name": "huge", "point": HUGE_POINT, "rotation": ROTATION, "radius": 0.0}),
    ],
)
def test_a_huge_offset_is_refused_and_changes_nothing(client: TestClient, path: str, body: dict) -> None:
    before = client.get("/position").json()
    response = client.post(path, json=body)
    assert response.status_code == 412, response.text
    assert "within" in response.json()
    after = client.get("/position")
    assert after.status_code == 200, after.text
    assert after.json() == before


@pytest.mark.parametrize("x", [1e6, 1e300])
@pytest.mark.parametrize("motion_type", ["JOINT", "LINEAR"])
def test_a_target_far_away_is_unreachable(client: TestClient, x: float, motion_type: str) -> None:
    far = {"point": {"x": x, "y": 0.0, "z": 0.4}, "rotation": ROTATION}
    response = client.put("/position", params={"speed": 50, "type": motion_type}, json=far)
    assert (response.status_code, response.json()) == (412, "Unreachable Position")
