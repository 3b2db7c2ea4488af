"""`pytest --cpu-report=FILE`: the CPU each test costs, to find what to make cheaper (issue 36: on a 2-core
machine the suite's wall time is at least its CPU over two).

Wall durations (`--durations`) mix what a test costs with what the machine's other work costs it; CPU
seconds do not. Each phase (set-up, call, tear-down) is charged this process's CPU plus that of the child
processes that ended during it (a pendant started by a fixture is charged to the tear-down that stops it,
so the module's first or last test carries it). One tab-separated line per phase, appended to FILE (one
file for every xdist worker): CPU seconds, wall seconds, phase, test id.
"""

from __future__ import annotations

import resource
import time
from collections.abc import Generator
from pathlib import Path

import pytest


def _cpu_seconds() -> float:
    own = resource.getrusage(resource.RUSAGE_SELF)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


class CpuReport:
    def __init__(self, path: Path) -> None:
        self.path = path

    def _charged(self, phase: str, item: pytest.Item) -> Generator[None]:
        cpu, wall = _cpu_seconds(), time.monotonic()
        try:
            yield
        finally:
            line = f"{_cpu_seconds() - cpu:.3f}\t{time.monotonic() - wall:.3f}\t{phase}\t{item.nodeid}\n"
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
