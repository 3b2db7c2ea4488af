"""Client churn: while ~100 browsers connect and leave, how long does a new viewer wait for its page, and is a
held jog ever cut?

A real `pendant` process (simulator, UI and API on loopback). In a process of their own (so that they are
not what slows the measurement), `--churners` headless browsers connect and leave continuously, each as a
browser does: GET the page, open the websocket (viser's protocol), announce its camera, receive for a random
0.5-5 s, then leave, half of them politely (a close handshake), half by dropping the TCP connection.

Meanwhile, in this process:
- a new viewer, one after the other, measures from starting its page GET to having its page: the HTML, and
  on the websocket the scene's state (viser's replay: the arm's meshes and /tcp_frame) and the Freeze
  button. "Whole panel": until the last tab (the Dashboard's plots) has arrived as well.
- the operator (the first browser, so it has control) holds J1+ for the whole run, its page's worker's way:
  a GuiButtonHoldMessage every 50 ms (pendant/ui/page/client_page.js). A cut is a "Jog J1+ stopped: ..."
  line in GET /pendant/events; the operator then lets go and holds again, so every cut is counted.

`--baseline REV` runs the same measurement first against the pendant of git revision REV (an exported copy),
then against this checkout: before and after, side by side, in one run.

Run: .venv/bin/python benchmarks/churn.py [--churners 100] [--seconds 40] [--baseline REV]
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import math
import multiprocessing
import os
import random
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Coroutine, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import httpx
import websockets
import zstandard

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from benchmarks.viewers import cpu_seconds
from tests.support.headless_viewer import (
    HOLD_HZ,
    JogPad,
    decode_window,
    gui_update,
    hold_message,
    line_hold,
    line_release,
    open_hold_line,
    open_viewer,
    read_jog_pad,
)
from tests.support.ports import free_port
from tests.support.waiting import answers, wait_until

REPO = Path(__file__).resolve().parents[1]
START_TIMEOUT_S = 60.0
STAY_S = (0.5, 5.0)  # how long a churning browser stays
CONNECT_TIMEOUT_S = 30.0
PAGE_TIMEOUT_S = 30.0  # a new viewer still without its page after this counts as this long
PANEL_TIMEOUT_S = 30.0
PROBE_EVERY_S = 2.0  # a new viewer every 2 s, each measured on its own (up to PROBES_AT_ONCE at a time)
PROBES_AT_ONCE = 10
JOG_SPEED_PERCENT = 2.0  # J1 at 2.4 °/s: no joint limit within any run
LAG_PERIOD_S = 0.05
LATE_GAP_S = 0.15  # the operator's own gap between two confirmations that can end in a cut (200 ms deadman)
WARM_UP_S = 3.0
EVENTS_POLL_S = 0.5
SCENE_NODES = ("/tcp_frame", "/arm/visual/base_link_visual")


async def get_page(port: int) -> int:
    """GET / as a browser does (gzip accepted); the body's size. Raw HTTP/1.1: cheap for 100 clients."""
    reader, writer = await asyncio.open_connection("127.0.0.1", port)
    try:
        writer.write(
            f"GET / HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nAccept-Encoding: gzip\r\n"
            "Connection: close\r\n\r\n".encode()
        )
        body = await reader.read()  # to the end: the server closes after the page
        if not body.startswith(b"HTTP/1.1 200"):
            raise RuntimeError(f"page GET answered {body[:40]!r}")
        return len(body)
    finally:
        writer.close()


# --- the churning browsers (their own process) -------------------------------------------------------------


async def churning_browser(port: int, until: float, seed: int, counts: dict[str, int]) -> None:
    rng = random.Random(seed)
    await asyncio.sleep(rng.uniform(0, 2.0))  # not all at once
    while time.monotonic() < until:
        try:
            await get_page(port)
            async with asyncio.timeout(CONNECT_TIMEOUT_S):
                ws = await open_viewer(port)
            leave_at = time.monotonic() + rng.uniform(*STAY_S)
            while (left := leave_at - time.monotonic()) > 0:
                try:
                    frame = await asyncio.wait_for(ws.recv(), timeout=left)
                    counts["bytes"] += len(frame)
                except TimeoutError:
                    break
            if rng.random() < 0.5:
                await ws.close()
                counts["polite"] += 1
            else:
                ws.transport.abort()  # the TCP connection dropped: no close handshake
                counts["dropped"] += 1
        except (OSError, websockets.WebSocketException, TimeoutError, RuntimeError):
            counts["failed"] += 1
            await asyncio.sleep(0.2)


