"""Run a user's test project (files written to a temp folder) with pytest in a subprocess, as a user would:
the pulse_sim plugin loaded by name, this worktree's `pendant` first on the path."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from tests.support.launchers import REPO_ROOT

RUN_TIMEOUT_S = 300.0


def run_project(
    folder: Path, files: dict[str, str], *args: str, by_name: bool = True, site: Path | None = None
) -> subprocess.CompletedProcess[str]:
    """Write `files` into `folder` and run pytest there; returns the finished process (output in stdout).

    `by_name`: load the plugin with `-p pendant.testing` (else only installed entry points load it);
    `site`: a folder of installed distributions' metadata put on the path after the worktree."""
    for name, text in files.items():
        (folder / name).write_text(text, encoding="utf-8")
    path = [str(REPO_ROOT), *([str(site)] if site is not None else [])]
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(path)}
    env.pop("PYTEST_ADDOPTS", None)
    for name in [n for n in env if n.startswith("PYTEST_XDIST_")]:  # this suite's own worker, if any
        env.pop(name)
    plugin = ["-p", "pendant.testing"] if by_name else []
    return subprocess.run(
        [sys.executable, "-m", "pytest", *plugin, "-q", "-p", "no:cacheprovider", *args],
        cwd=folder,
        env=env,
        capture_output=True,
        text=True,
        timeout=RUN_TIMEOUT_S,
        check=False,
    )


def port_is_closed(url: str) -> bool:
    """Nothing listens at `url` any more (the connection is refused)."""
    import socket
    from urllib.parse import urlsplit

    parts = urlsplit(url)
    with socket.socket() as probe:
        return probe.connect_ex((parts.hostname or "", parts.port or 0)) != 0
