"""What the program history costs: a save with its commit beside a plain save, listing a program's versions
from a long history, reading an old version and the diff of two.

In a temporary folder: a 40-step program saved N times (each save one changed speed), alternating rounds of
plain saves (ProgramStore) and versioned saves (VersionedStore, dulwich), then `versions()` of the program
with N commits, `version_program()` of the oldest and `diff_programs()` of the first and last. Times are
this process's CPU time, so the machine's other load does not count (nor do fsync's waits for the disk).

Run: .venv/bin/python benchmarks/history.py [--saves 1000]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from pendant.program import MoveStep, Program, WaitStep
from pendant.program.diff import diff_programs
from pendant.program.files import ProgramStore
from pendant.program.versions import VersionedStore
from pendant.ui.program.history_section import SHOWN_VERSIONS
from tests.support.program_history import waypoint

STEPS = 40
ROUND_SAVES = 20
ROUNDS = 3


def program(version: int) -> Program:
    waypoints = tuple(waypoint(f"P{i}", 300.0 + 5 * i) for i in range(STEPS // 2))
    steps = [MoveStep(waypoint=w.name, speed=10.0 + (version + i) % 90) for i, w in enumerate(waypoints)]
    steps += [WaitStep(ms=100 + i) for i in range(STEPS - len(steps))]
    return Program(name="bench", waypoints=waypoints, steps=tuple(steps))


def per_call_ms(action: Callable[[int], object], count: int) -> float:
    """Milliseconds of this process's CPU a call (the machine's other load left out; fsync waits too)."""
    start = time.process_time()
    for k in range(count):
        action(k)
    return 1000.0 * (time.process_time() - start) / count


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--saves", type=int, default=1000, help="versions in the long history")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as root:
        plain, versioned = ProgramStore(Path(root) / "plain"), VersionedStore(Path(root) / "versioned")
        plain_ms, versioned_ms = [], []
        for r in range(ROUNDS):  # side by side, alternating: the machine's load falls on both
            plain_ms.append(
                per_call_ms(lambda k, r=r: plain.save(program(r * ROUND_SAVES + k), "bench"), ROUND_SAVES)
            )
            versioned_ms.append(
                per_call_ms(lambda k, r=r: versioned.save(program(r * ROUND_SAVES + k), "bench"), ROUND_SAVES)
            )
        done = ROUNDS * ROUND_SAVES
        start = time.process_time()
        for k in range(done, args.saves):
            versioned.save(program(k), "bench")
        filling_s = time.process_time() - start
        list_ms = [per_call_ms(lambda _: versioned.versions("bench"), 1) for _ in range(3)]
        page_ms = [per_call_ms(lambda _: versioned.versions("bench", SHOWN_VERSIONS), 1) for _ in range(3)]
        versions = versioned.versions("bench")
        oldest, newest = versions[-1].commit, versions[0].commit
        read_ms = per_call_ms(lambda _: versioned.version_program("bench", oldest), 5)
        first, last = versioned.version_program("bench", oldest), versioned.version_program("bench", newest)
        diff_ms = per_call_ms(lambda _: diff_programs(first, last), 20)
    plain_median, versioned_median = statistics.median(plain_ms), statistics.median(versioned_ms)
    rows = [
        ("save, plain file (median of rounds)", f"{plain_median:.1f} ms"),
        ("save + commit (median of rounds)", f"{versioned_median:.1f} ms"),
        ("save + commit / plain save", f"{versioned_median / plain_median:.1f}x"),
        (f"filling the history to {len(versions)} versions", f"{filling_s:.1f} s"),
        (f"list {len(versions)} versions (best of 3)", f"{min(list_ms):.0f} ms"),
        (f"list the newest {SHOWN_VERSIONS}, as the page (best of 3)", f"{min(page_ms):.0f} ms"),
        ("read the oldest version", f"{read_ms:.1f} ms"),
        (f"diff of the first and last version ({STEPS} steps)", f"{diff_ms:.1f} ms"),
    ]
    width = max(len(name) for name, _ in rows)
    for name, value in rows:
        print(f"{name:<{width}}  {value:>10}")


if __name__ == "__main__":
    main()
