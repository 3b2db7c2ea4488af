"""Where the arm is on screen, as the operator sees it, next to the control panel (docs/screens.md).

The arm's box is every vertex of the arm's meshes (viser's scene node /arm) projected to page pixels with the
page's own camera (viser exposes its scene as `window.__viserMutable` for tests); the panel's box is where
Freeze's scrolling panel is (on a phone with the grab bar above it). `covered` lists the points of a 7x7
grid over the arm's box where something other than the 3D view is on top (the panel, a notification).

Used by tests/browser/test_phone_layout.py (behaviour) and benchmarks/screens.py (the numbers, the
screenshots).
"""

from __future__ import annotations

import contextlib
import io
import time
from typing import Any

ARM_NODE = "/arm"
MESHES_WITHIN_S = 60.0
# The arm drawn within this of its meshes arriving (a frame of software WebGL on a loaded machine, read back).
DRAWN_WITHIN_S = 10.0
GRID = 7
# Darker than the floor's grid lines: the arm's joint caps and shading (as test_jog_hold's arm check).
DARK_GREY = 110

MEASURE = """([armNode, grid]) => {
    const m = window.__viserMutable;
    const arm = m && m.nodeRefFromName[armNode];
    const freeze = [...document.querySelectorAll('button')].find((b) => b.textContent.trim() === 'Freeze');
    if (!arm || !m.camera || !freeze) return null;
    const canvas = m.canvas || document.querySelector('canvas');
    const c = canvas.getBoundingClientRect();
    const camera = m.camera;
    camera.updateMatrixWorld();
    arm.updateWorldMatrix(true, true);
    const v = camera.position.clone();
    let box = [Infinity, Infinity, -Infinity, -Infinity], vertices = 0;
    arm.traverse((o) => {
        if (!o.isMesh) return;
        const p = o.geometry.attributes.position;
        for (let i = 0; i < p.count; i++) {
            v.set(p.getX(i), p.getY(i), p.getZ(i)).applyMatrix4(o.matrixWorld).project(camera);
            const x = c.left + (v.x + 1) / 2 * c.width, y = c.top + (1 - v.y) / 2 * c.height;
            box = [Math.min(box[0], x), Math.min(box[1], y), Math.max(box[2], x), Math.max(box[3], y)];
            vertices++;
        }
    });
    if (vertices === 0) return null;
    // The 3D view: the biggest box around the canvas that is not also around the panel.
    let view = canvas;
    while (view.parentElement !== null && !view.parentElement.contains(freeze)) view = view.parentElement;
    const covered = [];
    for (let i = 0; i < grid; i++) {
        for (let j = 0; j < grid; j++) {
            const x = box[0] + (box[2] - box[0]) * i / (grid - 1);
            const y = box[1] + (box[3] - box[1]) * j / (grid - 1);
            const hit = document.elementFromPoint(x, y);
            if (hit === null || !view.contains(hit)) {
                const what = hit === null ? 'off screen' : hit.className;
                covered.push(`${Math.round(x)},${Math.round(y)} ${what}`);
            }
        }
    }
    const rect = (e) => { const r = e.getBoundingClientRect(); return [r.left, r.top, r.right, r.bottom]; };
    const panel = rect(freeze.closest('.mantine-ScrollArea-viewport'));
    const bar = document.getElementById('pendant-sheet-bar');
    const barBox = bar !== null && getComputedStyle(bar).display !== 'none' ? rect(bar) : null;
    return {
        arm: box, canvas: [c.left, c.top, c.right, c.bottom], panel, bar: barBox, freeze: rect(freeze),
        covered, width: innerWidth, height: innerHeight,
    };
}"""


def arm_on_screen(page: Any, node: str = ARM_NODE) -> dict[str, Any]:
    """The arm's, the 3D view's and the panel's boxes (left, top, right, bottom in page pixels), once the
    arm's meshes have arrived. `node`: another scene node's meshes instead of the arm's (its box in "arm"):
    "/cell", the obstacles."""
    deadline = time.monotonic() + MESHES_WITHIN_S
    while True:
        state = page.evaluate(MEASURE, [node, GRID])
        if state is not None:
            return dict(state)
        if time.monotonic() > deadline:
            raise AssertionError(f"the meshes of {node} never arrived in the page")
        time.sleep(0.2)


def close_notifications(page: Any) -> None:
    """Dismiss the toasts over the view (software WebGL's warning), as an operator would. A toast redrawn or
    closing itself under the click is looked up again."""
    from playwright.sync_api import Error as PlaywrightError

    closes = page.get_by_role("button", name="Close notification")
    for _ in range(10):
        if closes.count() == 0:
            return
        with contextlib.suppress(PlaywrightError):
            closes.first.click(timeout=2_000)
        page.wait_for_timeout(400)
    raise AssertionError("a notification over the view would not close")


def dark_pixels(page: Any, box: list[float]) -> int:
    """Pixels darker than the floor's grid lines inside `box` of the page as shown: the arm's joint caps."""
    import numpy as np
    from PIL import Image

    left, top, right, bottom = box
    png = page.screenshot(clip={"x": left, "y": top, "width": right - left, "height": bottom - top})
    grey = np.asarray(Image.open(io.BytesIO(png)).convert("L"))
    return int(np.count_nonzero(grey < DARK_GREY))


def drawn_dark_pixels(page: Any, box: list[float], at_least: int, within_s: float = DRAWN_WITHIN_S) -> int:
    """`dark_pixels` of `box` once they reach `at_least`, or their count after `within_s`: the view shows
    a frame once the renderer has drawn it and its pixels are read back (off the main thread, a frame or
    two behind the scene on a loaded machine), so the first look can come before the arm's first frame."""
    deadline = time.monotonic() + within_s
    while True:
        count = dark_pixels(page, box)
        if count >= at_least or time.monotonic() > deadline:
            return count
        time.sleep(0.25)


def overlap(a: list[float], b: list[float] | None) -> bool:
    """Two (left, top, right, bottom) boxes share some area."""
    return b is not None and a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]
