"""Reading a big program file beside a Freeze (issue #32): how long the other threads wait, and which garbage
collections run, over many readings of a 4.9 MB file of 170,000 steps (refused: at most 2,000) in a process
holding `--heap` other objects, as the pendant's process holds its own.

Before, a reading's objects were still alive when the collector came back on: the next collection moved
them on to the older generations, and every few readings a full collection walked the whole heap while
every thread waited. Target: no reading holds the other threads past 50 ms, and no collection of
generation 1 or 2 runs during the readings because of them.
Run: .venv/bin/python benchmarks/program_files.py [--readings 20] [--heap 50000]
"""

from __future__ import annotations

import argparse
import gc
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from pendant.program.files import ProgramFileError, parse_program
from tests.support.gil import longest_hold_ms
from tests.support.programs import dense_program_bytes


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--readings", type=int, default=20)
    parser.add_argument("--heap", type=int, default=50_000, help="other objects the process holds")
    args = parser.parse_args()
    heap = [{"k": i, "v": [i]} for i in range(args.heap)]
    data = dense_program_bytes()
    collections: list[tuple[int, float]] = []
    started = [0.0]

    def timed(phase: str, info: dict[str, int]) -> None:
        if phase == "start":
            started[0] = time.perf_counter()
        else:
            collections.append((info["generation"], (time.perf_counter() - started[0]) * 1000))

    gc.callbacks.append(timed)
    held = []
    for _ in range(args.readings):
        ms, outcome = longest_hold_ms(lambda: parse_program(data, "dense.json"))
        if not isinstance(outcome, ProgramFileError):
            raise SystemExit(f"the file was not refused: {outcome!r}")
        held.append(ms)
    gc.callbacks.remove(timed)
    print(
        f"load {os.getloadavg()[0]:.1f}; {args.readings} readings of {len(data) / 1e6:.1f} MB, "
        f"{len(heap):,} other objects"
    )
    print(
        f"  the other threads waited at most {max(held):.0f} ms (median {sorted(held)[len(held) // 2]:.0f})"
    )
    for generation in (0, 1, 2):
        times = [ms for g, ms in collections if g == generation]
        longest = f", the longest {max(times):.0f} ms" if times else ""
        print(f"  collections of generation {generation}: {len(times)}{longest}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
