"""FastAPI and viser call the simulator from different threads: the lock keeps every answer whole."""

from __future__ import annotations

import threading

import numpy as np

from pendant.controller.types import MotionParams, Pose
from pendant.sim import FakeClock, SimController
from tests.support.waiting import SAFETY_NET_S


def test_concurrent_readers_and_writers_see_consistent_states(sim: SimController, clock: FakeClock) -> None:
    errors: list[BaseException] = []
    stop = threading.Event()

    def read() -> None:
        try:
            while not stop.is_set():
                angles = sim.get_pose().angles
                assert len(angles) == 6 and all(np.isfinite(angles))
                sim.get_position()
                sim.get_motion_status()
        except BaseException as error:  # reported to the main thread
            errors.append(error)

    readers = [threading.Thread(target=read) for _ in range(3)]
    for reader in readers:
        reader.start()
    targets = [Pose(angles=[a, -80.0, 80.0, -90.0, -90.0, 0.0]) for a in (20.0, -20.0, 0.0)] * 3
    for target in targets:
        sim.set_pose(target, MotionParams(speed=100))
        clock.advance(0.3)
        sim.get_motors()
    sim.freeze()
    stop.set()
    for reader in readers:
        reader.join(timeout=SAFETY_NET_S)
    assert not errors
