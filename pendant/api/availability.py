"""A controller in EMERGENCY (or not responding) answers every PULSE call with 503 (500) before it looks at
the request: a malformed body or an out-of-range speed gets the same answer as a good one. SDK 1.8.4's
GET /status and /status/failure are the exception in EMERGENCY: they say so (and why)."""

from __future__ import annotations

from collections.abc import Callable

from starlette.types import ASGIApp, Receive, Scope, Send

from pendant.api.errors import error_response
from pendant.controller.errors import ControllerError, Emergency
from pendant.controller.operations import ANSWER_IN_EMERGENCY

# Served by the pendant, not the controller: they answer whatever state the arm is in (the operations
# table's `controller=False` entries are all under /sim/: tests/api/test_operations.py checks).
NOT_THE_CONTROLLERS = ("/sim/", "/pendant/", "/metrics", "/docs", "/redoc", "/openapi.json")
# ANSWER_IN_EMERGENCY (the table's `in_emergency`): SDK 1.8.4 asks these after a failure, to learn why.
__all__ = ["ANSWER_IN_EMERGENCY", "NOT_THE_CONTROLLERS", "UnavailableFirst"]


class UnavailableFirst:
    """ASGI middleware: ask `check_alive()` (raises the controller's error) before routing a PULSE call."""

    def __init__(self, app: ASGIApp, check_alive: Callable[[], None]) -> None:
        self.app = app
        self.check_alive = check_alive

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] == "http" and not scope["path"].startswith(NOT_THE_CONTROLLERS):
            try:
                self.check_alive()
            except Emergency as error:
                if scope["path"] not in ANSWER_IN_EMERGENCY:
                    await error_response(error)(scope, receive, send)
                    return
            except ControllerError as error:
                await error_response(error)(scope, receive, send)
                return
        await self.app(scope, receive, send)
