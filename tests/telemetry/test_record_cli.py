"""`pendant record --robot URL --seconds N` as a script runs it: a real pendant to record, the command as a
real process; the files are the Dashboard's, in the data folder's recordings/; refusals say why."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

from mcap.reader import make_reader

from tests.support import preloaded
from tests.support.launchers import REPO_ROOT, child_env, pendant_command, running_pendant
from tests.support.ports import free_port

RUN_TIMEOUT_S = 120.0


def record(*args: str) -> subprocess.CompletedProcess[str]:
    return preloaded.run(
        pendant_command("record", *args),
        cwd=REPO_ROOT,
        env=child_env(),
        capture_output=True,
        text=True,
        timeout=RUN_TIMEOUT_S,
    )


def test_a_headless_recording_of_an_arm(tmp_path: Path) -> None:
    with running_pendant("--data", str(tmp_path / "arm")) as arm:
        done = record("--robot", arm, "--seconds", "5", "--name", "ci-run", "--data", str(tmp_path))
        assert done.returncode == 0, done.stderr
        taken = record("--robot", arm, "--seconds", "1", "--name", "ci-run", "--data", str(tmp_path))
        bad = record("--robot", arm, "--seconds", "1", "--name", "../up", "--data", str(tmp_path))
    mcap = tmp_path / "recordings" / "pendant-ci-run.mcap"
    assert str(mcap) in done.stdout and "samples" in done.stdout, done.stdout
    with mcap.open("rb") as stream:
        joints = [
            json.loads(message.data)
            for _, channel, message in make_reader(stream).iter_messages()
            if channel.topic == "/joints"
        ]
    assert len(joints) >= 5 and joints[0]["name"] == [f"J{i}" for i in range(1, 7)]
    assert (tmp_path / "recordings" / "pendant-ci-run.csv").exists()
    assert taken.returncode == 2 and "already exists" in taken.stderr, taken.stderr
    assert bad.returncode == 2 and "Bad recording name" in bad.stderr, bad.stderr


def test_an_arm_that_does_not_answer_is_said_and_nothing_is_written(tmp_path: Path) -> None:
    nobody = f"http://127.0.0.1:{free_port()}"
    done = record("--robot", nobody, "--seconds", "1", "--data", str(tmp_path))
    assert done.returncode == 2 and f"cannot read the arm at {nobody}" in done.stderr, done.stderr
    assert not (tmp_path / "recordings").exists()
