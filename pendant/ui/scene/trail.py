"""A fading trail behind the TCP: where the tool went in the last few seconds."""

from __future__ import annotations

from collections import deque

import numpy as np
import viser

TRAIL_SECONDS = 3.0
MIN_STEP_M = 0.002  # points closer than this add nothing visible
NEW_RGB = np.array([255.0, 120.0, 0.0])  # orange at the tool
OLD_RGB = np.array([235.0, 235.0, 235.0])  # fading into the floor colour
THICKNESS_M = 0.004
# No trail: one segment of no length inside the arm's base, drawn but never seen. The trail's line is in
# the view from the start, so the page compiles its shaders at load; hidden or made at the first motion,
# software WebGL compiled them during the first jog (each compile waits for the frame being drawn: a
# 70-80 ms long task just after the press).
NO_TRAIL = np.array([[[0.0, 0.0, 0.05], [0.0, 0.0, 0.05]]])
NO_TRAIL_RGB = OLD_RGB.astype(np.uint8)[None, None, :].repeat(2, axis=1)


class TcpTrail:
    def __init__(self, server: viser.ViserServer) -> None:
        self._points: deque[tuple[float, np.ndarray]] = deque()
        self._handle = server.scene.add_line_segments(
            "/tcp_trail", NO_TRAIL, NO_TRAIL_RGB, thickness=THICKNESS_M
        )
        self._empty = True

    def update(self, now: float, tcp: np.ndarray | None) -> None:
        """Add the TCP position `tcp` (metres, base frame) seen at `now`, and drop what is too old."""
        changed = False
        if tcp is not None and (not self._points or np.linalg.norm(tcp - self._points[-1][1]) >= MIN_STEP_M):
            self._points.append((now, np.array(tcp, dtype=float)))
            changed = True
        while self._points and now - self._points[0][0] > TRAIL_SECONDS:
            self._points.popleft()
            changed = True
        if changed:
            self._draw(now)

    def _draw(self, now: float) -> None:
        if len(self._points) < 2:
            if not self._empty:
                self._handle.points, self._handle.colors = NO_TRAIL, NO_TRAIL_RGB
                self._empty = True
            return
        times = np.array([t for t, _ in self._points])
        xyz = np.stack([p for _, p in self._points])
        segments = np.stack([xyz[:-1], xyz[1:]], axis=1)
        freshness = np.clip(1.0 - (now - times) / TRAIL_SECONDS, 0.0, 1.0)
        rgb = OLD_RGB + freshness[:, None] * (NEW_RGB - OLD_RGB)
        colors = np.stack([rgb[:-1], rgb[1:]], axis=1).astype(np.uint8)
        self._handle.points = segments
        self._handle.colors = colors
        self._empty = False

    @property
    def n_points(self) -> int:
        return len(self._points)
