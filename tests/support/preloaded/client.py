"""`popen` and `run`: subprocess's, but `python -m pendant ...` forked from a preloaded interpreter.

A `subprocess.Popen` whose child is forked by `python -m tests.support.preloaded` (its __main__ says how):
Popen sets up the pipes, files and text mode as ever; only its start (`_execute_child`), its waits and
its signals go through the preloaded interpreter, which is the child's parent. One such interpreter per
pytest process, started on the first pendant; it ends with that process. PENDANT_TESTS_EXEC=1 starts
every pendant with exec instead, the way a user's shell does (to compare, or to rule the forking out).
"""

from __future__ import annotations

import contextlib
import inspect
import json
import os
import select
import signal
import socket
import subprocess
import sys
import tempfile
import threading
from collections.abc import Sequence
from pathlib import Path
from typing import Any

REPO_ROOT = Path(__file__).resolve().parents[3]
EXEC_ENV = "PENDANT_TESTS_EXEC"
START_TIMEOUT_S = 120.0  # its imports, beside a loaded machine's other work
ANSWER_MAX_BYTES = 4096
# Popen's private start, as CPython 3.11-3.13 have it: the one piece of subprocess this reaches into.
EXECUTE_CHILD_PARAMETERS = [
    *("self", "args", "executable", "preexec_fn", "close_fds", "pass_fds", "cwd", "env", "startupinfo"),
    *("creationflags", "shell", "p2cread", "p2cwrite", "c2pread", "c2pwrite", "errread", "errwrite"),
    *("restore_signals", "gid", "gids", "uid", "umask", "start_new_session", "process_group"),
]


def preloading_fits() -> bool:
    """Whether this Python's Popen has the shape ForkedProcess overrides (a test says so loudly)."""
    return (
        list(inspect.signature(vars(subprocess.Popen)["_execute_child"]).parameters)
        == EXECUTE_CHILD_PARAMETERS
    )


def readable(stream: Any, timeout_s: float | None) -> bool:
    """Whether `stream` has something to read (or its end) within `timeout_s` (None: however long).
    poll, not select: a test process with Chromiums and pendants can hold descriptors past select's 1024."""
    poller = select.poll()
    poller.register(stream, select.POLLIN)
    return bool(poller.poll(None if timeout_s is None else max(0, int(timeout_s * 1000))))


