"""The pre-flight's report: per step done or refused and why, clearance, peak joint speed, duration; the
cycle time; the inputs assumed; the first failure in words. `as_json()` is what the CLI and the API print."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pendant.controller.types import SignalLevel


@dataclass(frozen=True)
class StepCheck:
    """One line of the step list (1-based, as the page numbers them)."""

    line: int
    step: str
    ok: bool
    checked: bool  # False: the run never reached it (a branch not taken, or after the first failure)
    reason: str | None = None  # why it failed, in words
    note: str | None = None  # why it was not checked
    obstacle: str | None = None
    duration_s: float = 0.0
    min_clearance_mm: float | None = None
    closest_link: str | None = None
    closest_obstacle: str | None = None
    peak_joint_speed_deg_s: float | None = None
    peak_joint: int | None = None  # 1-based

    def as_json(self) -> dict[str, object]:
        return {
            "line": self.line,
            "step": self.step,
            "ok": self.ok,
            "checked": self.checked,
            "reason": self.reason,
            "note": self.note,
            "duration_s": round(self.duration_s, 4),
            "min_clearance_mm": None if self.min_clearance_mm is None else round(self.min_clearance_mm, 1),
            "closest": None
            if self.closest_obstacle is None
            else {"link": self.closest_link, "obstacle": self.closest_obstacle},
            "peak_joint_speed_deg_s": None
            if self.peak_joint_speed_deg_s is None
            else round(self.peak_joint_speed_deg_s, 1),
            "peak_joint": self.peak_joint,
        }


@dataclass(frozen=True)
class FirstFailure:
    line: int
    step: str
    reason: str
    obstacle: str | None

    @property
    def words(self) -> str:
        """ "Step 7 (Move L to place @ 20%): the tool would hit 'fixture' at 62 % of the move"."""
        return f"Step {self.line} ({self.step}): {self.reason}"

    def as_json(self) -> dict[str, object]:
        return {"line": self.line, "step": self.step, "reason": self.reason, "obstacle": self.obstacle}


@dataclass(frozen=True)
class AssumedInput:
    level: SignalLevel
    why: str  # "given", "read from the arm", "the wait's level"


@dataclass(frozen=True)
class PreflightReport:
    program: str
    steps: tuple[StepCheck, ...]
    cycle_time_s: float
    assumed_inputs: dict[int, AssumedInput]
    loop_passes: int  # passes assumed for each while/until loop
    first_failure: FirstFailure | None = None
    notes: tuple[str, ...] = field(default=())
    elapsed_s: float = 0.0  # wall time the check took
    # For the page's playback (not in the JSON): (seconds from the start, 0-based line, joint angles rad),
    # and where the first failure would touch (joint angles), when it is a collision.
    timeline: tuple[tuple[float, int, np.ndarray], ...] = ()
    failure_q: np.ndarray | None = None

    @property
    def ok(self) -> bool:
        return self.first_failure is None

    @property
    def summary(self) -> str:
        if self.first_failure is not None:
            return self.first_failure.words
        return f"All {len(self.steps)} steps pass; cycle time {self.cycle_time_s:.2f} s"

    def as_json(self) -> dict[str, object]:
        return {
            "ok": self.ok,
            "program": self.program,
            "summary": self.summary,
            "cycle_time_s": round(self.cycle_time_s, 4),
            "assumed_inputs": {
                str(port): {"level": a.level.value, "why": a.why}
                for port, a in sorted(self.assumed_inputs.items())
            },
            "while_loop_passes": self.loop_passes,
            "first_failure": None if self.first_failure is None else self.first_failure.as_json(),
            "steps": [step.as_json() for step in self.steps],
            "notes": list(self.notes),
            "elapsed_s": round(self.elapsed_s, 3),
        }
