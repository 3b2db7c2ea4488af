"""A pre-flight's budget: how many steps it may simulate and how long it may take (issue #32).

Two nested Loops of a million passes are 202 bytes and would take the pre-flight for days: the steps a
program would run are counted from its plan before anything runs (a loop's body times its passes, a branch's
longer side), and the wall time is checked while it runs, at every command and poll of the twin. Past either,
the pre-flight ends with `OverBudget` (a PreflightRefused: the program is not checked) saying which.
"""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass, field

from pendant.program.models import LoopMode
from pendant.program.plan import Branch, Loop, MoveGroup, Node, Pallet, Single

# ~3 s of checking for the cheapest steps (outputs); room for 1,000 passes of 100 steps.
MAX_STEPS_RUN = 100_000
MAX_WALL_S = 30.0
MSG_TOO_MANY = (
    "the program would run {steps:,} steps (loops times their passes): a pre-flight checks at most "
    "{limit:,}; run fewer passes"
)
MSG_TOO_LONG = "the pre-flight took longer than {limit:g} s and was stopped: check a shorter program"
MSG_CANCELLED = "the pre-flight was stopped: the pendant is quitting"


class OverBudget(Exception):
    """The pre-flight would take more steps or time than it may (or was cancelled): nothing is reported."""


@dataclass
class Budget:
    """Limits of one pre-flight; `cancel` set from another thread stops it at its next command or poll."""

    max_steps: int = MAX_STEPS_RUN
    max_wall_s: float = MAX_WALL_S
    cancel: threading.Event = field(default_factory=threading.Event)
    started: float = field(default_factory=time.monotonic)

    def check_steps(self, plan: tuple[Node, ...]) -> None:
        steps = steps_run(plan)
        if steps > self.max_steps:
            raise OverBudget(MSG_TOO_MANY.format(steps=steps, limit=self.max_steps))

    def check(self) -> None:
        """Raise OverBudget when cancelled or past the wall time (cheap: called at every command and poll)."""
        if self.cancel.is_set():
            raise OverBudget(MSG_CANCELLED)
        if time.monotonic() - self.started > self.max_wall_s:
            raise OverBudget(MSG_TOO_LONG.format(limit=self.max_wall_s))


def steps_run(plan: tuple[Node, ...]) -> int:
    """How many steps running `plan` executes at most (every loop pass counted, a branch's longer side)."""
    total = 0
    for node in plan:
        match node:
            case MoveGroup():
                total += len(node.targets)
            case Single():
                total += 1
            case Loop():
                inner = steps_run(node.body)
                passes = node.times if node.mode is LoopMode.TIMES else 1
                total += 1 + (passes * inner if inner else 0)  # an empty loop is not repeated
            case Branch():
                total += 1 + max(steps_run(node.then), steps_run(node.otherwise))
            case Pallet():
                total += 3 + steps_run(node.body)  # above, down, the body, back up: one cell per entry
    return total
