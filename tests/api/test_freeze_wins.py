"""Freeze always wins (issue #16, findings 1 and 5), over real HTTP against `pendant --no-ui`.

The pendant runs with the usual open-file limit of 1,024, as in the audit: ~1,010 idle connections used to
make every request fail, PUT /freeze included; a 10 MB body held PUT /freeze for up to 1.55 s; a 60 MB upload
grew the process by hundreds of MB. Latency figures are the benchmark's (benchmarks/freeze_under_load.py);
here: too-large bodies are refused with 413 and change nothing, a stop is answered whatever the other clients
are doing, and memory stays bounded.
"""

from __future__ import annotations

import contextlib
import json
import resource
import socket
import subprocess
import time
from collections.abc import Iterator

import httpx
import pytest

from pendant.api import create_app
from pendant.api.limits import DOCUMENT_BODY_LIMIT, RUN_BODY_LIMIT, too_large_message
from pendant.api.serving import MAX_HEAD_BYTES, connection_cap, guarded_protocol
from pendant.sim import SimController
from tests.support.launchers import pendant_process
from tests.support.ports import LOOPBACK
from tests.support.threads import serve_in_thread
from tests.support.waiting import SAFETY_NET_S, wait_until

pytestmark = pytest.mark.slow

AUDIT_OPEN_FILES = 1024
IDLE_CONNECTIONS = 1100
HUGE_UPLOAD_BYTES = 60 * 1024 * 1024
HUGE_UPLOADS = 3
# Refused uploads may leave a few allocator pages behind; before the fix three 60 MB uploads grew it 260 MB.
RSS_GROWTH_BOUND_KB = 20 * 1024
HOME = [0.0, -90.0, 90.0, -90.0, -90.0, 0.0]
TOOL = {
    "name": "probe",
    "point": {"x": 0.0, "y": 0.0, "z": 0.1},
    "rotation": {"roll": 0.0, "pitch": 0.0, "yaw": 0.0},
    "radius": 0.02,
}


@pytest.fixture(scope="module")
def pendant() -> Iterator[tuple[subprocess.Popen[str], str]]:
    with pendant_process(max_open_files=AUDIT_OPEN_FILES) as started:
        yield started


@pytest.fixture
def api(pendant: tuple[subprocess.Popen[str], str]) -> Iterator[httpx.Client]:
    with httpx.Client(base_url=pendant[1], timeout=SAFETY_NET_S) as client:
        client.put("/freeze").raise_for_status()
        yield client
        client.put("/freeze").raise_for_status()


def run_body(size: int) -> bytes:
    """A valid /poses/run body of 100 waypoints sweeping J1 90 deg from home (a few seconds at speed 20: still
    running when a loaded machine asks), padded with whitespace to exactly `size` bytes."""
    waypoints = [{"angles": [HOME[0] + 0.9 * i, *HOME[1:]]} for i in range(100)]
    body = json.dumps(waypoints).encode()
    assert len(body) <= size
    return body + b" " * (size - len(body))


def state(api: httpx.Client) -> tuple[list[float], str, str]:
    """What a refused request must leave as it was: the pose (its angles: the timestamp moves on), the
    motion status and the tool."""
    return api.get("/pose").json()["angles"], api.get("/status/motion").text, api.get("/tool").text


def assert_too_large(response: httpx.Response, limit: int) -> None:
    assert response.status_code == 413
    assert response.headers["content-type"].startswith("text/plain")
    assert response.json() == too_large_message(limit)


def test_a_body_over_the_limit_is_refused_with_413_and_changes_nothing(api: httpx.Client) -> None:
    before = state(api)
    assert_too_large(
        api.put("/poses/run", params={"speed": 50}, content=run_body(RUN_BODY_LIMIT + 1)), RUN_BODY_LIMIT
    )
    assert_too_large(
        api.post("/tool", content=json.dumps(TOOL | {"name": "x" * DOCUMENT_BODY_LIMIT})), DOCUMENT_BODY_LIMIT
    )
    assert state(api) == before


def test_a_chunked_body_is_counted_as_it_arrives_and_refused_at_the_limit(api: httpx.Client) -> None:
    before = state(api)
    chunks = iter([run_body(RUN_BODY_LIMIT), b" " * 1024])  # no Content-Length: chunked
    assert_too_large(api.put("/poses/run", params={"speed": 50}, content=chunks), RUN_BODY_LIMIT)
    assert state(api) == before


def test_the_largest_allowed_run_is_accepted(api: httpx.Client) -> None:
    response = api.put("/poses/run", params={"speed": 20}, content=run_body(RUN_BODY_LIMIT))
    assert response.status_code == 200, response.text
    assert api.get("/status/motion").json() == "RUNNING"


