"""The whole suite's count after `make test`'s two passes (the parallel one and the measuring one): reads
their JUnit XML reports and prints one closing line, `suite: N passed, N failed` (skips and errors added
when there are any), so the total is not two numbers to add up."""

from __future__ import annotations

import sys
import xml.etree.ElementTree as ET
from pathlib import Path


def counts(report: Path) -> dict[str, int]:
    """tests, failures, errors and skipped of one JUnit XML report (all its suites); zeros if it is missing
    (that pass did not run)."""
    totals = {"tests": 0, "failures": 0, "errors": 0, "skipped": 0}
    if not report.exists():
        return totals
    root = ET.parse(report).getroot()
    suites = [root] if root.tag == "testsuite" else list(root.iter("testsuite"))
    for suite in suites:
        for key in totals:
            totals[key] += int(suite.get(key, "0"))
    return totals


def main(paths: list[str]) -> int:
    totals = {"tests": 0, "failures": 0, "errors": 0, "skipped": 0}
    for path in paths:
        for key, value in counts(Path(path)).items():
            totals[key] += value
    failed = totals["failures"]
    passed = totals["tests"] - failed - totals["errors"] - totals["skipped"]
    line = f"suite: {passed} passed, {failed} failed"
    if totals["skipped"]:
        line += f", {totals['skipped']} skipped"
    if totals["errors"]:
        line += f", {totals['errors']} errors"
    print(line)
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
