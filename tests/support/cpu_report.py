"""`pytest --cpu-report=FILE`: the CPU each test costs, to find what to make cheaper (issue 36: on a 2-core
machine the suite's wall time is at least its CPU over two).

Wall durations (`--durations`) mix what a test costs with what the machine's other work costs it; CPU
seconds do not. Each phase (set-up, call, tear-down) is charged this process's CPU plus that of the child
processes that ended during it, plus what its live descendants spent meanwhile (so a pendant started by a
fixture is charged to each phase as it spends, and only its last part to the tear-down that stops it), read
from /proc: Chromium above all (its processes belong to Playwright's driver, never our children, and they draw
the 3D view in software). One tab-separated line per phase, appended to FILE (one file for every xdist
worker): CPU seconds, of which Chromium's, wall seconds, phase, test id.
"""

from __future__ import annotations

import os
import resource
import time
from collections.abc import Generator
from pathlib import Path
from typing import NamedTuple

import pytest

TICKS_PER_S = os.sysconf("SC_CLK_TCK")
CHROMIUM = "chromium"  # the name (comm) of every Chromium process


def _cpu_seconds() -> float:
    own = resource.getrusage(resource.RUSAGE_SELF)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


class Descendant(NamedTuple):
    command: str
    cpu_s: float  # its own and that of the children it reaped
    our_child: bool  # once it ends, RUSAGE_CHILDREN has its whole CPU


def descendants() -> dict[int, Descendant]:
    """This process's live descendants, read from /proc (benchmarks/idle_page.py reads Chromium's so too)."""
    parent_of: dict[int, int] = {}
    read: dict[int, tuple[str, float]] = {}
    for name in os.listdir("/proc"):
        if not name.isdigit():
            continue
        try:
            with open(f"/proc/{name}/stat", encoding="utf-8", errors="replace") as stat:
                text = stat.read()
        except OSError:
            continue  # ended meanwhile
        fields = text[text.rindex(")") + 2 :].split()
        pid = int(name)
        parent_of[pid] = int(fields[1])
        # utime, stime, cutime, cstime
        read[pid] = (
            text[text.index("(") + 1 : text.rindex(")")],
            sum(int(f) for f in fields[11:15]) / TICKS_PER_S,
        )
    me = os.getpid()
    found: dict[int, Descendant] = {}
    for pid, (command, cpu_s) in read.items():
        ancestor = parent_of[pid]
        while ancestor not in (0, 1, me):
            ancestor = parent_of.get(ancestor, 0)
        if ancestor == me:
            found[pid] = Descendant(command, cpu_s, parent_of[pid] == me)
    return found


def _spent_meanwhile(before: dict[int, Descendant], after: dict[int, Descendant]) -> tuple[float, float]:
    """CPU seconds the descendants spent between two readings, in all and Chromium's. One that ended takes
    its last seconds with it (unless its parent reaped it, and is read): the figures are floors. Our own
    child that ended is in RUSAGE_CHILDREN, whole: what was already read of it comes off."""
    every = chromium = 0.0
    for pid, now in after.items():
        then = before.get(pid)
        spent = now.cpu_s - (then.cpu_s if then is not None and then.command == now.command else 0.0)
        every += spent
        chromium += spent if now.command == CHROMIUM else 0.0
    every -= sum(then.cpu_s for pid, then in before.items() if then.our_child and pid not in after)
    return every, chromium


class CpuReport:
    def __init__(self, path: Path) -> None:
        self.path = path

    def _charged(self, phase: str, item: pytest.Item) -> Generator[None]:
        cpu, wall = _cpu_seconds(), time.monotonic()
        before = descendants()
        try:
            yield
        finally:
            theirs, drawn = _spent_meanwhile(before, descendants())
            spent = _cpu_seconds() - cpu + theirs
            line = f"{spent:.3f}\t{drawn:.3f}\t{time.monotonic() - wall:.3f}\t{phase}\t{item.nodeid}\n"
            with self.path.open("a", encoding="utf-8") as report:
                report.write(line)

    @pytest.hookimpl(wrapper=True)
    def pytest_runtest_setup(self, item: pytest.Item) -> Generator[None]:
        return (yield from self._charged("setup", item))

    @pytest.hookimpl(wrapper=True)
    def pytest_runtest_call(self, item: pytest.Item) -> Generator[None]:
        return (yield from self._charged("call", item))

    @pytest.hookimpl(wrapper=True)
    def pytest_runtest_teardown(self, item: pytest.Item) -> Generator[None]:
        return (yield from self._charged("teardown", item))


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption("--cpu-report", metavar="FILE", help="append each test phase's CPU seconds to FILE")


def pytest_configure(config: pytest.Config) -> None:
    path = config.getoption("--cpu-report")
    if path:
        config.pluginmanager.register(CpuReport(Path(path)), "cpu-report")
