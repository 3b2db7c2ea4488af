"""Why a test that was run again (pytest-rerunfailures, `--reruns`) failed its first time.

pytest-rerunfailures names a rerun test (`RERUN id` with `-rR`) but prints nothing of its first failure, so
a test that fails now and then in a full run and passes on its rerun left no trace of why (CI, 2 Dec:
test_jog_hold's Space hold). At the end of the run, each first failure's error and the last lines of its
traceback, under "why the rerun tests failed first".
"""

from __future__ import annotations

import pytest

TAIL_LINES = 30  # the error and the frames nearest it: what a flaky test needs to be understood
# The sections tests/browser/conftest.py adds to a failed test's report, shown with its rerun too.
PAGES_SECTION = "pages when it failed"
PENDANT_SECTION = "what its pendant said last"
OURS = (PAGES_SECTION, PENDANT_SECTION)


def _tail(text: str) -> str:
    lines = text.rstrip().splitlines()
    kept = lines[-TAIL_LINES:]
    return "\n".join((["..."] if len(lines) > len(kept) else []) + kept)


def pytest_terminal_summary(terminalreporter: pytest.TerminalReporter) -> None:
    reruns: list[pytest.TestReport] = terminalreporter.stats.get("rerun", [])
    if not reruns:
        return
    terminalreporter.section("why the rerun tests failed first")
    for report in reruns:
        terminalreporter.write_line(f"--- {report.nodeid} ({report.when}, {report.duration:.1f} s)")
        terminalreporter.write_line(_tail(report.longreprtext) or "(no traceback kept)")
        for title, content in report.sections:
            if title in OURS:  # what the failure hooks added (the pages, the pendant), not captured output
                terminalreporter.write_line(f"- {title}:\n{content}")