async def loop_lag(until: float, lags: list[float]) -> None:
    """How late this process's event loop wakes (its own load would show up as the pendant's slowness)."""
    while time.monotonic() < until:
        t = time.monotonic()
        await asyncio.sleep(LAG_PERIOD_S)
        lags.append(time.monotonic() - t - LAG_PERIOD_S)


async def churn(port: int, n: int, seconds: float) -> tuple[dict[str, int], list[float]]:
    until = time.monotonic() + seconds
    counts = {"polite": 0, "dropped": 0, "failed": 0, "bytes": 0}
    lags: list[float] = []
    await asyncio.gather(loop_lag(until, lags), *(churning_browser(port, until, i, counts) for i in range(n)))
    return counts, lags


def churn_process(port: int, n: int, seconds: float, results: multiprocessing.Queue) -> None:  # type: ignore[type-arg]
    t0, cpu0 = time.monotonic(), cpu_seconds(os.getpid())
    counts, lags = asyncio.run(churn(port, n, seconds))
    cores = (cpu_seconds(os.getpid()) - cpu0) / (time.monotonic() - t0)
    results.put((counts, sorted(lags)[int(0.95 * (len(lags) - 1))] if lags else 0.0, cores))


# --- the new viewers and the operator (this process) -------------------------------------------------------


@dataclass
class Deadline:
    """When the operator lets go (monotonic s): a time, brought forward if the benchmark is done sooner."""

    at: float

    def passed(self) -> bool:
        return time.monotonic() >= self.at


@dataclass
class Viewer:
    """One new viewer's times (s from starting its page GET); None: not within the timeouts."""

    html: float | None = None
    socket: float | None = None  # the websocket open
    scene: float | None = None  # viser's replay of the scene done (meshes, /tcp_frame)
    freeze: float | None = None  # the Freeze button
    panel: float | None = None  # the last tab's last element

    @property
    def page(self) -> float:
        """The page: HTML, scene and Freeze (PAGE_TIMEOUT_S when not within it)."""
        parts = (self.html, self.scene, self.freeze)
        return PAGE_TIMEOUT_S if any(p is None for p in parts) else max(p for p in parts if p is not None)


async def new_viewer(port: int) -> Viewer:
    t0 = time.monotonic()
    seen = Viewer()
    zstd = zstandard.ZstdDecompressor()
    try:
        async with asyncio.timeout(PAGE_TIMEOUT_S):
            await get_page(port)
            seen.html = time.monotonic() - t0
            ws = await open_viewer(port)
            seen.socket = time.monotonic() - t0
    except TimeoutError:
        return seen
    try:
        nodes: set[str] = set()
        deadline = t0 + PAGE_TIMEOUT_S + PANEL_TIMEOUT_S
        while (left := deadline - time.monotonic()) > 0 and seen.panel is None:
            if seen.page >= PAGE_TIMEOUT_S and time.monotonic() - t0 > PAGE_TIMEOUT_S:
                break
            try:
                frame = await asyncio.wait_for(ws.recv(), timeout=min(left, 1.0))
            except TimeoutError:
                continue
            now = time.monotonic() - t0
            for message in decode_window(frame, zstd):
                kind = message.get("type")
                nodes.add(str(message.get("name")))
                if kind == "ReplayDoneMessage" and all(n in nodes for n in SCENE_NODES):
                    seen.scene = now
                label = message.get("props", {}).get("label")
                if kind == "GuiButtonMessage" and label == "Freeze" and seen.freeze is None:
                    seen.freeze = now
                if kind == "GuiUplotMessage":  # the Dashboard's plots: the last tab's last element
                    seen.panel = now
        return seen
    finally:
        ws.transport.abort()


async def probe(port: int, until: float, viewers: list[Viewer]) -> None:
    slots = asyncio.Semaphore(PROBES_AT_ONCE)

    async def one() -> None:
        async with slots:
            viewers.append(await new_viewer(port))

    tasks = []
    while time.monotonic() < until:
        tasks.append(asyncio.create_task(one()))
        await asyncio.sleep(PROBE_EVERY_S)
    await asyncio.gather(*tasks)


