"""The suite's pendants are forked from a preloaded interpreter (tests/support/preloaded): what they say,
how they end, their limits and their folder are those of a pendant exec'd by a shell, or the suite would
test something no user runs."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from tests.support.launchers import REPO_ROOT, child_env, pendant_command
from tests.support.ports import LOOPBACK, free_port
from tests.support.preloaded import client
from tests.support.waiting import SAFETY_NET_S, answers, wait_until

RUN_TIMEOUT_S = 60.0


@pytest.fixture(autouse=True)
def forking(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv(client.EXEC_ENV, raising=False)  # whatever the run asks, these tests fork


def test_popen_has_the_shape_the_forked_process_overrides() -> None:
    # Fails when a new Python moves Popen's private start: then every pendant would be exec'd instead.
    assert client.preloading_fits()


@pytest.mark.parametrize(
    "args",
    [
        ["diff", "--help"],
        ["--no-ui", "--bogus"],
        ["history", "pick"],
        ["check", "http://127.0.0.1:9", "--timeout", "0"],
    ],
)
def test_a_forked_pendant_says_and_returns_what_an_execd_one_does(args: list[str], tmp_path: Path) -> None:
    env = child_env({"PENDANT_PROGRAMS_DIR": str(tmp_path)})
    execd = subprocess.run(
        pendant_command(*args), cwd=tmp_path, env=env, capture_output=True, text=True, timeout=RUN_TIMEOUT_S
    )
    forked = client.popen(
        pendant_command(*args),
        cwd=tmp_path,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    assert isinstance(forked, client.ForkedProcess)
    with forked:
        stdout, stderr = forked.communicate(timeout=RUN_TIMEOUT_S)
    assert (forked.returncode, stdout, stderr) == (execd.returncode, execd.stdout, execd.stderr)


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGKILL])
def test_a_forked_pendant_serves_within_its_limits_and_ends_on_a_signal(
    sig: signal.Signals, tmp_path: Path
) -> None:
    port = free_port()
    command = pendant_command("--no-ui", "--host", LOOPBACK, "--api-port", str(port))
    with open(tmp_path / "pendant.log", "w+") as log:
        process = client.popen(
            command, cwd=REPO_ROOT, env=child_env(), stdout=log, stderr=subprocess.STDOUT, max_open_files=512
        )
        try:
            wait_until(lambda: answers(f"http://{LOOPBACK}:{port}/robot/id"), SAFETY_NET_S, "the API")
            assert _listener_pid(port) == process.pid  # the pid Popen gives is the process serving
            limits = Path(f"/proc/{process.pid}/limits").read_text().splitlines()
            assert [line.split()[3:5] for line in limits if line.startswith("Max open files")] == [
                ["512", "512"]
            ]
            process.send_signal(sig)
            returncode = process.wait(SAFETY_NET_S)
        finally:
            process.kill()
            process.wait(SAFETY_NET_S)
        log.seek(0)
        said = log.read()
    # As exec'd: SIGTERM freezes the arm, says so and exits 143; SIGKILL ends it where it stands.
    assert returncode == (128 + signal.SIGTERM if sig == signal.SIGTERM else -signal.SIGKILL)
    assert ("Quitting (SIGTERM): PUT /freeze sent, the arm is frozen" in said) == (sig == signal.SIGTERM), (
        said
    )
    assert _listener_pid(port) is None


def _listener_pid(port: int) -> int | None:
    out = subprocess.run(["ss", "-Hltnp", f"sport = :{port}"], capture_output=True, text=True).stdout
    return int(out.split("pid=")[1].split(",")[0]) if "pid=" in out else None


def test_the_preloaded_interpreter_goes_when_its_test_process_does() -> None:
    script = (
        "import subprocess, sys\n"
        "from tests.support.launchers import pendant_command\n"
        "from tests.support.preloaded import client\n"
        "client.run(pendant_command('diff', '--help'), stdout=subprocess.DEVNULL, timeout=60)\n"
        "print(client.preloader().pid, flush=True)\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", script],
        cwd=REPO_ROOT,
        env=child_env(),
        capture_output=True,
        text=True,
        timeout=90,
    )
    assert done.returncode == 0, done.stderr
    preloaded_pid = int(done.stdout)
    deadline = time.monotonic() + SAFETY_NET_S
    while Path(f"/proc/{preloaded_pid}").exists() and _state(preloaded_pid) != "Z":
        assert time.monotonic() < deadline, (
            f"the preloaded interpreter {preloaded_pid} outlived its test process"
        )
        time.sleep(0.05)  # a real process ending on a real clock


def _state(pid: int) -> str:
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except (FileNotFoundError, ProcessLookupError):
        return "gone"


def test_what_a_fork_cannot_do_is_refused_before_anything_starts() -> None:
    with pytest.raises(ValueError, match="preexec_fn"):
        client.ForkedProcess(pendant_command("--help"), preexec_fn=os.getpid)
    with pytest.raises(ValueError, match="not `python -m pendant"):
        client.ForkedProcess([sys.executable, "-c", "pass"])
    assert not isinstance(client.popen([sys.executable, "-c", "pass"]), client.ForkedProcess)
