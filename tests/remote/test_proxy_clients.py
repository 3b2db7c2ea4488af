"""64 clients at once through the proxy (issue #32): a healthy controller's answers all come back, none is
a 502 or a 504, and the controller is never asked to hold more connections than it takes. Real processes
on loopback: a simulator, a relay in front of it that takes 24 connections at once (as an embedded
controller has few), and `pendant --no-ui --robot` in front of that."""

from __future__ import annotations

import collections
import threading
import time
from urllib.parse import urlsplit

import httpx

from pendant.remote.upstream import MAX_IN_FLIGHT
from tests.support.launchers import running_pendant
from tests.support.relay import capped_relay

CLIENTS = 64
LOAD_S = 4.0
# The proxy's own requests (MAX_IN_FLIGHT), a stop that skips the queue, the pendant's link for the page.
CONTROLLER_CONNECTIONS = MAX_IN_FLIGHT + 8


def test_64_clients_through_the_proxy_get_every_answer_and_no_502() -> None:
    with (
        running_pendant() as controller,
        capped_relay(urlsplit(controller).port or 80, CONTROLLER_CONNECTIONS) as (relay, seen),
        running_pendant("--robot", relay) as proxy,
    ):
        statuses: collections.Counter[int | str] = collections.Counter()
        lock = threading.Lock()
        stop_at = time.monotonic() + LOAD_S

        def client(number: int) -> None:
            with httpx.Client(base_url=proxy, timeout=30) as http:
                while time.monotonic() < stop_at:
                    status: int | str
                    try:
                        if number % 4 == 0:
                            status = http.put("/signal/output/1/high").status_code  # a command
                        else:
                            status = http.get("/pose").status_code
                    except httpx.HTTPError as error:
                        status = type(error).__name__
                    with lock:
                        statuses[status] += 1

        threads = [threading.Thread(target=client, args=(n,)) for n in range(CLIENTS)]
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join()

    assert set(statuses) == {200}, statuses
    assert seen.refused == 0 and seen.most_at_once <= CONTROLLER_CONNECTIONS
