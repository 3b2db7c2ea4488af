"""`pendant check URL [--timeout S]`: exits 0 once a PULSE API answers there, 1 with a message otherwise."""

from __future__ import annotations

import http.server
import subprocess
import sys
import threading
from collections.abc import Iterator

import pytest

from pendant.readiness import PROBE_TIMEOUT_S
from pendant.simserver import SimServer
from tests.support import preloaded
from tests.support.launchers import REPO_ROOT, START_TIMEOUT_S, running_pendant, stop
from tests.support.ports import LOOPBACK, free_port
from tests.support.waiting import SAFETY_NET_S

CHECK_TIMEOUT_S = START_TIMEOUT_S  # a pendant starting at nice 19 on a loaded machine: a minute or more
# What a check against a server that answers wrongly is given (it ends only then): probes enough that on a
# machine starved of CPU (at nice 19 beside two busy cores, 5 s saw one answer, 1.3 s late) one is answered
# within its PROBE_TIMEOUT_S; 0.5 s failed in CI.
WRONG_SERVER_TIMEOUT_S = "10"


def check(url: str, *flags: str) -> subprocess.CompletedProcess[str]:
    return preloaded.run(
        [sys.executable, "-m", "pendant", "check", url, *flags],
        cwd=REPO_ROOT,
        capture_output=True,
        text=True,
        timeout=CHECK_TIMEOUT_S + 30.0,
        check=False,
    )


@pytest.fixture
def not_pulse() -> Iterator[str]:
    """Some other HTTP server: it answers, but not as a PULSE controller would."""
    server = http.server.ThreadingHTTPServer((LOOPBACK, 0), http.server.SimpleHTTPRequestHandler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://{LOOPBACK}:{server.server_address[1]}"
    finally:
        server.shutdown()
        server.server_close()
        thread.join()


def test_exits_0_when_the_simulator_answers() -> None:
    with running_pendant() as url:
        done = check(url, "--timeout", f"{SAFETY_NET_S:g}")
    assert done.returncode == 0, done.stderr
    assert f"PULSE API at {url} answers: IDLE" in done.stdout


def test_waits_for_a_pendant_that_is_still_starting() -> None:
    port = free_port()
    url = f"http://{LOOPBACK}:{port}"
    waiting = preloaded.popen(
        [sys.executable, "-m", "pendant", "check", url, "--timeout", f"{CHECK_TIMEOUT_S:g}"],
        cwd=REPO_ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    pendant = preloaded.popen(
        [sys.executable, "-m", "pendant", "--no-ui", "--host", LOOPBACK, "--api-port", str(port)],
        cwd=REPO_ROOT,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    try:
        out, err = waiting.communicate(timeout=CHECK_TIMEOUT_S + 30.0)
        assert waiting.returncode == 0, err
        assert "answers: IDLE" in out
    finally:
        stop(pendant)  # killed if SIGTERM has not ended it in time (a starved pendant may still be starting)


def test_a_controller_in_emergency_still_answers() -> None:
    with SimServer() as server:
        from pendant.sim import Fault

        server.sim.inject_fault(Fault.EMERGENCY)
        done = check(server.url, "--timeout", f"{SAFETY_NET_S:g}")
    assert done.returncode == 0, done.stderr
    assert "Robot unavailable in emergency state" in done.stdout


def test_times_out_with_a_message_when_nothing_listens() -> None:
    url = f"http://{LOOPBACK}:{free_port()}"
    done = check(url, "--timeout", "0.5")
    assert done.returncode == 1
    assert f"no PULSE API answered at {url} within 0.5 s" in done.stderr
    assert "ConnectError" in done.stderr


def test_another_http_server_is_not_a_pulse_api(not_pulse: str) -> None:
    done = check(not_pulse, "--timeout", WRONG_SERVER_TIMEOUT_S)
    assert done.returncode == 1
    assert "HTTP 404" in done.stderr and "not a PULSE answer" in done.stderr


class _AnswersOnceThenStalls(http.server.BaseHTTPRequestHandler):
    """Says 404 until the checker has read one, then keeps every later probe waiting past its timeout.

    The checker has read a 404 when it sends its next probe on the same (kept-alive) connection: a 404 the
    checker gave up on (it had no CPU for a second) does not count."""

    protocol_version = "HTTP/1.1"  # keep-alive: the checker's next probe comes on the same connection
    read_404 = threading.Event()

    def do_GET(self) -> None:
        if getattr(self, "answered_here", False):
            self.read_404.set()
        if self.read_404.is_set():
            threading.Event().wait(PROBE_TIMEOUT_S + 1.0)
            self.close_connection = True  # the checker has given up on this one
            return
        self.answered_here = True
        body = b"not here"
        self.send_response(404)
        self.send_header("Content-Length", str(len(body)))
        self.end_headers()
        self.wfile.write(body)

    def log_message(self, format: str, *args: object) -> None:
        """Quiet: the test reads the checker's words, not the server's."""


def test_a_probe_that_times_out_after_a_non_pulse_answer_still_names_that_answer() -> None:
    """Seen in CI on a loaded machine: the one late probe hid that the server is not a PULSE API."""
    _AnswersOnceThenStalls.read_404.clear()
    server = http.server.ThreadingHTTPServer((LOOPBACK, 0), _AnswersOnceThenStalls)
    server.daemon_threads = True
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        done = check(f"http://{LOOPBACK}:{server.server_address[1]}", "--timeout", WRONG_SERVER_TIMEOUT_S)
    finally:
        server.shutdown()
        server.server_close()
    assert done.returncode == 1
    assert "ReadTimeout" in done.stderr and "before that HTTP 404" in done.stderr, done.stderr


@pytest.mark.parametrize(
    ("flags", "message"),
    [(["localhost:8081"], "URL must start with http://"), (["http://x", "--timeout", "0"], "--timeout")],
)
def test_bad_arguments_are_refused(flags: list[str], message: str) -> None:
    done = check(*flags)
    assert done.returncode == 2
    assert message in done.stderr
