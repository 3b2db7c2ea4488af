"""A classroom: N steady viewers watch while the operator holds a jog; does the hold ever notice them?

A real `pendant` process (simulator, UI and API on loopback). The operator (a process of its own, the first
browser: it has control) holds J1+ at 2 % for the whole run, a confirmation every 50 ms as the page sends
them (over the hold line when the pad names one, else over viser's websocket: see benchmarks/churn.py).
Meanwhile, in another process, N viewers (viser's websocket as a browser opens it, every frame read) count
the arm's updates (`/tcp_frame`); in this process a newcomer every 2 s times its Freeze and its whole panel
(every tab: a panel build each), and with `--plans` a thread keeps POST /pendant/plan and /pendant/preflight
busy. A cut is a "Jog J1+ stopped: ..." event (the operator then presses again).

Prints: deadman cuts, updates a second per viewer (min / median), the newcomers' Freeze and whole panel
(median / p95), the pendant's CPU with the operator alone and with the steady viewers (for STEADY_S, before
the first newcomer, once their panels are built), the difference per viewer, and the CPU once the
newcomers come too. `--baseline REV` measures the pendant of git revision REV first, then this checkout,
side by side.

`--program`: the operator runs a program from the page instead of holding the jog (benchmarks/
classroom_program.py): how late each step begins against the previous step's end + its wait, timed by the
simulator on its own clock, with the operator alone and then with the viewers (p50 / p99 / max); the
viewers' arm updates a second are counted while the arm moves (between moves it sends nothing new).

Run: .venv/bin/python benchmarks/classroom.py [--viewers 60 | --viewers 1,20,60,100] [--seconds 60]
     [--plans] [--program] [--baseline REV]
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import multiprocessing
import os
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import httpx

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from benchmarks.churn import (
    PAGE_TIMEOUT_S,
    PANEL_TIMEOUT_S,
    OperatorJob,
    Viewer,
    operate,
    operator_process,
    pendant_from,
    percentile,
    probe,
)
from benchmarks.classroom_program import (
    Lateness,
    ProgramRun,
    moving,
    pendant_with_program,
    summary,
    windows,
)
from benchmarks.classroom_program import (
    operate as operate_program,
)
from benchmarks.preflight_bodies import PLAN, SMALL
from benchmarks.viewers import cpu_seconds
from tests.support.headless_viewer import ViewerCounts, viewer
from tests.support.metrics import scrape, values

REPO = Path(__file__).resolve().parents[1]
START_TIMEOUT_S = 180.0  # the operator ready (--program: its Program tab built, at load 30 past a minute)
WARM_UP_S = 5.0
ALONE_S = 5.0  # the operator alone first: the pendant's CPU without viewers
# Then the viewers alone, before any newcomer: the pendant's CPU per steady viewer (a newcomer's panels
# are a build each, charged to the newcomers' own row, not to the viewers who watch).
STEADY_S = 10.0
# ... once their panels are built (the pendant's gauge of browsers with panels), at most this long after
# they connect: with builds held back while the operator jogs, 60 viewers' panels take a while.
BUILT_TIMEOUT_S = 45.0


def browsers_with_panels(api: str) -> int:
    """The pendant's `pendant_viewers_connected` gauge: browsers whose panels are built (-1: unread)."""
    try:
        gauge = values(scrape(api), "pendant_viewers_connected")
    except (httpx.HTTPError, AssertionError):  # no answer, or not /metrics' (scrape checks it)
        return -1
    return int(gauge[0]) if gauge else -1


async def wait_for_panels(api: str, n: int, timeout_s: float) -> int:
    """Until `n` browsers have their panels (or the time-out): how many had them."""
    deadline = time.monotonic() + timeout_s
    while (built := await asyncio.to_thread(browsers_with_panels, api)) < n and time.monotonic() < deadline:
        await asyncio.sleep(0.5)
    return built


