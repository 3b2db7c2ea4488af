"""A recording as one Path step of a program: simplified within half the operator's tolerance, so that the
other half can round each corner when the path plays back as one blended run (pendant.program.blended)."""

from __future__ import annotations

from pathlib import Path

from pendant.program.models import DEFAULT_PATH_NAME, PathPoint, PathStep
from pendant.teach.recording import Recording, read_recording
from pendant.teach.simplify import DEFAULT_TOL_DEG, DEFAULT_TOL_MM

SIMPLIFY_SHARE = 0.5  # of the tolerance; the rest is the corners' blend (PathStep.blend_mm)


def path_step(
    recording: Recording,
    tol_mm: float = DEFAULT_TOL_MM,
    tol_deg: float = DEFAULT_TOL_DEG,
    name: str = DEFAULT_PATH_NAME,
) -> PathStep:
    """The path step playing `recording` back within `tol_mm` / `tol_deg` (relaxed, and the step says so,
    when at most 100 waypoints need more). ValueError when the recording holds no path."""
    kept, used_mm, used_deg = recording.waypoints(tol_mm * SIMPLIFY_SHARE, tol_deg * SIMPLIFY_SHARE)
    return PathStep(
        name=name,
        points=tuple(PathPoint(pose=pose, position=position) for pose, position in kept),
        tol_mm=used_mm / SIMPLIFY_SHARE,
        tol_deg=used_deg / SIMPLIFY_SHARE,
        recording=recording.file,
    )


def resimplified(step: PathStep, folder: Path | None, tol_mm: float, tol_deg: float) -> PathStep:
    """`step` made again from its kept recording at another tolerance (its name and speeds kept).
    ValueError when the recording is not kept."""
    if step.recording is None or folder is None:
        raise ValueError(f"path {step.name} has no kept recording to simplify again")
    remade = path_step(read_recording(folder, step.recording), tol_mm, tol_deg, step.name)
    return remade.model_copy(update={"speed": step.speed, "velocity_mm_s": step.velocity_mm_s})
