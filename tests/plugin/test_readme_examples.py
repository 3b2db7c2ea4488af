"""The two example tests of README's "Testing your robot code" run as a user's project and pass."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from tests.support.launchers import REPO_ROOT

from .project import run_project

pytestmark = [pytest.mark.sdk, pytest.mark.slow]

MAX_EXAMPLE_LINES = 20


def readme_examples() -> list[str]:
    readme = (REPO_ROOT / "README.md").read_text(encoding="utf-8")
    section = readme.split("## Testing your robot code", 1)[1].split("\n## ", 1)[0]
    return re.findall(r"```python\n(.*?)```", section, flags=re.DOTALL)


def test_the_sdk_and_httpx_examples_pass(tmp_path: Path) -> None:
    sdk, plain = readme_examples()
    assert "from pulseapi import" in sdk and "import httpx" in plain
    assert all(len(example.splitlines()) < MAX_EXAMPLE_LINES for example in (sdk, plain))
    files = {"pytest.ini": "[pytest]\n", "test_sdk_example.py": sdk, "test_httpx_example.py": plain}
    run = run_project(tmp_path, files)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "2 passed" in run.stdout