def viewers_process(port: int, n: int, done: Any, results: multiprocessing.Queue) -> None:  # type: ignore[type-arg]
    """N viewers until `done` is set (a multiprocessing Event); when they began counting (WARM_UP_S after
    connecting) and when each received the arm's pose from then on."""

    async def run() -> tuple[float, list[list[float]]]:
        stop = asyncio.Event()
        counts = [ViewerCounts() for _ in range(n)]
        tasks = [asyncio.create_task(viewer(f"ws://127.0.0.1:{port}/", c, stop)) for c in counts]
        await asyncio.sleep(WARM_UP_S)
        t0 = time.monotonic()
        await asyncio.to_thread(done.wait)
        t1 = time.monotonic()
        stop.set()
        await asyncio.gather(*tasks, return_exceptions=True)
        return t0, [[t for t in c.state_times if t0 <= t < t1] for c in counts]

    results.put(asyncio.run(run()))


def rates_within(times: list[list[float]], spans: list[tuple[float, float]]) -> list[float]:
    """Each viewer's arm updates a second within `spans` (monotonic s): while the arm moved, for a program
    (standing still between moves, the arm sends nothing new)."""
    seconds = sum(t1 - t0 for t0, t1 in spans)
    return [sum(t0 <= t < t1 for t in viewer for t0, t1 in spans) / seconds for viewer in times]


def keep_planning(api: str, stop: threading.Event, done: list[int]) -> None:
    with httpx.Client(base_url=api, timeout=120) as http:
        while not stop.is_set():
            http.post("/pendant/plan", json=PLAN)
            http.post("/pendant/preflight", json=SMALL)
            done[0] += 2


@dataclass
class Outcome:
    label: str
    cuts: list[str]
    rates: list[float]
    newcomers: list[Viewer]
    alone_cores: float
    cores: float
    plans: int
    moved_deg: float
    hold_gap_s: float  # the operator's largest gap between two confirmations sent (its side)
    operator_late_cuts: int  # cuts within 1 s after the operator itself sent >= 150 ms late
    late_alone: Lateness | None = None  # --program: the steps' lateness, the operator alone
    late: Lateness | None = None  # ... and with the viewers
    ended: str = ""  # --program: the run's last line after Stop
    built: int = 0  # steady viewers with their panels built when their CPU was measured
    newcomer_cores: float = 0.0  # the pendant's CPU while newcomers came (a build each), the viewers too


