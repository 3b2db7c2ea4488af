"""The `pendant` subcommands, each a `main(args) -> exit status` of the package that does the work,
imported only when run (`pendant check` starts in a fraction of the server's import time)."""

from __future__ import annotations

from collections.abc import Callable


def check(args: list[str]) -> int:
    """`pendant check URL`: wait until a PULSE API answers at URL (for CI scripts)."""
    from pendant.readiness import check_main

    return check_main(args)


def run(args: list[str]) -> int:
    """`pendant run PROGRAM.json ...`: a saved program, no browser."""
    from pendant.kinematics import ArmModel
    from pendant.planning.live import ControllerPlanner
    from pendant.program.headless import main as run_program

    return run_program(args, lambda model: ControllerPlanner(ArmModel.load(model)))


def diff(args: list[str]) -> int:
    """`pendant diff A.json B.json`: a program's changes (docs/history.md)."""
    from pendant.program import history_cli

    return history_cli.diff_main(args)


def history(args: list[str]) -> int:
    """`pendant history PROGRAM`: a program's versions (docs/history.md)."""
    from pendant.program import history_cli

    return history_cli.history_main(args)


def record(args: list[str]) -> int:
    """`pendant record --robot URL --seconds N`: a recording, no page."""
    from pendant.remote.record_cli import main as record_main

    return record_main(args)


def preflight(args: list[str]) -> int:
    """`pendant preflight PROGRAM.json ...`: checked on the twin, nothing moves."""
    from pendant.planning.command import main as preflight_program

    return preflight_program(args)


SUBCOMMANDS: dict[str, Callable[[list[str]], int]] = {
    "check": check,
    "run": run,
    "diff": diff,
    "history": history,
    "record": record,
    "preflight": preflight,
}