class Preloader:
    """The preloaded interpreter of this process: started once, asked for a child per pendant."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._process: subprocess.Popen[str] | None = None
        self._folder = tempfile.TemporaryDirectory(prefix="pendant-preloaded-")
        self.socket_path = os.path.join(self._folder.name, "socket")
        self.log_path = os.path.join(self._folder.name, "log")

    def start(self) -> None:
        """Started, unless it runs already (a preloaded interpreter that died is started again)."""
        with self._lock:
            if self._process is None or self._process.poll() is not None:
                self._start()

    def connect(self) -> socket.socket:
        self.start()
        connection = socket.socket(socket.AF_UNIX, socket.SOCK_SEQPACKET)
        connection.connect(self.socket_path)
        return connection

    @property
    def pid(self) -> int | None:
        """The preloaded interpreter's pid, once it is started."""
        return None if self._process is None else self._process.pid

    def said(self) -> str:
        return Path(self.log_path).read_text(errors="replace")[-2000:]

    def _start(self) -> None:
        path = str(REPO_ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")
        with open(self.log_path, "w") as log:
            # stdin a pipe it reads to its end: it goes when this process does, however that ends.
            self._process = subprocess.Popen(
                [sys.executable, "-u", "-m", "tests.support.preloaded", self.socket_path],
                cwd=REPO_ROOT,
                env={**os.environ, "PYTHONPATH": path},
                stdin=subprocess.PIPE,
                stdout=subprocess.PIPE,
                stderr=log,
                text=True,
            )
        assert self._process.stdout is not None
        if (
            not readable(self._process.stdout, START_TIMEOUT_S)
            or self._process.stdout.readline() != "ready\n"
        ):
            self._process.kill()
            raise RuntimeError(f"the preloaded interpreter did not start: {self.said()!r}")


_preloader: Preloader | None = None
_preloader_lock = threading.Lock()


def preloader() -> Preloader:
    global _preloader
    with _preloader_lock:
        if _preloader is None:
            _preloader = Preloader()
        return _preloader


class ForkedProcess(subprocess.Popen[Any]):
    """A Popen whose child the preloaded interpreter forked; `max_open_files` as RLIMIT_NOFILE's soft and
    hard limit (what a preexec_fn would have set)."""

    def __init__(self, args: Sequence[str], *, max_open_files: int | None = None, **kwargs: Any) -> None:
        self._max_open_files = max_open_files
        self._connection: socket.socket | None = None
        self._pidfd = -1
        self._lock = threading.Lock()
        super().__init__(args, **kwargs)

    def _execute_child(  # Popen's private signature, checked by preloading_fits
        self, args: Sequence[str], executable: Any, preexec_fn: Any, close_fds: bool, pass_fds: Sequence[int],
        cwd: Any, env: Any, startupinfo: Any, creationflags: int, shell: bool, p2cread: int, p2cwrite: int,
        c2pread: int, c2pwrite: int, errread: int, errwrite: int, *rest: Any,
    ) -> None:  # fmt: skip
        _, gid, gids, uid, umask, start_new_session, process_group = rest
        if preexec_fn is not None or pass_fds or shell or start_new_session or {gid, gids, uid} != {None}:
            raise ValueError("a forked pendant takes no preexec_fn, pass_fds, shell, user or session")
        if umask >= 0 or (process_group is not None and process_group >= 0):
            raise ValueError("a forked pendant takes no umask or process group")
        if [str(a) for a in args[:3]] != [sys.executable, "-m", "pendant"]:
            raise ValueError(f"not `python -m pendant ...` with this interpreter: {args!r}")
        # -1: the stream is this process's own, as a child of Popen inherits it.
        fds = [fd if fd != -1 else own for fd, own in ((p2cread, 0), (c2pwrite, 1), (errwrite, 2))]
        request = {
            "argv": list(args[3:]),  # the pendant's
            "env": dict(os.environ if env is None else env),
            "cwd": os.fspath(cwd) if cwd is not None else os.getcwd(),
            "max_open_files": self._max_open_files,
        }
        self._connection = preloader().connect()
        try:
            socket.send_fds(self._connection, [json.dumps(request).encode()], fds)
            answer, pidfds, _, _ = socket.recv_fds(self._connection, ANSWER_MAX_BYTES, 1)
        finally:
            self._close_pipe_fds(p2cread, p2cwrite, c2pread, c2pwrite, errread, errwrite)  # type: ignore[attr-defined]
        reply = json.loads(answer or b"{}")
        if "pid" not in reply:
            self._connection.close()
            raise OSError(f"the preloaded interpreter refused {args!r}: {reply or preloader().said()!r}")
        self.pid = reply["pid"]
        self._pidfd = pidfds[0]
        self._child_created = True

    def _internal_poll(self, _deadstate: int | None = None, *_: Any) -> int | None:
        if self.returncode is None and self._lock.acquire(blocking=False):
            try:
                self._read_returncode(timeout=0)
            finally:
                self._lock.release()
        return self.returncode

    def _wait(self, timeout: float | None) -> int:
        with self._lock:
            if self.returncode is None and not self._read_returncode(timeout):
                raise subprocess.TimeoutExpired(self.args, timeout or 0)
        assert self.returncode is not None
        return self.returncode

    def _read_returncode(self, timeout: float | None) -> bool:
        """The child's return code once the preloaded interpreter sends it (within `timeout`)."""
        assert self._connection is not None
        if not readable(self._connection, timeout):
            return False
        message = self._connection.recv(ANSWER_MAX_BYTES)
        # No message: the preloaded interpreter has gone (killed), and with it the one way to the status.
        self.returncode = json.loads(message)["returncode"] if message else 255
        self._connection.close()
        os.close(self._pidfd)
        self._pidfd = -1
        return True

    def send_signal(self, sig: int) -> None:
        self.poll()
        if self.returncode is None:
            # The pidfd: this process and no other, even once its pid is reused; one that has just exited
            # is no error, as Popen's own send_signal has it.
            with contextlib.suppress(ProcessLookupError):
                signal.pidfd_send_signal(self._pidfd, sig)


def forks(args: Sequence[Any]) -> bool:
    """Whether `args` is `python -m pendant ...` with this interpreter, and forking is on here."""
    return (
        os.environ.get(EXEC_ENV) != "1"
        and [str(a) for a in args[:3]] == [sys.executable, "-m", "pendant"]
        and preloading_fits()
    )


def popen(args: Sequence[Any], *, max_open_files: int | None = None, **kwargs: Any) -> subprocess.Popen[Any]:
    """subprocess.Popen(args, **kwargs), forked from the preloaded interpreter where `forks(args)`."""
    if forks(args):
        return ForkedProcess([str(a) for a in args], max_open_files=max_open_files, **kwargs)
    if max_open_files is not None:
        kwargs["preexec_fn"] = lambda: _limit_open_files(max_open_files)
    return subprocess.Popen(args, **kwargs)


def run(
    args: Sequence[Any],
    *,
    input: Any = None,
    timeout: float | None = None,
    check: bool = False,
    **options: Any,
) -> subprocess.CompletedProcess[Any]:
    """subprocess.run(args, ...), started by `popen`."""
    if options.pop("capture_output", False):
        options["stdout"] = options["stderr"] = subprocess.PIPE
    if input is not None:
        options["stdin"] = subprocess.PIPE
    with popen(args, **options) as process:
        try:
            stdout, stderr = process.communicate(input, timeout=timeout)
        except BaseException:
            process.kill()
            raise
    completed = subprocess.CompletedProcess(process.args, process.returncode, stdout, stderr)
    if check:
        completed.check_returncode()
    return completed


def _limit_open_files(count: int) -> None:
    import resource

    resource.setrlimit(resource.RLIMIT_NOFILE, (count, count))
