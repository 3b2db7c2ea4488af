"""`pendant preflight PROGRAM.json`: check a program on the digital twin, for scripts and CI.

    pendant preflight PROGRAM.json [--robot URL] [--cell CELL.json] [--input N=HIGH ...] [--passes N]
                      [--model pulse75|pulse90] [--token TOKEN] [--json]

The twin is seeded from the controller at --robot with GET requests only (the arm does not move and
nothing is sent to it), else from a simulator at power-on. --cell checks against that cell file instead of
the controller's cell. Exit status: 0 every step passes, 1 a step fails, 2 the file, the flags or the
controller are refused (nothing checked).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from collections.abc import Sequence
from pathlib import Path

from pendant.cell.file import CellFileError, parse_cell
from pendant.controller import ControllerError
from pendant.controller.types import INPUT_PORTS, SignalLevel
from pendant.paths import MODEL_NAMES
from pendant.planning.preflight import MAX_LOOP_PASSES, PreflightRefused, preflight
from pendant.planning.report import PreflightReport
from pendant.planning.twin import TwinSeed, read_seed
from pendant.program.export import TOKEN_ENV
from pendant.program.files import ProgramFileError, ProgramStore, parse_program
from pendant.program.headless import make_controller

EXIT_FAILED = 1
EXIT_REFUSED = 2


class _Refused(Exception):
    pass


def parse_input(text: str) -> tuple[int, SignalLevel]:
    """ "2=HIGH" -> (2, HIGH); argparse.ArgumentTypeError naming what is wrong."""
    port_text, _, level_text = text.partition("=")
    try:
        port, level = int(port_text), SignalLevel(level_text.strip().upper())
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: expected PORT=HIGH or PORT=LOW, e.g. 1=HIGH") from None
    if port not in INPUT_PORTS:
        raise argparse.ArgumentTypeError(
            f"{text!r}: inputs are numbered {min(INPUT_PORTS)}-{max(INPUT_PORTS)}"
        )
    return port, level


def parse_args(argv: Sequence[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(
        prog="pendant preflight", description="Check a program on the digital twin before it runs on the arm."
    )
    parser.add_argument("program", type=Path, help="a program file (.json) saved by the pendant")
    parser.add_argument("--robot", metavar="URL", help="seed the twin from this controller (GETs only)")
    parser.add_argument("--cell", type=Path, metavar="CELL.json", help="check against this cell file")
    parser.add_argument(
        "--input",
        type=parse_input,
        action="append",
        default=[],
        metavar="N=LEVEL",
        help="assume digital input N at HIGH or LOW (default: as the arm reads it now)",
    )
    parser.add_argument("--passes", type=int, default=1, help="passes of each while/until loop (default 1)")
    parser.add_argument("--model", choices=MODEL_NAMES, default="pulse75", help="the arm's model")
    parser.add_argument("--token", default=os.environ.get(TOKEN_ENV), help="a pendant's access token")
    parser.add_argument("--json", action="store_true", help="print the report as JSON")
    args = parser.parse_args(argv)
    if not 0 <= args.passes <= MAX_LOOP_PASSES:
        parser.error(f"--passes must be 0 to {MAX_LOOP_PASSES}")
    return args


def _seed(args: argparse.Namespace) -> TwinSeed:
    try:
        seed = read_seed(make_controller(args))
    except ControllerError as error:
        where = args.robot or "the simulator"
        raise _Refused(f"Cannot read the arm at {where}: {error.message}") from error
    if args.cell is None:
        return seed
    try:
        cell = parse_cell(args.cell.read_bytes(), args.cell.name)
    except OSError as error:
        raise _Refused(f"Cannot read {args.cell}: {error.strerror or error}") from error
    except CellFileError as error:
        raise _Refused(str(error)) from error
    return seed.with_cell(cell.obstacles, cell.tool_shape)


def print_report(report: PreflightReport) -> None:
    for step in report.steps:
        mark = "ok  " if step.ok and step.checked else "FAIL" if not step.ok and step.checked else "--  "
        extra = [f"{step.duration_s:6.2f} s"]
        if step.min_clearance_mm is not None:
            extra.append(
                f"clearance {step.min_clearance_mm:.0f} mm ({step.closest_link}, {step.closest_obstacle!r})"
            )
        if step.reason or step.note:
            extra.append(step.reason or step.note or "")
        print(f"{mark} {step.line:>4}  {step.step}  " + "  ".join(extra))
    for port, assumed in sorted(report.assumed_inputs.items()):
        print(f"Assumed DI{port} {assumed.level.value} ({assumed.why})")
    for note in report.notes:
        print(f"Note: {note}")
    print(report.summary)


def main(argv: Sequence[str] | None = None) -> int:
    args = parse_args(argv)
    path: Path = args.program
    try:
        program = parse_program(path.read_bytes(), path.name)
        seed = _seed(args)
        report = preflight(
            program,
            seed,
            model=args.model,
            load=ProgramStore(path.parent).load,
            inputs=dict(args.input),
            loop_passes=args.passes,
        )
    except OSError as error:
        print(f"Cannot read {path}: {error.strerror or error}", file=sys.stderr)
        return EXIT_REFUSED
    except (ProgramFileError, PreflightRefused, _Refused) as error:
        print(str(error), file=sys.stderr)
        return EXIT_REFUSED
    if args.json:
        print(json.dumps(report.as_json(), indent=2))
    else:
        print_report(report)
    return 0 if report.ok else EXIT_FAILED
