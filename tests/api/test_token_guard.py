"""Finding 8 of the audit, over real HTTP: every method but GET/HEAD/OPTIONS needs the token (in the simulator
and through the proxy), the proxy never forwards it, wrong guesses are slowed per client and logged once per
burst, weak tokens are warned about, UTF-8 tokens work, and stopping needs no token."""

from __future__ import annotations

import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from urllib.parse import quote

import httpx
import pytest

from pendant.access import TOKEN_HEADER
from pendant.access.http_guard import AccessRules
from pendant.access.throttle import FailedAttempts
from pendant.api import create_app
from pendant.eventlog import EventKind, EventLog
from pendant.remote import create_proxy_app
from pendant.sim import FakeClock, SimController
from tests.support import preloaded
from tests.support.bad_servers import http_answer, raw_server
from tests.support.launchers import REPO_ROOT, START_TIMEOUT_S, running_pendant, stop
from tests.support.threads import serve_in_thread
from tests.support.waiting import SAFETY_NET_S

TOKEN = "Zürich-Ω-token-2026-ähnlich"  # UTF-8, and long enough not to be warned about
INTERVAL_S = 0.2  # a small turn so the test stays short; the product's is 1 s
FREE = 3


@pytest.fixture(scope="module")
def exposed() -> Iterator[str]:
    with running_pendant("--token", TOKEN) as url:
        yield url


@pytest.fixture(scope="module")
def proxied() -> Iterator[str]:
    sim = SimController("pulse75", FakeClock())
    with serve_in_thread(create_app(sim)) as controller_url:
        app = create_proxy_app(controller_url, access=AccessRules(token=TOKEN))
        with serve_in_thread(app) as proxy_url:
            yield proxy_url


@pytest.fixture(params=["exposed", "proxied"])
def api(request: pytest.FixtureRequest) -> Iterator[httpx.Client]:
    with httpx.Client(base_url=request.getfixturevalue(request.param), timeout=30.0) as client:
        yield client


@pytest.mark.parametrize("method", ["PROPFIND", "MOVE", "PATCH", "DELETE", "LOCK", "PUT", "POST"])
def test_every_method_but_reads_needs_the_token(api: httpx.Client, method: str) -> None:
    for path in ("/relax", "/sim/reset", "/tool"):
        assert api.request(method, path).status_code == 401, (method, path)
    assert api.get("/status/motion").text == '"IDLE"'


def test_stopping_needs_no_token(api: httpx.Client) -> None:
    assert api.put("/freeze").status_code == 200
    assert api.put("/freeze", headers={TOKEN_HEADER: "wrong"}).status_code == 200


def test_a_utf8_token_is_accepted_as_raw_bytes_or_percent_encoded(api: httpx.Client) -> None:
    raw = {TOKEN_HEADER.encode(): TOKEN.encode("utf-8")}
    assert api.put("/relax", headers=raw).status_code == 200
    assert api.get("/status/motion").text == '"ZERO_GRAVITY"'
    assert api.put("/freeze").status_code == 200
    encoded = {TOKEN_HEADER: quote(TOKEN, safe="")}
    assert api.put("/relax", headers=encoded).status_code == 200
    assert api.put("/freeze").status_code == 200
    assert api.get("/status/motion").text == '"IDLE"'
    assert api.put("/relax", headers={TOKEN_HEADER: "Zurich"}).status_code == 403


def test_the_proxy_never_forwards_the_token_to_the_controller() -> None:
    heads: list[bytes] = []

    def controller(head: bytes) -> bytes:
        heads.append(head)
        return http_answer("200 OK", b"")

    with (
        raw_server(controller) as robot_url,
        serve_in_thread(create_proxy_app(robot_url, access=AccessRules(token=TOKEN))) as proxy_url,
        httpx.Client(base_url=proxy_url) as client,
    ):
        answer = client.put("/relax", headers={TOKEN_HEADER: quote(TOKEN, safe=""), "X-Other": "kept"})
        assert answer.status_code == 200
    assert len(heads) == 1
    assert b"x-other: kept" in heads[0].lower()
    assert TOKEN_HEADER.lower().encode() not in heads[0].lower()
    assert quote(TOKEN, safe="").encode() not in heads[0]


def _guarded(events: EventLog) -> AccessRules:
    return AccessRules(
        token=TOKEN, events=events, attempts=FailedAttempts(free=FREE, interval_s=INTERVAL_S, max_wait_s=5.0)
    )


