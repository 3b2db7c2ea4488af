"""`pendant run PROGRAM.json`: run a saved program without a browser (from a PLC script or a service).

    pendant run PROGRAM.json [--robot URL] [--loops N] [--model pulse75|pulse90] [--token TOKEN]

Against the controller at --robot (or a pendant's API, with its access token), else an embedded simulator on
the real clock. The runner is the page's (pendant.program.runner): the same plan, the same checks. Progress
goes to stdout, one line per step; a failure goes to stderr with the step and the controller's message.
Exit status: 0 finished, 1 a step failed (or Ctrl-C: the arm is frozen), 2 the file or the flags are refused.
Call steps open their programs from the program file's folder.
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Callable, Sequence
from pathlib import Path

import httpx

from pendant.access import TOKEN_HEADER
from pendant.controller import Controller
from pendant.paths import MODEL_NAMES
from pendant.program.describe import describe_step
from pendant.program.export import TOKEN_ENV
from pendant.program.files import ProgramFileError, ProgramStore, parse_program
from pendant.program.models import Program
from pendant.program.motion import PathPlanner
from pendant.program.plan import PlanError
from pendant.program.runner import ProgramRunner, RunProgress, RunState
from pendant.program.stop_watch import StopWatch
from pendant.program.tree import lines

EXIT_FAILED = 1
EXIT_REFUSED = 2


def parse_args(argv: Sequence[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(prog="pendant run", description="Run a saved program without a browser.")
    parser.add_argument("program", type=Path, help="a program file (.json) saved by the pendant")
    parser.add_argument("--robot", metavar="URL", help="the controller (default: an embedded simulator)")
    parser.add_argument("--loops", type=int, default=1, help="how many times (0: until Ctrl-C; default 1)")
    parser.add_argument("--model", choices=MODEL_NAMES, default="pulse75", help="simulated arm (no --robot)")
    parser.add_argument(
        "--token",
        default=os.environ.get(TOKEN_ENV),
        help=f"access token of a teach pendant exposed on the network (default: ${TOKEN_ENV})",
    )
    args = parser.parse_args(argv)
    if args.loops < 0:
        parser.error("--loops must be >= 0")
    return args


def make_controller(args: argparse.Namespace) -> Controller:
    if args.robot is None:
        from pendant.sim import MonotonicClock, SimController

        return SimController(model=args.model, clock=MonotonicClock())
    from pendant.remote import RemoteController

    return RemoteController(args.robot, client=http_client(args))


def http_client(args: argparse.Namespace) -> httpx.Client:
    from pendant.remote.client import DEFAULT_CONNECT_TIMEOUT_S, DEFAULT_READ_TIMEOUT_S

    token = (args.token or "").strip()
    return httpx.Client(
        timeout=httpx.Timeout(DEFAULT_READ_TIMEOUT_S, connect=DEFAULT_CONNECT_TIMEOUT_S),
        headers={"Accept-Encoding": "identity", **({TOKEN_HEADER: token} if token else {})},
    )


class ProgressPrinter:
    """One line per step the run reaches: "[loop 1/3] step 4/12: Move L to pick+offset @ 20%"."""

    def __init__(self, program: Program) -> None:
        self._listed = [line.step for line in lines(program.steps)]
        self._last: tuple[int | None, int] | None = None
        self._notice = ""

    def __call__(self, progress: RunProgress) -> None:
        if progress.notice != self._notice:
            self._notice = progress.notice
            print(progress.notice, file=sys.stderr, flush=True)
        if progress.state is not RunState.RUNNING or progress.step_index is None:
            return
        here = (progress.step_index, progress.loop)
        if here == self._last:
            return
        self._last = here
        index = progress.step_index
        what = describe_step(self._listed[index]) if index < len(self._listed) else ""
        loops = "∞" if progress.loops == 0 else str(progress.loops)
        print(f"[loop {progress.loop}/{loops}] step {index + 1}/{len(self._listed)}: {what}", flush=True)


def main(argv: Sequence[str] | None = None, planner_for: Callable[[str], PathPlanner] | None = None) -> int:
    """`pendant run`; `planner_for(model)` plans the program's planned Move J steps (given by the CLI:
    the planner sits above the program package)."""
    args = parse_args(argv)
    path: Path = args.program
    try:
        program = parse_program(path.read_bytes(), path.name)
    except OSError as error:
        print(f"Cannot read {path}: {error.strerror or error}", file=sys.stderr)
        return EXIT_REFUSED
    except ProgramFileError as error:
        print(str(error), file=sys.stderr)
        return EXIT_REFUSED
    controller = make_controller(args)
    planner = planner_for(args.model) if planner_for is not None else None
    runner = ProgramRunner(controller, load=ProgramStore(path.parent).load, planner=planner)
    runner.add_listener(ProgressPrinter(program))
    where = args.robot or f"simulated {args.model}"
    print(f"Running {program.name!r} ({path}) on {where}", flush=True)
    # Against a pendant: a stop it hears from anywhere ends this run too (a bare controller cannot say).
    watch = StopWatch(http_client(args), args.robot, runner.stop_heard) if args.robot else None
    if watch is not None:
        if watch.start():
            runner.hear_stops_now = watch.poll_now
        else:
            print("The controller does not report stops: only this run's own stops end it", file=sys.stderr)
    try:
        result = runner.run(program, args.loops)
    except PlanError as error:
        print(str(error), file=sys.stderr)
        return EXIT_REFUSED
    except KeyboardInterrupt:
        runner.stop()
        print("Interrupted: the arm is frozen", file=sys.stderr)
        return EXIT_FAILED
    finally:
        if watch is not None:
            watch.stop()
    if result.state in (RunState.FAILED, RunState.STOPPED):
        print(result.message, file=sys.stderr)
        return EXIT_FAILED
    print(f"{result.message}: {result.loop} loop(s)", flush=True)
    return 0
