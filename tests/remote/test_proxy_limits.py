"""The proxy bounds bodies as the simulator's API does: a GET (or any request) with a body over its limit is
refused with 413 before it is buffered, and never reaches the controller (issue #16, finding 5)."""

from __future__ import annotations

from collections.abc import Iterator

import httpx
import pytest

from pendant.api.limits import DEFAULT_BODY_LIMIT, RUN_BODY_LIMIT, too_large_message
from pendant.remote import create_proxy_app
from tests.support.bad_servers import http_answer, raw_server, request_path
from tests.support.threads import serve_in_thread
from tests.support.waiting import SAFETY_NET_S

HUGE_BYTES = 8 * 1024 * 1024


@pytest.fixture
def forwarded() -> Iterator[tuple[str, list[str]]]:
    """(proxy URL, paths the controller received) for a controller that answers every request `"IDLE"`."""
    received: list[str] = []

    def controller(head: bytes) -> bytes:
        received.append(request_path(head))
        return http_answer("200 OK", b'"IDLE"')

    with raw_server(controller) as robot_url, serve_in_thread(create_proxy_app(robot_url)) as proxy_url:
        yield proxy_url, received


def test_a_get_with_a_huge_body_is_refused_and_not_forwarded(forwarded: tuple[str, list[str]]) -> None:
    proxy_url, received = forwarded
    for content in (b" " * HUGE_BYTES, iter([b" " * DEFAULT_BODY_LIMIT, b" "])):  # declared, then chunked
        response = httpx.request("GET", f"{proxy_url}/status/motion", content=content, timeout=SAFETY_NET_S)
        assert response.status_code == 413
        assert response.json() == too_large_message(DEFAULT_BODY_LIMIT)
    assert received == []
    assert httpx.get(f"{proxy_url}/status/motion").json() == "IDLE"  # an ordinary read still goes through
    assert received == ["/status/motion"]


def test_a_run_over_its_limit_is_refused_and_not_forwarded(forwarded: tuple[str, list[str]]) -> None:
    proxy_url, received = forwarded
    response = httpx.put(f"{proxy_url}/poses/run?speed=10", content=b" " * (RUN_BODY_LIMIT + 1))
    assert response.status_code == 413
    assert response.json() == too_large_message(RUN_BODY_LIMIT)
    assert received == []
