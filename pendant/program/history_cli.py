"""`pendant diff A B` and `pendant history PROGRAM`: a program's versions and changes on the command line.

pendant diff A.json B.json          what changed from A to B, in the operator's words
pendant diff pick.json@~1 pick.json  a version of a file (`@` a version id, or ~N: N versions before the
                                     newest) against the file as it is now
pendant history PROGRAM [--programs DIR] [--limit N]
                                    the versions of PROGRAM (a name in the programs folder, or a .json
                                    file's path), newest first: id, time, who, summary
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

from pendant.program.diff import diff_programs
from pendant.program.files import SUFFIX, ProgramFileError, parse_program, programs_dir, sanitize_name
from pendant.program.history import MAX_VERSIONS, HistoryError, ProgramHistory
from pendant.program.models import Program

EXIT_REFUSED = 2  # like argparse's usage errors: the command could not do what was asked


def _split(argument: str) -> tuple[Path, str | None]:
    """`pick.json@abc123` -> (pick.json, "abc123"); a plain path -> (path, None)."""
    path, at, revision = argument.rpartition("@")
    if at and path and ("/" not in revision):
        return Path(path), revision
    return Path(argument), None


def _revision(history: ProgramHistory, file_name: str, revision: str) -> str:
    """A version id as given, or ~N: the version N before the newest of `file_name`."""
    if not revision.startswith("~"):
        return revision
    try:
        back = int(revision[1:] or "1")
    except ValueError:
        raise HistoryError(f"{revision!r} is not a version: use an id or ~N (N versions back)") from None
    versions = history.versions(file_name, limit=back + 1)
    if back < 0 or back >= len(versions):
        raise HistoryError(f"{file_name} has {len(versions)} versions: there is no {revision}")
    return versions[back].commit


def read_program(argument: str) -> Program:
    """The program a command-line argument names: a file, or `file@version` from its folder's history."""
    path, revision = _split(argument)
    if revision is None:
        try:
            return parse_program(path.read_bytes(), str(path))
        except OSError as error:
            raise ProgramFileError(f"{path} cannot be read: {error.strerror or error}") from error
    history = ProgramHistory(path.parent)
    version, data = history.read(path.name, _revision(history, path.name, revision))
    return parse_program(data, f"{path}@{version.short}")


def diff_main(argv: Sequence[str]) -> int:
    parser = argparse.ArgumentParser(
        prog="pendant diff", description="What changed from program A to program B, in words."
    )
    parser.add_argument("old", metavar="A", help="a program file, or FILE@VERSION (an id, or ~N)")
    parser.add_argument("new", metavar="B", help="a program file, or FILE@VERSION (an id, or ~N)")
    args = parser.parse_args(argv)
    try:
        change = diff_programs(read_program(args.old), read_program(args.new))
    except (ProgramFileError, HistoryError) as error:
        print(f"pendant diff: {error}", file=sys.stderr)
        return EXIT_REFUSED
    if not change.changed:
        print("No changes.")
    for line in change.lines:
        print(line)
    return 0


def history_main(argv: Sequence[str]) -> int:
    parser = argparse.ArgumentParser(
        prog="pendant history", description="The saved versions of a program, newest first."
    )
    parser.add_argument("program", metavar="PROGRAM", help="a program's name, or the path of its .json file")
    parser.add_argument("--programs", metavar="DIR", help="the programs folder (default: as `pendant`)")
    parser.add_argument(
        "--limit", type=int, default=MAX_VERSIONS, metavar="N", help="at most N versions (%(default)s)"
    )
    args = parser.parse_args(argv)
    if not 1 <= args.limit <= MAX_VERSIONS:
        parser.error(f"--limit is 1 to {MAX_VERSIONS}")
    try:
        folder, file_name = _locate(args.program, args.programs)
        versions = ProgramHistory(folder).versions(file_name, args.limit)
    except (ProgramFileError, HistoryError) as error:
        print(f"pendant history: {error}", file=sys.stderr)
        return EXIT_REFUSED
    if not versions:
        print(f"{folder / file_name}: no versions in the history yet", file=sys.stderr)
        return EXIT_REFUSED
    for v in versions:
        print(f"{v.short}  {v.time:%Y-%m-%d %H:%M:%S} UTC  {v.who}  {v.summary}")
    return 0


def _locate(program: str, folder: str | None) -> tuple[Path, str]:
    """(programs folder, file name) of PROGRAM: a path to a .json file, or a name in the folder."""
    path = Path(program)
    if folder is None and (program.endswith(SUFFIX) and (path.parent != Path() or path.exists())):
        return path.parent, path.name
    return (Path(folder) if folder else programs_dir()), sanitize_name(program) + SUFFIX
