"""Real `pendant` processes on free loopback ports (`python -m pendant ...`), started, waited for, stopped.

They are forked from a preloaded interpreter (tests/support/preloaded: the suite starts some 150, and each
spent 1.5 CPU-s importing what the others had imported); PENDANT_TESTS_EXEC=1 execs them instead."""

from __future__ import annotations

import contextlib
import os
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import IO

import httpx

from pendant.monitoring import DATA_DIR_ENV
from pendant.paths import PROGRAMS_DIR_ENV

from . import preloaded
from .ports import LOOPBACK, free_port
from .waiting import SAFETY_NET_S, answers, wait_until

REPO_ROOT = Path(__file__).resolve().parents[2]
START_TIMEOUT_S = 120.0  # a pendant with its page, beside Chromiums, on a loaded 2-core machine
STOP_TIMEOUT_S = SAFETY_NET_S  # SIGKILL only after this: a starved pendant still ends by itself


def pendant_command(*args: str) -> list[str]:
    """`python -m pendant ARGS...` with this interpreter (so this checkout's package, via PYTHONPATH)."""
    return [sys.executable, "-m", "pendant", *args]


def child_env(extra: dict[str, str] | None = None) -> dict[str, str]:
    """The environment for a child process: this checkout first on PYTHONPATH, unbuffered output."""
    path = str(REPO_ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")
    return {**os.environ, "PYTHONPATH": path, "PYTHONUNBUFFERED": "1", **(extra or {})}


def stop(process: subprocess.Popen, timeout_s: float = STOP_TIMEOUT_S) -> None:
    """SIGTERM, then SIGKILL if it has not exited within `timeout_s`."""
    if process.poll() is None:
        process.terminate()
    try:
        process.wait(timeout_s)
    except subprocess.TimeoutExpired:
        process.kill()
        process.wait(timeout_s)


@contextlib.contextmanager
def running_pendant(*extra_args: str, max_open_files: int | None = None) -> Iterator[str]:
    """The base URL of a freshly started `pendant --no-ui`; the process is stopped on exit.

    `max_open_files`: the process's open-file limit (soft and hard), as a service or shell might set it."""
    with pendant_process(*extra_args, max_open_files=max_open_files) as (_, base_url):
        yield base_url


@contextlib.contextmanager
def pendant_process(
    *extra_args: str, max_open_files: int | None = None
) -> Iterator[tuple[subprocess.Popen[str], str]]:
    """running_pendant(), also giving the process (to read its memory, say)."""
    port = free_port()
    command = pendant_command("--no-ui", "--host", LOOPBACK, "--api-port", str(port), *extra_args)
    # A data folder of its own unless the test names one: a module's pendant starts before the per-test
    # $PENDANT_DATA_DIR is set, and the checkout's pendant-data/ would carry its kept cell to the next run.
    data = tempfile.TemporaryDirectory(prefix="pendant-data-")
    env = {**os.environ, DATA_DIR_ENV: os.environ.get(DATA_DIR_ENV) or data.name}
    # Its output goes to a file, never a pipe: a pipe nobody reads fills up and blocks a chatty pendant.
    # `process.stdout` reads that file (what it printed so far), as it read the pipe before.
    log = tempfile.NamedTemporaryFile("w+", prefix="pendant-", suffix=".log", delete=False)  # noqa: SIM115
    process = preloaded.popen(
        command,
        cwd=REPO_ROOT,
        env=env,
        stdout=log,
        stderr=subprocess.STDOUT,
        text=True,
        max_open_files=max_open_files,
    )
    log.close()
    process.stdout = open(log.name)  # noqa: SIM115  # closed below
    base_url = f"http://{LOOPBACK}:{port}"
    try:
        _wait_until_serving(process, base_url)
        yield process, base_url
    finally:
        stop(process)
        process.stdout.close()
        os.unlink(log.name)
        data.cleanup()


SAID_CHARS = 4_000  # of a pendant's output in a failed test's report: its last warnings and traceback
ANNOUNCE_MAX_LINES = 200  # the lines of a repair running beside the start-up may come before the URL


def _wait_until_serving(process: subprocess.Popen[str], base_url: str) -> None:
    deadline = time.monotonic() + START_TIMEOUT_S
    said = _read_announcement(process, base_url, deadline)
    if base_url not in said[-1]:
        raise RuntimeError(f"pendant did not announce {base_url}, it said: {''.join(said)!r}")
    while time.monotonic() < deadline:
        if process.poll() is not None:
            output = process.stdout.read() if process.stdout else ""
            raise RuntimeError(f"pendant exited with {process.returncode}:\n{output}")
        try:
            if httpx.get(f"{base_url}/robot/id", timeout=1.0).status_code == 200:
                return
        except httpx.TransportError:
            pass
        time.sleep(0.05)  # polling a real process starting up: no fake clock can stand in for this wait
    raise RuntimeError(f"pendant did not answer on {base_url} within {START_TIMEOUT_S} s")


def _read_announcement(process: subprocess.Popen[str], base_url: str, deadline: float) -> list[str]:
    """The lines the pendant printed up to the one announcing `base_url` (at most ANNOUNCE_MAX_LINES), read
    from its log file as it writes them; fewer if it exits or the deadline passes first."""
    assert process.stdout is not None
    said: list[str] = []
    partial = ""
    while len(said) < ANNOUNCE_MAX_LINES and time.monotonic() < deadline:
        partial += process.stdout.readline()
        if partial.endswith("\n"):
            said.append(partial)
            partial = ""
            if base_url in said[-1]:
                return said
        elif process.poll() is not None:
            partial += process.stdout.read()
            break
        else:
            time.sleep(0.02)  # the file has no more yet: a real process writing on a real clock
    return [*said, partial]


class Pendant:
    """A running pendant with its page: the page's URL, an HTTP client of its API, and its process (to
    signal)."""

    # The folders of a test module that starts its pendant with its own (set by that module).
    programs: Path
    data: Path

    def __init__(
        self,
        ui_port: int,
        api_port: int,
        process: subprocess.Popen[bytes] | None = None,
        output: IO[str] | None = None,
    ) -> None:
        self.process = process
        self.ui_port = ui_port
        self.ui_url = f"http://{LOOPBACK}:{ui_port}/"
        self.api = httpx.Client(base_url=f"http://{LOOPBACK}:{api_port}", timeout=30.0)
        self._output = output  # the file its output goes to, while it runs

    def said(self, max_chars: int = SAID_CHARS) -> str:
        """The end of what the process printed so far (its log's warnings and tracebacks), for a failed
        test's report: a flaky test's pendant is gone, with its temporary log, by the end of the run."""
        if self._output is None or self._output.closed:
            return ""
        # pread: the file's offset is the one the process writes at, shared with it, and stays put.
        fd = self._output.fileno()
        size = os.fstat(fd).st_size
        start = max(0, size - 4 * max_chars)  # UTF-8: at most 4 bytes a character
        return os.pread(fd, size - start, start).decode("utf-8", errors="replace")[-max_chars:]

    def pose(self) -> list[float]:
        return self.api.get("/pose").json()["angles"]

    def status(self) -> str:
        return self.api.get("/status/motion").text.strip('"')

    def events(self, text: str, since: float) -> list[str]:
        """The messages of the event log's events holding `text`, since `since` (epoch s)."""
        query: dict[str, str | float] = {"text": text, "since": since}
        return [e["message"] for e in self.api.get("/pendant/events", params=query).json()["events"]]


@contextlib.contextmanager
def running_pendant_ui(
    *flags: str, env: dict[str, str] | None = None, launcher: Sequence[str] = ("-m", "pendant")
) -> Iterator[Pendant]:
    """A `pendant` process (simulator, page and API on free loopback ports) with extra `flags`; its event
    log and recordings in a temporary data folder (`env={"PENDANT_DATA_DIR": ...}` names another), its
    programs in a temporary folder too (`--programs` or PENDANT_PROGRAMS_DIR names another: the checkout's
    programs/ carried one test's autosaved working copy into the next pendant, and into the README's
    pictures); `launcher`: what this interpreter runs, the pendant's arguments after it (a script that
    starts it)."""
    ui_port, api_port = free_port(), free_port()
    data = tempfile.TemporaryDirectory(prefix="pendant-data-")
    programs = tempfile.TemporaryDirectory(prefix="pendant-programs-")
    # Its output goes to a file (a pipe nobody reads fills up and blocks a chatty pendant); a start-up
    # failure quotes it.
    with tempfile.TemporaryFile("w+") as log:
        process = preloaded.popen(
            [sys.executable, *launcher, "--ui-port", str(ui_port), "--api-port", str(api_port), *flags],
            stdout=log,
            stderr=subprocess.STDOUT,
            env={
                **os.environ,
                "PYTHONUNBUFFERED": "1",
                "PENDANT_DATA_DIR": data.name,
                PROGRAMS_DIR_ENV: programs.name,
                **(env or {}),
            },
        )
        try:
            try:
                wait_until(lambda: answers(f"http://{LOOPBACK}:{api_port}/pose"), START_TIMEOUT_S, "the API")
                wait_until(lambda: answers(f"http://{LOOPBACK}:{ui_port}/"), START_TIMEOUT_S, "the page")
            except TimeoutError as late:
                log.seek(0)
                raise TimeoutError(f"{late}; the pendant said: {log.read()[-2000:]!r}") from late
            yield Pendant(ui_port, api_port, process, log)
        finally:
            stop(process)
            data.cleanup()
            programs.cleanup()


class Launcher:
    """`launcher(args, name="pendant")` starts `python -m pendant ARGS...`, its output in FOLDER/NAME.log;
    `close()` kills every process it started (the `launch` fixture)."""

    def __init__(self, folder: Path) -> None:
        self._folder = folder
        self._processes: list[subprocess.Popen[bytes]] = []

    def __call__(self, args: list[str], name: str = "pendant") -> subprocess.Popen[bytes]:
        with open(self._folder / f"{name}.log", "wb") as log:
            process = preloaded.popen(
                pendant_command(*args), cwd=REPO_ROOT, env=child_env(), stdout=log, stderr=subprocess.STDOUT
            )
        self._processes.append(process)
        return process

    def close(self) -> None:
        for process in self._processes:
            if process.poll() is None:
                process.kill()
            process.wait(STOP_TIMEOUT_S)