class Operator:
    """The first browser (it has control): holds J1+ at HOLD_HZ; after a cut, lets go and holds again. Over
    the hold line when its pad names one (as client_page.js does), else over viser's websocket."""

    def __init__(self, port: int) -> None:
        self.port = port
        self.ws: websockets.ClientConnection | None = None
        self.line: websockets.ClientConnection | None = None
        self.pad: JogPad | None = None
        self.regrasp = asyncio.Event()
        self.largest_gap_s = 0.0  # between two confirmations sent: a gap on this side is not the pendant's
        self.late_sends: list[float] = []  # wall times of confirmations sent after a gap >= LATE_GAP_S
        self.cut_times: list[float] = []  # wall times of the cuts (the events' own)
        self.let_go_at = math.inf  # wall time the operator let go at the end (what follows is no cut)

    async def connect(self) -> None:
        self.ws = await open_viewer(self.port)
        self.pad = await read_jog_pad(self.ws, START_TIMEOUT_S)
        await self.ws.send(gui_update(self.pad.speed, JOG_SPEED_PERCENT))
        if self.pad.line is not None:
            self.line = await open_hold_line(self.pad)

    async def _send_hold(self) -> None:
        assert self.ws is not None and self.pad is not None
        if self.line is not None:
            await self.line.send(line_hold(self.pad.hold))
        else:
            await self.ws.send(hold_message(self.pad.hold))

    async def _send_stop(self) -> None:
        assert self.ws is not None and self.pad is not None
        if self.line is not None:
            await self.line.send(line_release(self.pad.stop))
        else:
            await self.ws.send(gui_update(self.pad.stop, True))

    async def hold(self, until: Deadline) -> None:
        assert self.ws is not None and self.pad is not None
        drain = asyncio.create_task(self._drain())
        next_at = sent_at = time.monotonic()
        while not until.passed():
            if self.regrasp.is_set():  # the jog was cut: let go, then press again
                self.regrasp.clear()
                await self._send_stop()
                await asyncio.sleep(0.3)
                next_at = sent_at = time.monotonic()
            await self._send_hold()
            sent_at, last = time.monotonic(), sent_at
            self.largest_gap_s = max(self.largest_gap_s, sent_at - last)
            if sent_at - last >= LATE_GAP_S:
                self.late_sends.append(time.time())
            next_at += 1.0 / HOLD_HZ
            await asyncio.sleep(max(0.0, next_at - time.monotonic()))
        # Its socket closes right after: a jog still pressed then ends as "control changed", not a cut.
        self.let_go_at = time.time()
        await self._send_stop()
        drain.cancel()
        await self.ws.close()
        if self.line is not None:
            await self.line.close()

    async def _drain(self) -> None:
        assert self.ws is not None
        with contextlib.suppress(websockets.ConnectionClosed):
            async for _ in self.ws:
                pass


async def watch_cuts(api: str, until: Deadline, operator: Operator, cuts: list[str]) -> None:
    since = time.time()
    async with httpx.AsyncClient(base_url=api, timeout=5.0) as client:
        while not until.passed():
            await asyncio.sleep(EVENTS_POLL_S)
            answer = await client.get("/pendant/events", params={"text": "stopped:", "since": since})
            found = [
                e
                for e in answer.json()["events"]
                if e["message"].startswith("Jog J1+ stopped")
                and not e["message"].endswith(": released")
                and not (e["message"].endswith(": control changed") and e["time"] >= operator.let_go_at)
            ]  # "released": the operator's own letting go before pressing again; "control changed" after
            # let_go_at: its socket closing at the end
            if found:
                since = max(e["time"] for e in found) + 1e-3
                cuts.extend(e["message"] for e in found)
                operator.cut_times.extend(e["time"] for e in found)
                operator.regrasp.set()


@dataclass
class Outcome:
    label: str
    viewers: list[Viewer]
    cuts: list[str]
    pendant_cores: float
    churn: dict[str, int]
    churn_lag_p95_s: float
    churn_cores: float
    probe_lag_p95_s: float
    moved_deg: float
    hold_gap_s: float


async def finish_early(until: Deadline, finish: Any) -> None:
    """Brings `until` forward to the moment `finish` (a multiprocessing Event) is set, if before it."""
    if await asyncio.to_thread(finish.wait, max(0.0, until.at - time.monotonic())):
        until.at = min(until.at, time.monotonic())


