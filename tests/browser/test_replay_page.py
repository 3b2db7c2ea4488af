"""Replay in a real browser: record a program run (two moves, the Dashboard's recording on), then Replay it.
At two times typed into the slider's box, the ghost arm the browser is sent stands where the recording says
the joints were (read back with the official reader), and the step text is the step recorded then. The
live arm does not move meanwhile."""

from __future__ import annotations

import re
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import msgspec
import numpy as np
import pytest
import viser.transforms as vtf
import yourdfpy
import zstandard

from pendant.kinematics import ArmModel
from tests.support.browser_pages import (
    ARTIFACTS,
    AWAY_DEG,
    POSE_A_DEG,
    POSE_B_DEG,
    move_to,
    open_tab,
    take_control,
)
from tests.support.launchers import Pendant
from tests.support.mcap_reading import read_mcap

UI_TIMEOUT_MS = 60_000
RUN_TIMEOUT_MS = 90_000
GHOST = "/replay_ghost"
GHOST_TOL_DEG = 0.05  # the slider's box holds tenths of a second; the ghost stands at the sample before
SETTLE_S = 1.5  # the browser receives the ghost's new pose


class GhostWatch:
    """The ghost's joint frames as this page's websocket receives them (viser's wire format: an 8-byte
    length, an 8-byte compressed length, zstd-compressed msgpack {"messages": [...]}, binary buffers)."""

    def __init__(self) -> None:
        self.wxyz: dict[str, tuple[float, ...]] = {}

    def frame(self, payload: bytes | str) -> None:
        if isinstance(payload, str) or len(payload) < 16:
            return
        size = int.from_bytes(payload[:8], "little")
        compressed = int.from_bytes(payload[8:16], "little")
        inner = zstandard.ZstdDecompressor().decompress(payload[16 : 16 + compressed], max_output_size=size)
        for message in msgspec.msgpack.decode(inner).get("messages", ()):
            if message.get("type") == "SetOrientationMessage" and str(message["name"]).startswith(GHOST):
                self.wxyz[message["name"]] = tuple(float(v) for v in message["wxyz"])

    def joints_deg(self, urdf: yourdfpy.URDF) -> list[float]:
        """Each arm joint's angle from its frame's orientation: R = R_origin · Rot(axis, q)."""
        angles = []
        for joint in urdf.actuated_joints[:6]:
            sent = [wxyz for name, wxyz in self.wxyz.items() if name.endswith("/" + joint.child)]
            assert len(sent) <= 1, f"two ghost frames for {joint.child}"
            # A node is created at identity; viser sends an orientation only when it differs.
            wxyz = np.array(sent[0] if sent else (1.0, 0.0, 0.0, 0.0))
            relative = vtf.SO3.from_matrix(joint.origin[:3, :3]).inverse() @ vtf.SO3(wxyz)
            angles.append(float(np.degrees(relative.log() @ np.asarray(joint.axis, dtype=float))))
        return angles


def time_box(page: Any) -> Any:
    """The number box beside the replay's "Time s" slider."""
    row = page.get_by_text("Time s", exact=True).locator("xpath=ancestor::div[.//input][1]")
    return row.locator("input.mantine-NumberInput-input").first


@pytest.fixture
def watched_page(browser: Any, pendant: Pendant) -> Iterator[tuple[Any, GhostWatch]]:
    """A page whose websocket is watched from its first frame (and patient: a loaded machine is slow)."""
    watch = GhostWatch()
    page = browser.new_page(viewport={"width": 1400, "height": 900})
    page.set_default_timeout(UI_TIMEOUT_MS)
    page.on("websocket", lambda socket: socket.on("framereceived", watch.frame))
    page.goto(pendant.ui_url)
    page.get_by_role("button", name="Freeze").wait_for()
    yield page, watch
    # A failed attempt may leave its recording running: its rerun (same pendant) could not start one.
    stop = page.get_by_role("button", name="Stop recording")
    if stop.is_enabled():
        open_tab(page, "Dashboard")
        stop.click()
        page.get_by_text(re.compile(r"Stopped · \d+ samples")).first.wait_for()
    page.close()


def test_replay_draws_the_recorded_arm_and_steps_at_the_slider_time(
    watched_page: tuple[Any, GhostWatch], pendant: Pendant
) -> None:
    page, watch = watched_page
    # Not one look for Take control: a loaded page may not yet say whose control it is (a clean-clone run,
    # 2 Dec: it stayed a viewer, its Record greyed out, and the click waited 60 s).
    take_control(page)
    open_tab(page, "Program")
    move_to(pendant, POSE_A_DEG)
    page.get_by_role("button", name="Record", exact=True).click()
    page.get_by_text("1. Move J to P1 @ 20%").first.wait_for()
    move_to(pendant, POSE_B_DEG)
    page.get_by_role("button", name="Record", exact=True).click()
    page.get_by_text("2. Move J to P2 @ 20%").first.wait_for()
    move_to(pendant, AWAY_DEG)

    open_tab(page, "Dashboard")
    page.get_by_role("button", name="Start recording").click()
    page.get_by_text(re.compile(r"Recording · \d+ samples")).first.wait_for()
    open_tab(page, "Program")
    page.get_by_role("button", name="Run", exact=True).click()
    page.get_by_text("Finished").first.wait_for(timeout=RUN_TIMEOUT_MS)
    open_tab(page, "Dashboard")
    page.get_by_role("button", name="Stop recording").click()
    page.get_by_text(re.compile(r"Stopped · \d+ samples")).first.wait_for()

    # The newest: a rerun's pendant still holds the first try's recording.
    path = max(Path(pendant.data, "recordings").glob("pendant-*.mcap"), key=lambda p: p.stat().st_mtime)
    _, messages = read_mcap(path)
    joints = [(t, m["position_deg"]) for topic, t, m in messages if topic == "/joints"]
    start_ns = joints[0][0]
    steps = [((t - start_ns) / 1e9, m) for topic, t, m in messages if topic == "/program" and m["line"]]
    assert [m["line"] for _, m in steps][:2] == [1, 2], steps
    live = pendant.pose()

    page.get_by_role("button", name="Replay", exact=True).click()
    page.get_by_text(re.compile(r"Ghost: J1")).first.wait_for()
    urdf = yourdfpy.URDF.load(str(ArmModel.load("pulse75").urdf_path), load_meshes=False)
    box = time_box(page)
    for line, (at_s, step) in enumerate(steps[:2], start=1):
        t = np.ceil((at_s + 0.3) * 10) / 10  # into the step, on the slider's tenths
        box.fill(f"{t:.1f}")
        box.press("Enter")
        page.get_by_text(f"Program step {line}: {step['step']}").first.wait_for()
        time.sleep(SETTLE_S)
        recorded = [q for time_ns, q in joints if (time_ns - start_ns) / 1e9 <= t][-1]
        np.testing.assert_allclose(watch.joints_deg(urdf), recorded, atol=GHOST_TOL_DEG)
        page.screenshot(path=str(ARTIFACTS / f"replay-step-{line}.png"))
    first, second = (
        [q for time_ns, q in joints if (time_ns - start_ns) / 1e9 <= s + 0.3][-1] for s, _ in steps[:2]
    )
    assert not np.allclose(first, second, atol=1.0), "the two times show the arm in two places"
    np.testing.assert_allclose(pendant.pose(), live, atol=1e-6)  # replay moved nothing