async def measure(
    ui: int, api: str, pid: int, n: int, seconds: float, plans: bool, program: ProgramRun | None
) -> Outcome:
    spawn = multiprocessing.get_context("spawn")
    # The operator's hold (or run): long enough, and let go as soon as the newcomers are done (`watched`).
    total = ALONE_S + WARM_UP_S + BUILT_TIMEOUT_S + STEADY_S + seconds + PAGE_TIMEOUT_S + PANEL_TIMEOUT_S
    watched = spawn.Event()
    operated: multiprocessing.Queue = spawn.Queue()  # type: ignore[type-arg]
    job = OperatorJob(ui, api, total, operated, watched)
    operates = operate if program is None else operate_program
    operator = spawn.Process(target=operator_process, args=(operates, job), daemon=True)
    operator.start()
    assert await asyncio.to_thread(operated.get, True, START_TIMEOUT_S) == "ready"
    t0, cpu0 = time.monotonic(), cpu_seconds(pid)
    await asyncio.sleep(ALONE_S)
    alone = (cpu_seconds(pid) - cpu0) / (time.monotonic() - t0)
    rated: multiprocessing.Queue = spawn.Queue()  # type: ignore[type-arg]
    watchers = spawn.Process(target=viewers_process, args=(ui, n, watched, rated), daemon=True)
    watchers.start()
    stop, done = threading.Event(), [0]
    planner = threading.Thread(target=keep_planning, args=(api, stop, done), daemon=True)
    await asyncio.sleep(WARM_UP_S)
    watching = time.monotonic()  # the viewers count from about now (their own WARM_UP_S)
    if plans:
        planner.start()
    built = await wait_for_panels(api, n + 1, BUILT_TIMEOUT_S)  # the viewers and the operator
    t1, cpu1 = time.monotonic(), cpu_seconds(pid)
    await asyncio.sleep(STEADY_S)
    cores = (cpu_seconds(pid) - cpu1) / (time.monotonic() - t1)
    t_newcomers, cpu_newcomers = time.monotonic(), cpu_seconds(pid)
    newcomers: list[Viewer] = []
    await probe(ui, t_newcomers + seconds, newcomers)
    newcomer_cores = (cpu_seconds(pid) - cpu_newcomers) / (time.monotonic() - t_newcomers)
    watched.set()
    stop.set()
    t2 = time.monotonic()
    counted_from, times = await asyncio.to_thread(rated.get, True, 120.0)
    watching = max(watching, counted_from)  # the viewers' process may have started counting later
    operated_result = await asyncio.to_thread(operated.get, True, 120.0)
    for process in (watchers, operator):
        await asyncio.to_thread(process.join, 10.0)
    if program is None:
        rates = rates_within(times, [(watching, t2)])
        cuts, gap, moved, own = operated_result
        outcome = Outcome("", cuts, rates, newcomers, alone, cores, done[0], moved, gap, own)
        outcome.newcomer_cores = newcomer_cores
        outcome.built = built - 1  # the operator's own panels are not a viewer's
        return outcome
    late_alone, late = windows(program, (t0, t0 + ALONE_S), (t1, t2))
    rates = rates_within(times, moving(program, watching, t2))
    outcome = Outcome("", [], rates, newcomers, alone, cores, done[0], 0.0, 0.0, 0, late_alone, late)
    outcome.ended = str(operated_result)
    outcome.newcomer_cores = newcomer_cores
    outcome.built = built - 1  # the operator's own panels are not a viewer's
    return outcome


def run(label: str, source: Path, n: int, seconds: float, plans: bool, program: bool) -> Outcome:
    if program:
        with pendant_with_program(source, "pendant-classroom-") as (ui, api, pid, steps):
            outcome = asyncio.run(measure(ui, api, pid, n, seconds, plans, steps))
    else:
        with pendant_from(source, "pendant-classroom-") as (ui, api, pid):
            outcome = asyncio.run(measure(ui, api, pid, n, seconds, plans, None))
    outcome.label = label
    return outcome


def row(name: str, cells: list[str]) -> None:
    print(f"{name:44}" + "".join(f"{c:>24}" for c in cells))


def program_rows(outcomes: list[Outcome]) -> None:
    lates = [(o.late_alone or Lateness([], []), o.late or Lateness([], [])) for o in outcomes]
    print("program steps late (ms): p50 / p99 / max (steps)")
    row("  the operator alone", [summary(alone.all) for alone, _ in lates])
    row("  with the viewers", [summary(late.all) for _, late in lates])
    row("  … outputs (the move's end polled /50 ms)", [summary(late.outputs) for _, late in lates])
    row("  … moves (after an output and a wait)", [summary(late.moves) for _, late in lates])
    row("the run's line after Stop", [o.ended[:22] for o in outcomes])


def program_ok(o: Outcome) -> bool:
    """No step later with the viewers than the latest with the operator alone + 50 ms."""
    alone, late = o.late_alone, o.late
    if alone is None or late is None or not late.all or not o.ended.startswith("Stopped"):
        return False
    return max(late.all) <= max(alone.all, default=0.0) + 0.05


