"""Waypoint names never overlap on screen (issue 33), in a browser's own view: two waypoints 6 cm apart (more
than the 5 cm under which scene.py gives them one label) are drawn side by side from the pendant's usual
camera, and their names overlapped. A real viser server on loopback with the Program tab's scene, the browser
a bare websocket that reports its camera and reads what it is sent: the labels it then shows (their texts,
which are visible) must not overlap, and every step's name must be on one of them. Turning the view so the
two are far apart on screen gives each its own label back."""

from __future__ import annotations

import asyncio
import math
from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest
import viser
import zstandard

from pendant.program import Program
from pendant.sim import FakeClock, SimController
from pendant.ui.program.label_layout import View, label_box, overlap, project, stack_overlapping
from pendant.ui.program.scene import LABEL_ABOVE_M, ProgramScene
from pendant.ui.scene.arm import CAMERA_LOOK_AT_M, CAMERA_POSITION_M
from tests.support.headless_viewer import camera_report, next_messages, open_viewer
from tests.support.ports import LOOPBACK, free_port
from tests.support.programs import POSE_A_DEG, POSE_B_DEG, move, program_of, teach

READ_TIMEOUT_S = 60.0  # labels are laid out within 0.15 s of a report; a pass at nice 19 can starve it
FOV_RAD = math.radians(50.0)
DESK = (1400, 900)
P2_J1_OFFSET_DEG = 7.0  # P2 beside P1: some 6 cm of the TCP's swing about J1
# From above, straight down on the two waypoints and close: their labels far apart on screen.
CLOSE_ABOVE_M = 0.5


@pytest.fixture
def program(sim: SimController, clock: FakeClock) -> Program:
    p1 = teach(sim, clock, POSE_B_DEG, "P1")
    beside = (POSE_B_DEG[0] + P2_J1_OFFSET_DEG, *POSE_B_DEG[1:])
    p2 = teach(sim, clock, beside, "P2")
    p3 = teach(sim, clock, POSE_A_DEG, "P3")
    return program_of(move(p1), move(p2), move(p3))


@pytest.fixture
def server(sim: SimController, program: Program) -> Iterator[viser.ViserServer]:
    server = viser.ViserServer(host=LOOPBACK, port=free_port(), verbose=False)

    def draw(client: viser.ClientHandle) -> None:
        ProgramScene(client, sim.arm).show(program)

    server.on_client_connect(draw)
    try:
        yield server
    finally:
        server.stop()


def waypoint_points(program: Program) -> dict[str, np.ndarray]:
    return {
        w.name: np.array([w.position.point.x, w.position.point.y, w.position.point.z])
        for w in program.waypoints
    }


class Shown:
    """The labels as the browser has them: name -> [text, visible]."""

    def __init__(self) -> None:
        self.labels: dict[str, list[Any]] = {}

    def read(self, messages: list[dict[str, Any]]) -> None:
        for m in messages:
            name = m.get("name", "")
            if m.get("type") == "LabelMessage":
                self.labels[name] = [m["props"]["text"], True]
            elif m.get("type") == "SceneNodeUpdateMessage" and name in self.labels and "text" in m["updates"]:
                self.labels[name][0] = m["updates"]["text"]
            elif m.get("type") == "SetSceneNodeVisibilityMessage" and name in self.labels:
                self.labels[name][1] = m["visible"]

    def visible(self) -> list[str]:
        return sorted(text for text, on in self.labels.values() if on)


async def labels_for(port: int, views: list[bytes], wanted: list[list[str]]) -> list[list[str]]:
    """Report each view in turn and read the labels the browser then shows, until they are `wanted`'s (or the
    time is up: what it showed then)."""
    ws = await open_viewer(port, hello=views[0])
    seen: list[list[str]] = []
    shown = Shown()
    zstd = zstandard.ZstdDecompressor()
    try:
        for view, want in zip(views, wanted, strict=True):
            await ws.send(view)  # again for the first: the scene is drawn once the browser has connected
            try:
                async with asyncio.timeout(READ_TIMEOUT_S):
                    while shown.visible() != sorted(want):
                        shown.read(await next_messages(ws, zstd))
            except TimeoutError:
                pass
            seen.append(shown.visible())
    finally:
        await ws.close()
    return seen


def test_names_that_would_overlap_are_stacked_and_part_again_when_the_view_turns(
    server: viser.ViserServer, program: Program
) -> None:
    points = waypoint_points(program)
    usual = View(
        np.array(CAMERA_POSITION_M), np.array(CAMERA_LOOK_AT_M), np.array([0, 0, 1.0]), FOV_RAD, *DESK
    )
    above = np.array([0.0, 0.0, LABEL_ABOVE_M])
    a1, a2 = (project(usual, points[n] + above) for n in ("P1", "P2"))
    assert a1 is not None and a2 is not None
    assert overlap(label_box(a1, "1. P1"), label_box(a2, "2. P2")), "P1's and P2's names do not meet: no test"

    middle = (points["P1"] + points["P2"]) / 2
    close = camera_report(
        middle + np.array([0.0, -0.01, CLOSE_ABOVE_M]), DESK, look_at=middle, fov_rad=FOV_RAD
    )
    usual_view = camera_report(CAMERA_POSITION_M, DESK, look_at=CAMERA_LOOK_AT_M, fov_rad=FOV_RAD)
    stacked = ["1. P1\n2. P2", "3. P3"]
    apart = ["1. P1", "2. P2", "3. P3"]
    seen = asyncio.run(labels_for(server.get_port(), [usual_view, close], [stacked, apart]))
    assert seen == [sorted(stacked), sorted(apart)]


def test_stacking_goes_on_until_no_two_labels_overlap() -> None:
    """A crowd of names in a row, each just beside the last: stacked labels grow upwards and meet the ones
    above them; the layout merges until none overlaps, and keeps every line once."""
    anchors: list[tuple[float, float] | None] = [(100.0 + 8 * k, 300.0 - 12 * k) for k in range(12)]
    anchors.append(None)  # off the view: kept as it is
    texts = [f"{k + 1}. P{k + 1}" for k in range(13)]
    shown = stack_overlapping(anchors, texts)
    boxes = [label_box(a, t) for a, t in zip(anchors, shown, strict=True) if a is not None and t is not None]
    assert not any(overlap(a, b) for i, a in enumerate(boxes) for b in boxes[i + 1 :])
    lines = [line for text in shown if text is not None for line in text.split("\n")]
    assert sorted(lines) == sorted(texts)
    assert shown[-1] == texts[-1]
