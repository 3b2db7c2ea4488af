"""A test that fails once and passes on its rerun: the run's end says why it failed the first time (the
flaky tests of a full run were named but never explained). pytest in a subprocess, on a project in a temp
folder, as `make test` runs it (`--reruns 1`, on an xdist worker)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from tests.support.launchers import child_env

FLAKY_TEST = """
from pathlib import Path

def test_a_hold_that_is_cut_once():
    tried = Path(__file__).with_name("tried")
    first = not tried.exists()
    tried.write_text("once")
    assert not first, "the deadman cut the hold after 0.42 s"
"""


def test_the_end_of_the_run_says_why_a_rerun_test_failed_first(tmp_path: Path) -> None:
    (tmp_path / "pytest.ini").write_text("[pytest]\n")
    (tmp_path / "test_flaky.py").write_text(FLAKY_TEST)
    run = subprocess.run(
        [
            sys.executable,
            "-m",
            "pytest",
            "-q",
            "-p",
            "no:cacheprovider",
            "-p",
            "tests.support.rerun_report",
            "--reruns",
            "1",
            "-n",
            "1",
            "-rR",
            "test_flaky.py",
        ],
        cwd=tmp_path,
        env=child_env(),  # this checkout first on PYTHONPATH: the plugin is importable
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert run.returncode == 0, run.stdout + run.stderr  # it passed on its rerun
    summary = run.stdout.split("why the rerun tests failed first", 1)
    assert len(summary) == 2, run.stdout
    assert "test_flaky.py::test_a_hold_that_is_cut_once (call" in summary[1]
    assert "the deadman cut the hold after 0.42 s" in summary[1]
