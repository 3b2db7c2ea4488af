"""Waypoint names that would overlap on screen are stacked into one label (issue 33: "labels never overlap").

scene.py already gives markers within 5 cm of one another one label. Markers farther apart can still be
drawn on top of one another: one behind the other along the view, or a far view. Each browser's camera is
known to the server (viser's camera reports), so the labels are laid out for that view: the box of each name
is estimated from its text (viser draws screen-size labels at a 12 px em whatever the view:
client/src/label/LabelRenderer.tsx), and a label whose box would overlap one already placed adds its lines to
that one and is hidden. Labels are placed in step order, so the first step's label is where it always is.
"""

from __future__ import annotations

import asyncio
import logging
import math
import threading
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np
import viser

from pendant.ui.kit.gui_target import GuiTarget

EM_PX = 12.0  # viser's screen-size label at font_screen_scale 1
CHAR_EM = 0.62  # a generous average width of the system font's characters
LINE_EM = 1.3
PAD_EM = 0.6  # the label's background around its text, both sides together
Box = tuple[float, float, float, float]  # left, top, right, bottom (px, y down)
Anchor = tuple[float, float] | None  # a label's place on the view (px), None when off it
log = logging.getLogger(__name__)
# Camera reports come some 50 a second while the operator turns the view: the labels follow at most this
# often, on a thread of their own (never viser's callback pool nor the event loop, which carry the stops).
LAYOUT_EVERY_S = 0.15
_layouts = ThreadPoolExecutor(max_workers=1, thread_name_prefix="label-layout")


@dataclass(frozen=True)
class View:
    """A browser's camera as viser reports it (world frame, z up; vertical field of view; px)."""

    position: np.ndarray
    look_at: np.ndarray
    up: np.ndarray
    fov_rad: float
    width: int
    height: int


def project(view: View, point: np.ndarray) -> Anchor:
    """`point` in the view's pixels, or None when it is behind the camera."""
    forward = view.look_at - view.position
    forward = forward / np.linalg.norm(forward)
    right = np.cross(forward, view.up)
    if float(np.linalg.norm(right)) < 1e-9:
        return None  # looking straight along "up": no screen orientation to speak of
    right = right / np.linalg.norm(right)
    up = np.cross(right, forward)
    d = np.asarray(point, dtype=float) - view.position
    depth = float(d @ forward)
    if depth <= 1e-6:
        return None
    px_per_unit = view.height / 2 / math.tan(view.fov_rad / 2) / depth  # square pixels
    return view.width / 2 + float(d @ right) * px_per_unit, view.height / 2 - float(d @ up) * px_per_unit


def label_box(anchor: tuple[float, float], text: str) -> Box:
    """The box a label of `text` takes with its bottom centre at `anchor` (the scene's labels' anchor)."""
    lines = text.split("\n")
    width = (max(len(line) for line in lines) * CHAR_EM + PAD_EM) * EM_PX
    height = (len(lines) * LINE_EM + PAD_EM) * EM_PX
    x, y = anchor
    return x - width / 2, y - height, x + width / 2, y


def overlap(a: Box, b: Box) -> bool:
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


def stack_overlapping(anchors: Sequence[Anchor], texts: Sequence[str]) -> list[str | None]:
    """Each label's text as shown (its own lines, then those of the labels stacked into it), or None for a
    label stacked into another (hidden). A label off the view (None anchor) keeps its own text."""
    groups: list[list[int]] = []  # labels on the view: each group shown at its first label's anchor

    def box(group: list[int]) -> Box:
        anchor = anchors[group[0]]
        assert anchor is not None  # only labels on the view are grouped
        return label_box(anchor, "\n".join(texts[k] for k in group))

    for k, anchor in enumerate(anchors):
        if anchor is None:
            continue
        own = label_box(anchor, texts[k])
        into = next((g for g in groups if overlap(own, box(g))), None)
        if into is None:
            groups.append([k])
        else:
            into.append(k)
    # A stacked label is taller: it may now cover another. Merge until none overlaps (each merge drops one).
    merged = True
    while merged:
        merged = False
        for a in range(len(groups)):
            later = range(a + 1, len(groups))
            hit = next((b for b in later if overlap(box(groups[a]), box(groups[b]))), None)
            if hit is not None:
                groups[a].extend(groups.pop(hit))
                merged = True
                break
    shown: list[str | None] = list(texts)
    for group in groups:
        shown[group[0]] = "\n".join(texts[k] for k in group)
        for k in group[1:]:
            shown[k] = None
    return shown


class ScreenLabels:
    """One browser's waypoint labels laid out for its camera (`replace` gives the labels drawn now). On the
    server's shared scene, which has no one camera, labels stay as drawn."""

    def __init__(self, target: GuiTarget) -> None:
        self._lock = threading.Lock()
        self._labels: list[tuple[viser.LabelHandle, np.ndarray, str]] = []  # (label, anchor, own text)
        self._shown: list[str | None] = []  # as the browser has them
        self._view: View | None = None
        self._due = False
        if isinstance(target, viser.ClientHandle):
            target.camera.on_update(self._camera_moved)

    def replace(self, labels: list[tuple[viser.LabelHandle, np.ndarray, str]]) -> None:
        """The labels just drawn (each with its world anchor and own text), laid out for the last view."""
        with self._lock:
            self._labels = labels
            self._shown = [text for _, _, text in labels]
        self.lay_out()

    def lay_out(self) -> None:
        with self._lock:
            view, labels = self._view, self._labels
            if view is None or len(labels) < 2:
                return
            shown = stack_overlapping([project(view, p) for _, p, _ in labels], [t for _, _, t in labels])
            for (label, _, _), want, before in zip(labels, shown, self._shown, strict=True):
                if want == before:
                    continue
                if want is not None:
                    label.text = want
                label.visible = want is not None
            self._shown = shown

    async def _camera_moved(self, camera: viser.CameraHandle) -> None:
        """On viser's event loop: note the view, and lay out a little later (once for a burst of reports)."""
        self._view = View(
            np.asarray(camera.position, dtype=float),
            np.asarray(camera.look_at, dtype=float),
            np.asarray(camera.up_direction, dtype=float),
            float(camera.fov),
            int(camera.image_width),
            int(camera.image_height),
        )
        if self._due or len(self._labels) < 2:
            return
        self._due = True
        loop = asyncio.get_running_loop()
        loop.call_later(LAYOUT_EVERY_S, lambda: loop.run_in_executor(_layouts, self._lay_out_due))

    def _lay_out_due(self) -> None:
        self._due = False
        try:
            self.lay_out()
        except Exception:  # the labels stay as they were; the next view lays them out again
            log.exception("laying out the waypoint labels failed")
