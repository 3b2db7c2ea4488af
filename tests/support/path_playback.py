"""A hand-drawn path on the simulator, and playing one back on a fake clock: shared by the path-step tests
and benchmarks/path_playback.py."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from starlette.types import Receive, Scope, Send

from pendant.controller import Pose
from pendant.kinematics.transforms import position_to_matrix
from pendant.sim import FakeClock, SimController
from pendant.teach.recording import PathRecorder, Recording

HAND_STEPS = 90
HAND_RATE_HZ = 30.0
SAMPLE_S = 0.002  # the played TCP is sampled this often (simulated time)


def hand_drawn_s(
    sim: SimController, clock: FakeClock, steps: int = HAND_STEPS, folder: Path | None = None
) -> Recording:
    """Free drive: the arm pulled by hand through an S (J1 sweeps while J2, J3 and J5 bend and come back),
    recorded at 30 Hz as the page's refresh feeds the recorder (which keeps it in `folder`, if given)."""
    recorder = PathRecorder(folder)
    home = np.array(sim.get_pose().angles)
    sim.zg_on()
    recorder.start()
    for i in range(steps + 1):
        s = i / steps
        wave = np.sin(2.0 * np.pi * s)
        q = home + np.array([40.0 * s, 12.0 * wave, -15.0 * wave, 0.0, 10.0 * np.sin(np.pi * s), 0.0])
        sim.move_by_hand(Pose(angles=[float(v) for v in q]))
        clock.advance(1.0 / HAND_RATE_HZ)
        recorder.add(clock.now(), np.radians(q), sim.get_position(), {}, {})
    sim.zg_off()
    recording = recorder.stop()
    assert recording is not None
    return recording


def recorded_points(recording: Recording) -> np.ndarray:
    return np.array([[s.tcp.point.x, s.tcp.point.y, s.tcp.point.z] for s in recording.samples])


class Sampler:
    """The runner's sleep: advances the fake clock in small steps, noting the TCP position at each."""

    def __init__(self, sim: SimController, clock: FakeClock) -> None:
        self._sim, self._clock = sim, clock
        self.poses: list[np.ndarray] = []  # T_zero_tcp
        self.at: Callable[[], None] | None = None  # done once, at the next sleep

    def __call__(self, dt: float) -> None:
        if self.at is not None:
            action, self.at = self.at, None
            action()
        for _ in range(max(1, round(dt / SAMPLE_S))):
            self._clock.advance(dt / max(1, round(dt / SAMPLE_S)))
            self.poses.append(position_to_matrix(self._sim.get_position()))

    @property
    def played(self) -> np.ndarray:
        return np.array(self.poses)[:, :3, 3]


class WithoutRunOperations:
    """The simulator's API as a controller older than SDK 1.8 answers it: 404 to every /run/* request."""

    def __init__(self, app: Any) -> None:
        self._app = app

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] == "http" and scope.get("path", "").startswith("/run/"):
            await send(
                {"type": "http.response.start", "status": 404, "headers": [(b"content-type", b"text/plain")]}
            )
            await send({"type": "http.response.body", "body": b"Not Found"})
            return
        await self._app(scope, receive, send)
