"""A preloaded interpreter that forks pendants: `python -m tests.support.preloaded SOCKET`.

The suite starts some 150 pendant processes, and each spent 1.1-2.8 CPU-s importing what every other one
imported too (pinocchio, viser, FastAPI, yourdfpy's trimesh and scipy). This process imports it all once
and forks a child per request on the unix socket SOCKET (`tests/support/preloaded/client.py` asks): the
child takes the client's stdin, stdout and stderr, environment, folder and arguments and runs `python -m
pendant ARGS` in its own process, as exec would have, with what it imports already in memory. The module
ends in `.__main__`, so a pendant's multiprocessing `spawn` workers never import it again.

Each request is one SOCK_SEQPACKET connection: the client sends a JSON request with its three file
descriptors; this process answers with the child's pid and a pidfd (signals reach that process and no
other, even once its pid is reused), then, when the child exits, its return code as Popen gives it
(negative: the signal that ended it). It exits when its stdin closes: the pytest process that started it
has gone."""

from __future__ import annotations

import contextlib
import gc
import json
import os
import selectors
import signal
import socket
import sys
from dataclasses import dataclass, field

REQUEST_MAX_BYTES = 1 << 20  # arguments and environment: far under this
# What `pendant` and `pendant --no-ui` import by the time they serve (pendant/cli/serve.py imports most of
# it inside its functions), but OMPL: its bindings (nanobind) report "leaked instances" on stderr at exit,
# so a child that would never import it (`pendant diff`, say) must not have it. What imports it
# (pendant.planning's planners, and so pendant.ui.app) is left to the child: 0.13 CPU-s of the 1.6.
PRELOADED = (
    "pendant.cli.serve",
    "pendant.cli.subcommands",
    "pendant.readiness",  # the subcommands' modules: check, run, history and diff, record
    "pendant.program.headless",
    "pendant.program.history_cli",
    "pendant.remote.record_cli",
    "pendant.api.serving",
    "pendant.api.quitting",
    "pendant.cell.keeper",
    "pendant.kinematics",
    "pendant.program",
    "pendant.stale_files",
    "pendant.telemetry",
    "pendant.telemetry.headless",
    "pendant.telemetry.live",
    "pendant.telemetry.recordings_api",
    "pendant.telemetry.repair",
    "scipy.spatial",
    "trimesh",
    "uvicorn",
    "viser",
    "yourdfpy",
)
NEVER_PRELOADED = "ompl"


@dataclass
class ChildJob:
    """What a forked child runs once the server's loop is gone from its stack."""

    argv: list[str]  # the pendant's arguments (after `-m pendant`)
    env: dict[str, str]
    cwd: str
    max_open_files: int | None


@dataclass
class Server:
    listener: socket.socket
    selector: selectors.DefaultSelector = field(default_factory=selectors.DefaultSelector)
    children: dict[int, tuple[int, socket.socket]] = field(default_factory=dict)  # pidfd: (pid, connection)

    def serve(self) -> ChildJob | None:
        """Forks a child per request until stdin closes (None), or, in a child, its job."""
        self.selector.register(self.listener, selectors.EVENT_READ, "accept")
        self.selector.register(sys.stdin, selectors.EVENT_READ, "stdin")
        while True:
            for key, _ in self.selector.select():
                if key.data == "stdin":
                    if not os.read(sys.stdin.fileno(), 4096):
                        return None
                elif key.data == "accept":
                    connection, _ = self.listener.accept()
                    job = self._start(connection)
                    if job is not None:
                        return job
                else:
                    self._reap(key.fd)

    def _start(self, connection: socket.socket) -> ChildJob | None:
        fds: list[int] = []
        try:
            message, fds, _, _ = socket.recv_fds(connection, REQUEST_MAX_BYTES, 3)
            request = json.loads(message)
            job = ChildJob(request["argv"], request["env"], request["cwd"], request.get("max_open_files"))
            if len(fds) != 3:
                raise ValueError(f"{len(fds)} file descriptors, not 3")
        except (OSError, ValueError, KeyError, TypeError) as refused:
            for fd in fds:
                os.close(fd)
            with contextlib.suppress(OSError):  # a client that has gone already hears nothing
                connection.sendall(json.dumps({"error": repr(refused)}).encode())
            connection.close()
            return None
        sys.stdout.flush()
        sys.stderr.flush()
        pid = os.fork()
        if pid == 0:
            self._leave_to_child(connection, fds)
            return job
        for fd in fds:
            os.close(fd)
        pidfd = os.pidfd_open(pid)
        with contextlib.suppress(OSError):  # a client gone meanwhile: the child is still reaped below
            socket.send_fds(connection, [json.dumps({"pid": pid}).encode()], [pidfd])
        self.children[pidfd] = (pid, connection)
        self.selector.register(pidfd, selectors.EVENT_READ, "child")
        return None

    def _reap(self, pidfd: int) -> None:
        pid, connection = self.children.pop(pidfd)
        self.selector.unregister(pidfd)
        os.close(pidfd)
        _, status = os.waitpid(pid, 0)
        with contextlib.suppress(OSError):  # the client has gone: nobody to tell
            connection.sendall(json.dumps({"returncode": os.waitstatus_to_exitcode(status)}).encode())
        connection.close()

    def _leave_to_child(self, connection: socket.socket, fds: list[int]) -> None:
        """In the child: the server's sockets, pidfds and selector closed (as objects, so nothing closes a
        number later reused), the client's descriptors as 0, 1 and 2, signals as a new interpreter has
        them."""
        self.selector.close()
        self.listener.close()
        connection.close()
        for pidfd, (_, other) in self.children.items():
            os.close(pidfd)
            other.close()
        for target, fd in enumerate(fds):
            os.dup2(fd, target)
        for fd in set(fds):
            if fd > 2:
                os.close(fd)
        signal.signal(signal.SIGINT, signal.default_int_handler)
        signal.signal(signal.SIGTERM, signal.SIG_DFL)


def run_child(job: ChildJob) -> None:
    """`python -m pendant ARGV` in this process: its SystemExit ends the interpreter as exec's would."""
    import resource
    import runpy

    os.environ.clear()
    os.environ.update(job.env)
    os.chdir(job.cwd)
    if job.max_open_files is not None:
        resource.setrlimit(resource.RLIMIT_NOFILE, (job.max_open_files, job.max_open_files))
    # sys.stdin, stdout and stderr are this interpreter's objects on descriptors 0-2, now the client's;
    # unbuffered (-u), as the suite's pendants ask (PYTHONUNBUFFERED). `python -m` puts its folder first.
    sys.path[0] = job.cwd
    sys.argv = ["-m", *job.argv]
    runpy.run_module("pendant", run_name="__main__", alter_sys=True)


def main() -> ChildJob | None:
    import importlib

    for name in PRELOADED:
        importlib.import_module(name)
    if NEVER_PRELOADED in sys.modules:
        raise SystemExit(f"preloading imported {NEVER_PRELOADED}: its children would say what exec's do not")
    gc.collect()
    gc.freeze()  # what is imported is never collected: the children's collections leave its pages shared
    listener = socket.socket(socket.AF_UNIX, socket.SOCK_SEQPACKET)
    listener.bind(sys.argv[1])
    listener.listen(64)
    print("ready", flush=True)
    return Server(listener).serve()


if __name__ == "__main__":
    child_job = main()
    if child_job is not None:
        run_child(child_job)
