"""Controller implementation 2: a real PULSE controller over HTTP, and the proxy that serves its API."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from pendant.remote.client import Health, RemoteController
from pendant.remote.health import HEALTH_PATH, PendantHealth, health_router, probe_health

if TYPE_CHECKING:
    from pendant.remote.proxy import create_proxy_app

__all__ = [
    "HEALTH_PATH",
    "Health",
    "PendantHealth",
    "RemoteController",
    "create_proxy_app",
    "health_router",
    "probe_health",
]


def __getattr__(name: str) -> Any:
    # Imported on first use, so `python -m pendant.remote.proxy` does not find itself half-imported.
    if name == "create_proxy_app":
        from pendant.remote.proxy import create_proxy_app

        return create_proxy_app
    raise AttributeError(f"module 'pendant.remote' has no attribute {name!r}")