@dataclass
class OperatorJob:
    """What an operator process is given: the pendant's ports, how long to go on (or until `finish`, a
    multiprocessing Event, is set), and the queue for its "ready" and then its outcome."""

    ui_port: int
    api: str
    seconds: float
    results: Any  # a multiprocessing Queue
    finish: Any = None


async def operate(job: OperatorJob) -> tuple:  # type: ignore[type-arg]
    """The operator: connect (first, so it has control), then hold J1+ for the job's time; its cuts, its
    largest gap between two confirmations sent, and how far J1 went."""
    operator = Operator(job.ui_port)
    await operator.connect()
    async with httpx.AsyncClient(base_url=job.api, timeout=5.0) as client:
        j1_before = (await client.get("/pose")).json()["angles"][0]
        job.results.put("ready")
        until = Deadline(time.monotonic() + job.seconds)
        cuts: list[str] = []
        early = [finish_early(until, job.finish)] if job.finish is not None else []
        await asyncio.gather(operator.hold(until), watch_cuts(job.api, until, operator, cuts), *early)
        moved = (await client.get("/pose")).json()["angles"][0] - j1_before
    # A cut within a second after the operator itself sent late is this side's (a loaded machine), not the
    # pendant's: counted apart.
    own = sum(any(0 <= cut - late <= 1.0 for late in operator.late_sends) for cut in operator.cut_times)
    return cuts, operator.largest_gap_s, moved, own


def operator_process(
    operates: Callable[[OperatorJob], Coroutine[Any, Any, object]], job: OperatorJob
) -> None:
    """`operates` (this module's `operate`, or classroom_program's) in a process of its own, as a tablet's
    page would be on a device of its own (and ahead of the loaded machine's other processes where it may
    be), so its confirmations leave on time; its outcome goes to the job's queue, after its "ready"."""
    with contextlib.suppress(OSError):
        os.nice(-10)
    job.results.put(asyncio.run(operates(job)))


async def measure(ui_port: int, api: str, pid: int, churners: int, seconds: float) -> tuple:  # type: ignore[type-arg]
    spawn = multiprocessing.get_context("spawn")
    operated: multiprocessing.Queue = spawn.Queue()  # type: ignore[type-arg]
    operator = spawn.Process(
        target=operator_process,
        args=(operate, OperatorJob(ui_port, api, WARM_UP_S + seconds, operated)),
        daemon=True,
    )
    operator.start()
    assert await asyncio.to_thread(operated.get, True, START_TIMEOUT_S) == "ready"
    results: multiprocessing.Queue = spawn.Queue()  # type: ignore[type-arg]
    churner = spawn.Process(
        target=churn_process, args=(ui_port, churners, WARM_UP_S + seconds, results), daemon=True
    )
    start = time.monotonic()
    churner.start()
    until = start + WARM_UP_S + seconds
    lags: list[float] = []
    lag = asyncio.create_task(loop_lag(until, lags))
    await asyncio.sleep(WARM_UP_S)
    t0, cpu0 = time.monotonic(), cpu_seconds(pid)
    result: list[Viewer] = []
    await probe(ui_port, until, result)
    cpu = (cpu_seconds(pid) - cpu0) / (time.monotonic() - t0)
    await lag
    cuts, hold_gap, moved, _own = await asyncio.to_thread(operated.get, True, 60.0)
    counts, churn_lag, churn_cores = await asyncio.to_thread(results.get, True, 60.0)
    for process in (churner, operator):
        await asyncio.to_thread(process.join, 10.0)
    probe_lag = sorted(lags)[int(0.95 * (len(lags) - 1))] if lags else 0.0
    return result, cuts, cpu, counts, churn_lag, churn_cores, probe_lag, moved, hold_gap


@contextlib.contextmanager
def pendant_from(
    source: Path,
    prefix: str,
    launcher: Sequence[str] = ("-m", "pendant"),
    env: dict[str, str] | None = None,
) -> Iterator[tuple[int, str, int]]:
    """A pendant run from the checkout at `source` with a data folder of its own, started and answering:
    (page port, API URL, process id); stopped on the way out (SIGTERM, then kill). `launcher`: what the
    interpreter runs (the pendant's arguments follow); `env`: added to its environment."""
    ui_port, api_port = free_port(), free_port()
    api = f"http://127.0.0.1:{api_port}"
    with tempfile.TemporaryDirectory(prefix=prefix) as data:
        process = subprocess.Popen(
            [sys.executable, *launcher, "--ui-port", str(ui_port), "--api-port", str(api_port)],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            cwd=source,
            env={**os.environ, "PYTHONPATH": str(source), "PENDANT_DATA_DIR": data, **(env or {})},
        )
        try:
            wait_until(lambda: answers(f"{api}/pose"), START_TIMEOUT_S, what="the API answering")
            wait_until(lambda: answers(f"http://127.0.0.1:{ui_port}/"), START_TIMEOUT_S, what="the page")
            yield ui_port, api, process.pid
        finally:
            process.terminate()
            try:
                process.wait(timeout=10)
            except subprocess.TimeoutExpired:
                process.kill()


