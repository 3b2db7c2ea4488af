"""The API's stops told to the rest of the pendant (a held jog in the page ends for good, see pendant.jog).

One ASGI middleware, on the simulator's API and on the proxy to a real controller alike: a request that stops
the arm is announced on the StopBus before it goes on to the controller, so that a jog confirmation from
the page that slips in between is refused rather than restarting the arm.
"""

from __future__ import annotations

from starlette.responses import JSONResponse
from starlette.types import ASGIApp, Receive, Scope, Send

from pendant.controller.stops import STOPS_PATH, StopBus

# (method, path) of the requests that stop the arm, and how the page names them.
STOP_REQUESTS = {
    ("PUT", "/freeze"): "Freeze",
    ("POST", "/stop"): "Protective stop",
}


def stop_name(method: str, path: str) -> str | None:
    return STOP_REQUESTS.get((method.upper(), path.rstrip("/") or "/"))


class StopNotice:
    """ASGI middleware: `stops.notify("Freeze from the API (10.0.0.9)")` on every stop request."""

    def __init__(self, app: ASGIApp, stops: StopBus) -> None:
        self.app = app
        self.stops = stops

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] == "http":
            if scope["method"] == "GET" and scope["path"] == STOPS_PATH:  # `pendant run` polls it
                heard = {"count": self.stops.count, "last": self.stops.last_cause}
                await JSONResponse(heard)(scope, receive, send)
                return
            name = stop_name(scope["method"], scope["path"])
            if name is not None:
                client = scope.get("client")
                self.stops.notify(f"{name} from the API ({client[0] if client else 'unknown address'})")
        await self.app(scope, receive, send)
