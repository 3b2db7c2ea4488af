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


class TcpTrail:
    def __init__(self, server: viser.ViserServer) -> None:
        self._server = server
        self._points: deque[tuple[float, np.ndarray]] = deque()
        self._handle: viser.LineSegmentsHandle | None = None

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
            if self._handle is not None:
                self._handle.visible = False
            return
        times = np.array([t for t, _ in self._points])
        xyz = np.stack([p for _, p in self._points])
        segments = np.stack([xyz[:-1], xyz[1:]], axis=1)
        freshness = np.clip(1.0 - (now - times) / TRAIL_SECONDS, 0.0, 1.0)
        rgb = OLD_RGB + freshness[:, None] * (NEW_RGB - OLD_RGB)
        colors = np.stack([rgb[:-1], rgb[1:]], axis=1).astype(np.uint8)
        if self._handle is None:
            self._handle = self._server.scene.add_line_segments(
                "/tcp_trail", segments, colors, thickness=THICKNESS_M
            )
        else:
            self._handle.points = segments
            self._handle.colors = colors
            self._handle.visible = True

    @property
    def n_points(self) -> int:
        return len(self._points)
