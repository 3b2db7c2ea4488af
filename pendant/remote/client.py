"""RemoteController: the Controller protocol over HTTP to a real PULSE controller (or the simulator's API).

Every failure comes out as a ControllerError carrying the controller's message; anything that is not an answer
the PULSE API defines (refused connection, timeout, garbage) is ControllerOffline. Only GETs are retried, and
only when no answer came at all: a motion or IO command is sent at most once, and nothing is queued for later.
"""

from __future__ import annotations

import contextlib
import threading
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any, TypeVar

import httpx
from pydantic import ValidationError

from pendant.controller.errors import ControllerError, ControllerOffline, Unsupported
from pendant.controller.types import (
    MotionParams,
    MotionStatus,
    MotorStatus,
    Pose,
    Position,
    RecoverResult,
    SignalLevel,
    Tool,
)
from pendant.remote.sdk18 import Pulse18Client, dump
from pendant.remote.wire import error_for_status, quote_body

T = TypeVar("T")

DEFAULT_CONNECT_TIMEOUT_S = 1.0
DEFAULT_READ_TIMEOUT_S = 3.0
DEFAULT_GET_RETRIES = 2
_RETRY_PAUSE_S = 0.05
# Below the usual server idle timeouts (uvicorn: 5 s), so we drop an idle connection before the server does
# and rarely send a command into a socket the server is closing.
_KEEPALIVE_EXPIRY_S = 2.0


@dataclass(frozen=True)
class Health:
    """How the link to the controller is doing, as of the last call.

    `online`: the last call got an answer the PULSE API defines (an error status like 503 counts: the
    controller answered). `latency_s`: round trip of the last answered call. `last_seen`: `time.monotonic()`
    of the last answer, None if never.
    """

    online: bool
    latency_s: float | None
    last_error: str | None
    last_seen: float | None


