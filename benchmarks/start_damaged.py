"""Start-up with damaged recordings (issue #32): the time from starting `pendant` (page and API) to both
answering, on an empty data folder and on one holding every crafted damaged recording of the test kit, a
500 MB sparse file with an MCAP header and a recording cut short by a kill (10 minutes by default), started
alternately. The repair runs beside the start-up; its lines reach the event log after.

Target: the pendant serves within its usual start time whatever is in the data folder.
Run: .venv/bin/python benchmarks/start_damaged.py [--rounds 3] [--recorded-s 600]
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from pendant.telemetry.mcap_scan import MAGIC
from tests.support.launchers import running_pendant_ui
from tests.support.recordings import CRAFTED, HEADER, crafted, make_recording

SPARSE_BYTES = 500 * 1024 * 1024


def damaged_folder(root: Path, recorded_s: float) -> Path:
    """A data folder whose recordings/ holds what no start-up should trip on; rebuilt for every start (the
    pendant moves the damaged files aside and finishes the cut one)."""
    data = Path(tempfile.mkdtemp(prefix="damaged-", dir=root))
    recordings = data / "recordings"
    recordings.mkdir()
    make_recording(data / "live", recorded_s, unfinished_copy=recordings / "pendant-20270101-000000.mcap")
    for name in CRAFTED:
        (recordings / f"pendant-{name}.mcap").write_bytes(crafted(name))
    sparse = recordings / "pendant-sparse.mcap"
    sparse.write_bytes(MAGIC + HEADER)
    os.truncate(sparse, SPARSE_BYTES)
    return data


def started_in_s(data: Path) -> float:
    began = time.monotonic()
    with running_pendant_ui(env={"PENDANT_DATA_DIR": str(data)}):
        return time.monotonic() - began


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--recorded-s", type=float, default=600.0, help="the recording cut short, in seconds")
    args = parser.parse_args()
    times: dict[str, list[float]] = {"empty": [], "damaged": []}
    with tempfile.TemporaryDirectory() as root:
        for number in range(1, args.rounds + 1):
            empty = Path(tempfile.mkdtemp(prefix="empty-", dir=root))
            times["empty"].append(started_in_s(empty))
            times["damaged"].append(started_in_s(damaged_folder(Path(root), args.recorded_s)))
            print(f"round {number}: empty {times['empty'][-1]:.1f} s, damaged {times['damaged'][-1]:.1f} s")
    for label, seconds in times.items():
        each = ", ".join(f"{s:.1f}" for s in seconds)
        print(f"{label:<8} median {statistics.median(seconds):.1f} s  ({each})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