def test_freeze_answers_while_a_max_size_body_is_uploaded_slowly(api: httpx.Client, pendant: tuple) -> None:
    body = run_body(RUN_BODY_LIMIT)
    head = b"PUT /poses/run?speed=20 HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: %d\r\n\r\n" % len(body)
    with socket.create_connection(
        (LOOPBACK, int(pendant[1].rsplit(":", 1)[1])), timeout=SAFETY_NET_S
    ) as upload:
        upload.sendall(head + body[: len(body) // 2])
        assert api.put("/freeze").status_code == 200  # while half the body is still to come
        assert api.get("/status/motion").json() == "IDLE"
        upload.sendall(body[len(body) // 2 :])
        assert upload.recv(4096).startswith(b"HTTP/1.1 200")  # the slow upload itself is served
    assert api.get("/status/motion").json() == "RUNNING"


def test_1100_idle_connections_do_not_stop_freeze(api: httpx.Client, pendant: tuple) -> None:
    _, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    resource.setrlimit(resource.RLIMIT_NOFILE, (hard, hard))  # this process holds the idle connections
    port = int(pendant[1].rsplit(":", 1)[1])
    idle = [socket.create_connection((LOOPBACK, port), timeout=SAFETY_NET_S) for _ in range(IDLE_CONNECTIONS)]
    try:
        # A new connection, after them.
        with httpx.Client(base_url=pendant[1], timeout=SAFETY_NET_S) as newcomer:
            assert newcomer.put("/freeze").status_code == 200
            assert newcomer.get("/status/motion").json() == "IDLE"
        cap = connection_cap(AUDIT_OPEN_FILES)
        wait_until(
            lambda: sum(map(still_open, idle)) <= cap, SAFETY_NET_S, f"at most {cap} idle connections left"
        )
    finally:
        for connection in idle:
            connection.close()
    assert api.put("/freeze").status_code == 200


def test_a_request_head_over_the_limit_is_refused_with_431(api: httpx.Client, pendant: tuple) -> None:
    port = int(pendant[1].rsplit(":", 1)[1])
    with socket.create_connection((LOOPBACK, port), timeout=SAFETY_NET_S) as connection:
        # The server may answer and close before the end: the answer is still there to read.
        with contextlib.suppress(OSError):
            connection.sendall(b"GET /pose HTTP/1.1\r\nHost: t\r\nX-Big: " + b"a" * (4 * MAX_HEAD_BYTES))
        answer = connection.recv(4096)
    assert answer.startswith(b"HTTP/1.1 431")
    assert answer.endswith(b'"Request head too large: at most %d bytes"' % MAX_HEAD_BYTES)
    assert api.put("/freeze").status_code == 200


def still_open(connection: socket.socket) -> bool:
    """The server has not closed `connection` (nothing to read, no end of stream)."""
    connection.setblocking(False)
    try:
        return connection.recv(1) != b""
    except BlockingIOError:
        return True
    except OSError:
        return False


def rss_kb(process: subprocess.Popen[str]) -> int:
    with open(f"/proc/{process.pid}/status") as status:
        line = next(line for line in status if line.startswith("VmRSS:"))
    return int(line.split()[1])


def upload(port: int, path: str, size: int, chunked: bool) -> bytes:
    """Send a `size`-byte body as fast as the server takes it; what it answered (the 413)."""
    framing = b"Transfer-Encoding: chunked" if chunked else b"Content-Length: %d" % size
    piece = b" " * (1024 * 1024)
    with socket.create_connection((LOOPBACK, port), timeout=SAFETY_NET_S) as connection:
        connection.sendall(b"PUT %s HTTP/1.1\r\nHost: 127.0.0.1\r\n%s\r\n\r\n" % (path.encode(), framing))
        try:
            for _ in range(size // len(piece)):
                connection.sendall(b"%x\r\n%s\r\n" % (len(piece), piece) if chunked else piece)
        except OSError:
            pass  # the server answered and closed: the rest of the upload is not read
        return connection.recv(4096)


def test_memory_stays_bounded_after_refused_huge_uploads(api: httpx.Client, pendant: tuple) -> None:
    process, base_url = pendant
    port = int(base_url.rsplit(":", 1)[1])
    before_state = state(api)
    upload(port, "/poses/run?speed=50", HUGE_UPLOAD_BYTES, chunked=True)  # warm the refusal path up
    before = rss_kb(process)
    for chunked in (False, True):
        for _ in range(HUGE_UPLOADS):
            assert upload(port, "/poses/run?speed=50", HUGE_UPLOAD_BYTES, chunked).startswith(b"HTTP/1.1 413")
    assert rss_kb(process) - before < RSS_GROWTH_BOUND_KB
    assert state(api) == before_state


SHORT_READ_TIMEOUT_S = 0.5
SLOW_CLIENT_GIVE_UP_S = 5.0


def test_a_slow_or_silent_client_is_disconnected(sim: SimController) -> None:
    """Slowloris: a byte of header now and then used to keep a connection open for ever."""
    protocol = guarded_protocol(max_connections=64, request_read_timeout_s=SHORT_READ_TIMEOUT_S)
    with serve_in_thread(create_app(sim), http=protocol) as base_url:
        port = int(base_url.rsplit(":", 1)[1])
        with (
            socket.create_connection((LOOPBACK, port)) as silent,
            socket.create_connection((LOOPBACK, port)) as slow,
        ):
            trickle = iter(b"GET /pose HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: " + b"a" * 1000)
            deadline = time.monotonic() + SLOW_CLIENT_GIVE_UP_S
            while still_open(slow) and time.monotonic() < deadline:
                slow.sendall(bytes([next(trickle)]))
                time.sleep(0.05)
            assert not still_open(slow)
            assert not still_open(silent)
            assert httpx.put(f"{base_url}/freeze").status_code == 200