def report(outcomes: list[Outcome], n: int, seconds: float, plans: bool, program: bool) -> None:
    load = "plans and pre-flights kept running, " if plans else ""
    doing = "running a program" if program else "holding J1+"
    print(f"{n} steady viewers + a newcomer every 2 s, {load}the operator {doing}, {seconds:.0f} s")
    print(f"{'':44}" + "".join(f"{o.label:>24}" for o in outcomes))
    if program:
        program_rows(outcomes)
    else:
        row("held jog cut (times)", [str(len(o.cuts)) for o in outcomes])
        row("… of which the operator had sent late (its own)", [str(o.operator_late_cuts) for o in outcomes])
        row("J1 moved while held (deg)", [f"{o.moved_deg:.1f}" for o in outcomes])
    row(
        "arm updates per viewer /s: min / median" + (" (moving)" if program else ""),
        [f"{min(o.rates):.1f} / {statistics.median(o.rates):.1f}" for o in outcomes],
    )
    for part in ("freeze", "panel"):
        cells = []
        for o in outcomes:
            times = [t for v in o.newcomers if (t := getattr(v, part)) is not None]
            missing = len(o.newcomers) - len(times)
            text = f"{percentile(times, 0.5):.2f} / {percentile(times, 0.95):.2f}" if times else "-"
            cells.append(text + (f" ({missing} never)" if missing else ""))
        row(f"newcomer {part} median / p95 s", cells)
    row(
        "pendant CPU: operator alone / with viewers",
        [f"{o.alone_cores:.2f} / {o.cores:.2f}" for o in outcomes],
    )
    row("pendant CPU with the newcomers too (cores)", [f"{o.newcomer_cores:.2f}" for o in outcomes])
    row("… steady viewers with panels built by then", [f"{o.built} of {n}" for o in outcomes])
    row("pendant CPU per viewer (cores)", [f"{(o.cores - o.alone_cores) / n:.4f}" for o in outcomes])
    if not program:
        row("operator: largest gap between holds sent ms", [f"{o.hold_gap_s * 1000:.0f}" for o in outcomes])
    if plans:
        row("plans + pre-flights answered", [str(o.plans) for o in outcomes])
    for o in outcomes:
        for cut in sorted(set(o.cuts))[:3]:
            print(f"  {o.label}: {cut}")
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    after = outcomes[-1]
    panels = [v.panel if v.panel is not None else 99.0 for v in after.newcomers]
    freeze = [v.freeze if v.freeze is not None else 99.0 for v in after.newcomers]
    ok = (
        (program_ok(after) if program else not after.cuts)
        and min(after.rates) >= 20
        and percentile(freeze, 0.95) <= 0.5
        and percentile(panels, 0.95) <= 3.0
        and (after.cores - after.alone_cores) / n <= 0.005
    )
    print(
        ("PASS" if ok else "MISS")
        + (" (targets: no step later than alone + 50 ms," if program else " (targets: 0 cuts,")
        + " every viewer >= 20/s, Freeze p95 <= 0.5 s, panel p95 <= 3 s,"
        " <= 0.005 core/viewer)"
    )


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--viewers", default="60", help="how many steady viewers; a list (1,20,60,100) runs each in turn"
    )
    parser.add_argument("--seconds", type=float, default=60.0)
    parser.add_argument("--plans", action="store_true", help="keep plans and pre-flights running too")
    parser.add_argument("--program", action="store_true", help="the operator runs a program, no jog")
    parser.add_argument("--baseline", help="a git revision to measure first (before), e.g. main")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="pendant-baseline-") as baseline:
        if args.baseline:
            archive = subprocess.run(
                ["git", "archive", args.baseline], cwd=REPO, check=True, capture_output=True
            ).stdout
            subprocess.run(["tar", "-x", "-C", baseline], input=archive, check=True)
        for n in (int(count) for count in args.viewers.split(",")):
            measured = (n, args.seconds, args.plans, args.program)
            outcomes = []
            if args.baseline:
                outcomes.append(run(f"before ({args.baseline})", Path(baseline), *measured))
            outcomes.append(run("this checkout", REPO, *measured))
            report(outcomes, n, args.seconds, args.plans, args.program)
            print(flush=True)
    return 0


if __name__ == "__main__":
    with contextlib.suppress(KeyboardInterrupt):
        raise SystemExit(main())
