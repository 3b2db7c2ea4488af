"""`GET /pendant/health`: is the pendant up, which controller does it drive, and can it reach it.

Served on the pendant's API port in both modes (the embedded simulator and a real robot behind the proxy),
under /pendant/ so it never shadows a PULSE path.
"""

from __future__ import annotations

import time
from dataclasses import asdict, dataclass

from fastapi import APIRouter

from pendant import __version__
from pendant.config import Settings
from pendant.controller.errors import ControllerError, ControllerOffline, Emergency
from pendant.controller.protocol import Controller
from pendant.controller.types import MotionStatus

HEALTH_PATH = "/pendant/health"


@dataclass(frozen=True)
class PendantHealth:
    """The JSON body of GET /pendant/health."""

    mode: str  # "sim" or "robot"
    robot_url: str | None
    online: bool  # the controller answered (an error answer such as 503 still counts)
    latency_s: float | None  # round trip of the probe
    motion_status: str | None  # EMERGENCY on a 503; None when the probe failed otherwise
    last_error: str | None  # the controller's message if the probe failed
    uptime_s: float
    version: str


def probe_health(settings: Settings, controller: Controller, started_at: float) -> PendantHealth:
    """Ask the controller for its motion status once and report. Never raises a ControllerError.

    For a RemoteController the probe also refreshes its `health()`; its round trip is the latency.
    """
    t0 = time.perf_counter()
    motion_status: str | None = None
    last_error: str | None = None
    online = True
    try:
        motion_status = str(controller.get_motion_status())
    except ControllerOffline as exc:
        online, last_error = False, exc.message
    except Emergency as exc:
        # The controller answers every call with 503 in an emergency: that is its motion status.
        motion_status, last_error = MotionStatus.EMERGENCY.value, exc.message
    except ControllerError as exc:
        last_error = exc.message
    latency_s: float | None = time.perf_counter() - t0
    link_health = getattr(controller, "health", None)
    if callable(link_health):
        latency_s = link_health().latency_s if online else None
    return PendantHealth(
        mode="sim" if settings.robot_url is None else "robot",
        robot_url=settings.robot_url,
        online=online,
        latency_s=latency_s,
        motion_status=motion_status,
        last_error=last_error,
        uptime_s=time.monotonic() - started_at,
        version=__version__,
    )


def health_router(settings: Settings, controller: Controller, started_at: float) -> APIRouter:
    """A router with GET /pendant/health. `started_at` is the pendant's start, `time.monotonic()`."""
    router = APIRouter(tags=["pendant"])

    # A plain `def`: FastAPI runs it in its thread pool, so a slow controller never blocks the event loop.
    @router.get(HEALTH_PATH, summary="Pendant and controller link health")
    def get_health() -> dict[str, object]:
        return asdict(probe_health(settings, controller, started_at))

    return router
