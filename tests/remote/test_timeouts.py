"""`--connect-timeout` and `--read-timeout` reach both ends of the link to the controller: the client the page
and programs use, and the proxy on the API port (real sockets on 127.0.0.1)."""

from __future__ import annotations

import time

import httpx
import pytest
from fastapi import FastAPI

from pendant.cli import make_api_app, make_controller, parse_settings
from pendant.controller.errors import ControllerOffline
from pendant.remote import RemoteController, create_proxy_app
from pendant.remote.client import DEFAULT_CONNECT_TIMEOUT_S, DEFAULT_READ_TIMEOUT_S
from tests.support.bad_servers import http_answer, raw_server, request_path
from tests.support.threads import serve_in_thread
from tests.support.waiting import SAFETY_NET_S

READ_TIMEOUT_S = 0.3  # short, so the hung request costs a fraction of a second
PROXY_CLIENT_TIMEOUT_S = SAFETY_NET_S  # the test's own client waits well past the proxy's read timeout
IDLE_ANSWER = http_answer("200 OK", b'"IDLE"')


def hang_on_pose(head: bytes) -> bytes | None:
    """Answers GET /status/motion; accepts GET /pose and never answers it."""
    return None if request_path(head) == "/pose" else IDLE_ANSWER


def test_the_configured_read_timeout_bounds_the_client_and_the_proxy() -> None:
    with raw_server(hang_on_pose) as robot_url:
        argv = ["--robot", robot_url, "--no-ui", "--connect-timeout", "0.5", "--read-timeout", "0.3"]
        settings = parse_settings(argv)
        controller = make_controller(settings)
        assert isinstance(controller, RemoteController)
        app = make_api_app(settings, controller, started_at=time.monotonic())
        assert isinstance(app, FastAPI)  # the proxy
        with (
            controller,
            serve_in_thread(app) as proxy_url,
            httpx.Client(base_url=proxy_url, timeout=PROXY_CLIENT_TIMEOUT_S) as client,
        ):
            with pytest.raises(ControllerOffline, match=r"did not answer GET /pose within 0\.3 s"):
                controller.get_pose()
            answer = client.get("/pose")
            assert answer.status_code == 502
            assert "no answer within 0.3 s" in answer.text
            assert client.get("/status/motion").content == b'"IDLE"'  # the link itself is fine
            upstream = app.state.upstream
            assert (upstream.connect_timeout, upstream.read_timeout) == (0.5, READ_TIMEOUT_S)
            assert app.state.health_probe is controller


def test_a_proxy_built_without_timeouts_takes_the_settings_defaults() -> None:
    app = create_proxy_app("http://127.0.0.1:9")
    upstream, probe = app.state.upstream, app.state.health_probe
    assert (upstream.connect_timeout, upstream.read_timeout) == (
        DEFAULT_CONNECT_TIMEOUT_S,
        DEFAULT_READ_TIMEOUT_S,
    )
    assert (probe.connect_timeout, probe.read_timeout) == (DEFAULT_CONNECT_TIMEOUT_S, DEFAULT_READ_TIMEOUT_S)
    probe.close()
