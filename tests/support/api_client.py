"""Constants and helpers of the API tests: tolerances, content types, the arm's observable state."""

from __future__ import annotations

from typing import Any

from fastapi.testclient import TestClient

POS_TOL_M = 1e-6
ANGLE_TOL_DEG = 1e-6
MOTION_STEP_S = 0.05
MOTION_MAX_S = 120.0

TEXT = "text/plain; charset=utf-8"
JSON = "application/json"

PULSE_READS = (
    "/pose",
    "/position",
    "/tool",
    "/base",
    "/signal/output/1",
    "/signal/output/2",
    "/status/motion",
)


def arm_state(client: TestClient) -> dict[str, Any]:
    """What a user can read of the arm: pose, position, tool, base, outputs, motion status."""
    return {path: client.get(path).text for path in PULSE_READS}


def finish_motion(client: TestClient, clock: Any) -> str:
    """Advance the fake clock until the arm stops moving; the final motion status."""
    elapsed = 0.0
    status = client.get("/status/motion").json()
    while status == "RUNNING" and elapsed < MOTION_MAX_S:
        clock.advance(MOTION_STEP_S)
        elapsed += MOTION_STEP_S
        status = client.get("/status/motion").json()
    return status


def angles_close(actual: list[float], expected: list[float], tol: float = ANGLE_TOL_DEG) -> bool:
    return len(actual) == len(expected) and all(
        abs(a - e) <= tol for a, e in zip(actual, expected, strict=True)
    )


MOTION_METHODS = frozenset({"set_position", "set_pose", "run_positions", "run_poses"})


class RecordingController:
    """The real simulator, noting the MotionParams each motion command reaches it with.

    Not a fake: every call goes to the simulator. Being a wrapper, it is not a SimController, so an app built
    on it has no /sim routes, like an app in front of a real arm.
    """

    def __init__(self, sim: Any) -> None:
        self._sim = sim
        self.motion_params: list[Any] = []

    def __getattr__(self, name: str) -> Any:
        attribute = getattr(self._sim, name)
        if name not in MOTION_METHODS:
            return attribute

        def recorded(target: Any, params: Any) -> Any:
            self.motion_params.append(params)
            return attribute(target, params)

        return recorded
