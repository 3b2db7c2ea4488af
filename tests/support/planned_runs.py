"""A plan from POST /pendant/plan run as docs/planning.md says: one PUT /run/joint/poses, BLEND with a
near-zero blend at each corner, so the arm follows the straight joint segments the planner checked (the
simulator's /poses/run draws a spline through the same waypoints, which can bulge into what the path goes
around)."""

from __future__ import annotations

from collections.abc import Sequence

from pendant.program.blended import PLANNED_CORNER_BLEND_DEG  # the corners of the pendant's own Move


def along_segments(angles: Sequence[Sequence[float]], percent: float) -> dict[str, object]:
    """The body of PUT /run/joint/poses through `angles` (degrees), at `percent` of the joints' limits."""
    return {
        "poses": [{"angles": [float(a) for a in pose], "blend": PLANNED_CORNER_BLEND_DEG} for pose in angles],
        "motionParameters": {"interpolation_type": "BLEND", "velocity": percent, "acceleration": percent},
    }