def test_wrong_guesses_are_slowed_per_client_and_logged_once_per_burst() -> None:
    events = EventLog()
    sim = SimController("pulse75", FakeClock())
    guesses = 12
    with (
        serve_in_thread(create_app(sim, access=_guarded(events))) as url,
        httpx.Client(base_url=url, timeout=SAFETY_NET_S) as client,
        ThreadPoolExecutor(max_workers=guesses) as pool,
    ):
        started = time.monotonic()
        # Many connections at once: the guesses are served one per turn, not in parallel.
        statuses = list(
            pool.map(
                lambda i: client.put("/relax", headers={TOKEN_HEADER: f"guess-{i}"}).status_code,
                range(guesses),
            )
        )
        took = time.monotonic() - started
        assert statuses == [403] * guesses
        assert took >= (guesses - FREE - 1) * INTERVAL_S, f"{guesses} guesses took only {took:.2f} s"
        # The right token still works (its check waits for its turn too, then clears the record).
        assert client.put("/relax", headers={TOKEN_HEADER: quote(TOKEN)}).status_code == 200
    refused = [e for e in events.recent() if e.kind is EventKind.REFUSED]
    assert len(refused) == 1, [e.message for e in refused]
    assert "Wrong access token" in refused[0].message


def test_a_client_far_behind_its_turn_is_told_to_wait_at_once() -> None:
    sim = SimController("pulse75", FakeClock())
    rules = AccessRules(token=TOKEN, attempts=FailedAttempts(free=1, interval_s=10.0, max_wait_s=1.0))
    with (
        serve_in_thread(create_app(sim, access=rules)) as url,
        httpx.Client(base_url=url, timeout=30.0) as client,
    ):
        assert client.put("/relax", headers={TOKEN_HEADER: "guess"}).status_code == 403
        answer = client.put("/relax", headers={TOKEN_HEADER: "guess-2"})
        assert answer.status_code == 429
        assert "Too many wrong access tokens" in answer.text
        assert client.put("/freeze").status_code == 200  # stopping is never held up
    assert sim.get_motion_status().value == "IDLE"


@pytest.mark.parametrize("token", ["1", "aaaaaaaaaaaaaaaaaaaa"])
def test_a_weak_token_is_warned_about_at_start_up(token: str) -> None:
    output = _start_and_read(["--token", token])
    assert "WARNING: this access token is easy to guess" in output


def test_a_generated_token_is_not_warned_about() -> None:
    output = _start_and_read(["--token", TOKEN])
    assert "easy to guess" not in output


def test_a_token_with_spaces_is_refused_at_start_up() -> None:
    done = preloaded.run(
        [sys.executable, "-m", "pendant", "--no-ui", "--token", "two words"],
        cwd=REPO_ROOT,
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert done.returncode == 2
    assert "--token: the access token must not contain spaces" in done.stderr


def _start_and_read(flags: list[str]) -> str:
    """Start `pendant --no-ui` with `flags`, read what it prints until it serves, stop it."""
    from tests.support.ports import free_port

    port = free_port()
    process = preloaded.popen(
        [sys.executable, "-m", "pendant", "--no-ui", "--api-port", str(port), *flags],
        cwd=REPO_ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
    lines: list[str] = []

    def read() -> None:
        assert process.stdout is not None
        for line in process.stdout:
            lines.append(line)

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    try:
        deadline = time.monotonic() + START_TIMEOUT_S
        while time.monotonic() < deadline:
            try:
                httpx.get(f"http://127.0.0.1:{port}/pose", timeout=1.0)
                break
            except httpx.HTTPError:
                time.sleep(0.05)
    finally:
        stop(process)
        reader.join(START_TIMEOUT_S)  # to the end of its output: the pendant has exited
    return "".join(lines)


def test_the_proxy_logs_refusals_and_commands_with_the_client_and_the_controllers_status() -> None:
    events = EventLog()
    sim = SimController("pulse75", FakeClock())
    with (
        serve_in_thread(create_app(sim)) as controller_url,
        serve_in_thread(
            create_proxy_app(controller_url, access=AccessRules(token=TOKEN, events=events))
        ) as url,
        httpx.Client(base_url=url, headers={"User-Agent": "cell-script/1.0"}) as client,
    ):
        assert client.put("/relax").status_code == 401
        assert client.put("/relax", headers={TOKEN_HEADER: quote(TOKEN)}).status_code == 200
    refused, accepted = events.recent()
    assert refused.kind is EventKind.REFUSED and "PUT /relax: 401" in refused.message
    assert accepted.kind is EventKind.COMMAND and accepted.message == "PUT /relax -> 200"
    assert accepted.source == "API 127.0.0.1 (cell-script/1.0)"
