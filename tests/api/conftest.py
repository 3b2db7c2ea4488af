"""API test fixtures: the app over the simulator (fake clock) and a TestClient of it."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest
from fastapi import FastAPI
from fastapi.testclient import TestClient

from pendant.api import create_app


@pytest.fixture
def app(sim: Any) -> FastAPI:
    return create_app(sim)


@pytest.fixture
def client(app: FastAPI) -> Iterator[TestClient]:
    with TestClient(app) as test_client:
        yield test_client