def run(label: str, source: Path, churners: int, seconds: float) -> Outcome:
    with pendant_from(source, "pendant-churn-") as (ui_port, api, pid):
        outcome = asyncio.run(measure(ui_port, api, pid, churners, seconds))
    return Outcome(label, *outcome)


def percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, round(q * (len(ordered) - 1)))]


def report(outcomes: list[Outcome], churners: int, seconds: float) -> None:
    print(
        f"{churners} browsers connecting and leaving (each stays {STAY_S[0]}-{STAY_S[1]} s), {seconds:.0f} s"
    )
    columns = [o.label for o in outcomes]
    print(f"{'':44}" + "".join(f"{c:>22}" for c in columns))

    def row(name: str, cells: list[str]) -> None:
        print(f"{name:44}" + "".join(f"{c:>22}" for c in cells))

    row("new viewers measured", [str(len(o.viewers)) for o in outcomes])
    for name, q in (("median", 0.5), ("p95", 0.95), ("max", 1.0)):
        row(
            f"page (HTML, scene, Freeze) {name} s",
            [f"{percentile([v.page for v in o.viewers], q):.2f}" for o in outcomes],
        )
    for part in ("html", "socket", "scene", "freeze", "panel"):
        cells = []
        for o in outcomes:
            times = [t for v in o.viewers if (t := getattr(v, part)) is not None]
            missing = len(o.viewers) - len(times)
            text = f"{percentile(times, 0.5):.2f} / {percentile(times, 0.95):.2f}" if times else "-"
            cells.append(text + (f" ({missing} never)" if missing else ""))
        row(f"  {part} median / p95 s", cells)
    row("held jog cut (times)", [str(len(o.cuts)) for o in outcomes])
    row("J1 moved while held (deg)", [f"{o.moved_deg:.1f}" for o in outcomes])
    row("pendant CPU (cores)", [f"{o.pendant_cores:.2f}" for o in outcomes])
    row(
        "churners: left polite / dropped / failed",
        [f"{o.churn['polite']}/{o.churn['dropped']}/{o.churn['failed']}" for o in outcomes],
    )
    row(
        "churn process: CPU cores, loop lag p95 ms",
        [f"{o.churn_cores:.2f}, {o.churn_lag_p95_s * 1000:.0f}" for o in outcomes],
    )
    row("probe loop lag p95 ms", [f"{o.probe_lag_p95_s * 1000:.0f}" for o in outcomes])
    row("operator: largest gap between holds sent ms", [f"{o.hold_gap_s * 1000:.0f}" for o in outcomes])
    for o in outcomes:
        for cut in sorted(set(o.cuts))[:5]:
            print(f"  {o.label}: {cut}")
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    after = outcomes[-1]
    ok = percentile([v.page for v in after.viewers], 0.95) <= 3.0 and not after.cuts
    print(("PASS" if ok else "MISS") + " (target: page p95 <= 3 s, no jog cut)")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--churners", type=int, default=100)
    parser.add_argument("--seconds", type=float, default=40.0)
    parser.add_argument("--baseline", help="a git revision to measure first (before), e.g. HEAD~1")
    args = parser.parse_args()
    outcomes = []
    with tempfile.TemporaryDirectory(prefix="pendant-baseline-") as baseline:
        if args.baseline:
            archive = subprocess.run(
                ["git", "archive", args.baseline], cwd=REPO, check=True, capture_output=True
            ).stdout
            subprocess.run(["tar", "-x", "-C", baseline], input=archive, check=True)
            outcomes.append(run(f"before ({args.baseline})", Path(baseline), args.churners, args.seconds))
        outcomes.append(run("this checkout", REPO, args.churners, args.seconds))
    report(outcomes, args.churners, args.seconds)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
