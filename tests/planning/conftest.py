"""What the planning tests share: a `pendant --no-ui` on a fast clock, one per test module."""

from __future__ import annotations

from collections.abc import Iterator

import httpx
import pytest

from tests.support.launchers import running_pendant
from tests.support.waiting import SAFETY_NET_S


@pytest.fixture(scope="module")
def fast_api() -> Iterator[httpx.Client]:
    """A client of the simulator's API, ten times faster than real time."""
    with (
        running_pendant("--time-scale", "10") as url,
        httpx.Client(base_url=url, timeout=SAFETY_NET_S) as client,
    ):
        yield client