class RemoteController(Pulse18Client):
    """A PULSE controller reached over HTTP. Thread-safe: the UI may call it from several threads.

    Pass `transport` (an httpx transport) or a ready `client` (e.g. Starlette's TestClient, which is an
    httpx.Client) to run without a network; `base_url` still prefixes every path.
    """

    def __init__(
        self,
        base_url: str,
        connect_timeout: float = DEFAULT_CONNECT_TIMEOUT_S,
        read_timeout: float = DEFAULT_READ_TIMEOUT_S,
        transport: httpx.BaseTransport | None = None,
        client: httpx.Client | None = None,
        get_retries: int = DEFAULT_GET_RETRIES,
    ) -> None:
        self.base_url = base_url.rstrip("/")
        self.connect_timeout = connect_timeout
        self.read_timeout = read_timeout
        self.get_retries = get_retries
        self._owns_client = client is None
        self._client = client or httpx.Client(
            transport=transport,
            timeout=httpx.Timeout(read_timeout, connect=connect_timeout, pool=connect_timeout),
            limits=httpx.Limits(max_keepalive_connections=8, keepalive_expiry=_KEEPALIVE_EXPIRY_S),
            # The controller speaks plain text and JSON; a compressed body would only cost time.
            headers={"Accept-Encoding": "identity"},
        )
        self._health_lock = threading.Lock()
        self._health = Health(online=False, latency_s=None, last_error=None, last_seen=None)
        # The PULSE API cannot read the gripper back: remember what this client last told it (None: nothing).
        self._gripper_opening: float | None = None

    # Lifetime

    def close(self) -> None:
        if self._owns_client:
            self._client.close()

    def __enter__(self) -> RemoteController:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.close()

    def __repr__(self) -> str:
        return f"RemoteController({self.base_url!r})"

    # Health

    def health(self) -> Health:
        """The link's state as of the last call (no network traffic)."""
        with self._health_lock:
            return self._health

    def ping(self) -> Health:
        """Ask the controller for its motion status to refresh `health()`; never raises."""
        with contextlib.suppress(ControllerError):
            self.get_motion_status()
        return self.health()

    # Reads (each a thin wrapper naming its operations-table row: `call`, pendant.remote.calls)

    def get_position(self) -> Position:
        return self.call("GET /position", result=Position)  # firmware before 1.8 sends no timestamp

    def get_pose(self) -> Pose:
        return self.call("GET /pose", result=Pose)  # likewise

    def get_motion_status(self) -> MotionStatus:
        return self.call("GET /status/motion")

    def get_motors(self) -> list[MotorStatus]:
        return self.call("GET /status/motors")

    def get_tool(self) -> Tool:
        return self.call("GET /tool")

    def get_base(self) -> Position:
        return self.call("GET /base")

    def get_robot_id(self) -> str:
        return self.call("GET /robot/id")

    def get_output(self, port: int) -> SignalLevel:
        return self.call("GET /signal/output/{port}", path={"port": port})

    def get_input(self, port: int) -> SignalLevel:
        return self.call("GET /signal/input/{port}", path={"port": port})

    # Motion

    def set_position(self, position: Position, params: MotionParams) -> Position:
        return self.call("PUT /position", json=dump(position), params=_motion_query(params))

    def set_pose(self, pose: Pose, params: MotionParams) -> None:
        self.call("PUT /pose", json=dump(pose), params=_motion_query(params))

    def run_positions(self, positions: list[Position], params: MotionParams) -> None:
        body = [dump(position) for position in positions]
        self.call("PUT /positions/run", json=body, params=_motion_query(params))

    def run_poses(self, poses: list[Pose], params: MotionParams) -> None:
        body = [dump(pose) for pose in poses]
        self.call("PUT /poses/run", json=body, params=_motion_query(params))

    def open_gripper(self, timeout_ms: int) -> None:
        self.call("PUT /gripper/open", params={"timeout": timeout_ms})
        self._gripper_opening = 1.0

    def close_gripper(self, timeout_ms: int) -> None:
        self.call("PUT /gripper/close", params={"timeout": timeout_ms})
        self._gripper_opening = 0.0

    def gripper_opening(self) -> float | None:
        """What the gripper was last told through this client (1 open, 0 closed), None when never: scripts
        going through the pendant's proxy, or the controller's own panel, are not seen here."""
        return self._gripper_opening

    def pack(self) -> None:
        self.call("PUT /pack")

    # State

    def relax(self) -> None:
        self.call("PUT /relax")

    def freeze(self) -> None:
        self.call("PUT /freeze")

    def recover(self) -> RecoverResult:
        return self.call("PUT /recover")

    # IO and settings

    def set_output(self, port: int, level: SignalLevel) -> None:
        self.call(f"PUT /signal/output/{{port}}/{level.value.lower()}", path={"port": port})

    def set_tool(self, tool: Tool) -> Tool:
        return self.call("POST /tool", json=tool.model_dump())

    def set_base(self, base: Position) -> Position:
        return self.call("POST /base", json=base.model_dump())

    # Transport

    def _request(
        self,
        method: str,
        path: str,
        *,
        json: Any = None,
        params: Mapping[str, str | int | float] | None = None,
    ) -> httpx.Response:
        """One call: the answer if 2xx, else the typed error. GETs are retried on connection failures only
        (not on timeouts: a hung controller must be reported within one read timeout)."""
        request_line = f"{method} {path}"
        attempts = 1 + (self.get_retries if method == "GET" else 0)
        for attempt in range(attempts):
            started = time.perf_counter()
            try:
                response = self._client.request(method, self.base_url + path, json=json, params=params)
            except httpx.TimeoutException as exc:
                raise self._offline(self._timeout_message(request_line, exc)) from exc
            except httpx.HTTPError as exc:
                if attempt + 1 < attempts:
                    time.sleep(_RETRY_PAUSE_S * (attempt + 1))
                    continue
                raise self._offline(self._transport_message(request_line, exc)) from exc
            latency_s = time.perf_counter() - started
            if not response.is_success:
                error = error_for_status(response.status_code, response.content, request_line)
                if isinstance(error, Unsupported):  # an older controller, answering: the link is fine
                    self._mark_online(latency_s)
                    raise error
                if isinstance(error, ControllerOffline):
                    raise self._offline(error.message)
                self._mark_online(latency_s)  # a refusal is still an answer
                raise error
            self._mark_online(latency_s)
            return response
        raise AssertionError("unreachable")  # the loop always returns or raises

    def _parse(self, response: httpx.Response, request_line: str, parse: Callable[[bytes], T]) -> T:
        try:
            return parse(response.content)
        except (ValidationError, ValueError) as exc:
            raise self._offline(
                f"Unparsable answer from the controller to {request_line}: {quote_body(response.content)}"
            ) from exc

    def _timeout_message(self, request_line: str, exc: httpx.TimeoutException) -> str:
        if isinstance(exc, httpx.ConnectTimeout | httpx.PoolTimeout):
            return (
                f"Controller at {self.base_url} did not accept a connection within "
                f"{self.connect_timeout:g} s ({request_line})"
            )
        return f"Controller at {self.base_url} did not answer {request_line} within {self.read_timeout:g} s"

    def _transport_message(self, request_line: str, exc: httpx.HTTPError) -> str:
        if isinstance(exc, httpx.ConnectError):
            reason = str(exc) or "connection failed"
            return f"Controller at {self.base_url} is unreachable ({request_line}): {reason}"
        if isinstance(exc, httpx.RemoteProtocolError):
            return f"Controller at {self.base_url} sent no valid HTTP answer to {request_line}: {exc}"
        return f"Connection to the controller at {self.base_url} failed ({request_line}): {exc!r}"

    def _mark_online(self, latency_s: float) -> None:
        with self._health_lock:
            now = time.monotonic()
            self._health = Health(online=True, latency_s=latency_s, last_error=None, last_seen=now)

    def _offline(self, message: str) -> ControllerOffline:
        with self._health_lock:
            self._health = Health(
                online=False,
                latency_s=self._health.latency_s,
                last_error=message,
                last_seen=self._health.last_seen,
            )
        return ControllerOffline(message)


def _motion_query(params: MotionParams) -> dict[str, str | int | float]:
    """The motion parameters as the PULSE API takes them: query parameters."""
    query: dict[str, str | int | float] = {
        "speed": params.speed,
        "type": params.motion_type.value,
        "tcp_max_velocity": params.tcp_max_velocity,
    }
    if params.acceleration is not None:
        query["acceleration"] = params.acceleration
    return query
