"""Controller implementation 2: a real PULSE controller over HTTP, and the proxy that serves its API."""

from pendant.remote.client import Health, RemoteController
from pendant.remote.health import HEALTH_PATH, PendantHealth, health_router, probe_health
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
