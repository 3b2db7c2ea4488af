"""The example tests of docs/testing-your-code.md run as a user's project and pass."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from tests.support.launchers import REPO_ROOT
from tests.support.user_project import run_project

pytestmark = [pytest.mark.sdk, pytest.mark.slow]

MAX_EXAMPLE_LINES = 20


PAGE = REPO_ROOT / "docs" / "testing-your-code.md"
CELL = REPO_ROOT / "examples" / "cell.json"  # the cell file the page's third example names


def readme_examples() -> list[str]:
    return re.findall(r"```python\n(.*?)```", PAGE.read_text(encoding="utf-8"), flags=re.DOTALL)


def test_the_sdk_httpx_stop_and_cell_examples_pass(tmp_path: Path) -> None:
    sdk, plain, stop_and_cell = readme_examples()
    assert "from pulseapi import" in sdk and "import httpx" in plain and "protective_stop" in stop_and_cell
    assert all(len(example.splitlines()) < MAX_EXAMPLE_LINES for example in (sdk, plain, stop_and_cell))
    files = {
        "pytest.ini": "[pytest]\n",
        "test_sdk_example.py": sdk,
        "test_httpx_example.py": plain,
        "test_stop_and_cell_example.py": stop_and_cell,
        "cell.json": CELL.read_text(encoding="utf-8"),
    }
    run = run_project(tmp_path, files)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "4 passed" in run.stdout
