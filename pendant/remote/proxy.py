"""The pendant's API port in robot mode: a transparent proxy to the real PULSE controller.

Every request except GET /pendant/health goes to the controller with its method, path, query string, body and
headers (minus hop-by-hop ones); the controller's status, content type and body come back byte for byte.
If the controller cannot be reached, or does not answer within the read timeout, the proxy answers
502 Bad Gateway with a plain-text message saying why. Nothing is queued or retried later: a command that
could not be delivered is lost, and the caller is told so. GETs (idempotent) are retried once on a failed
connection.

Run alone (the CLI's `pendant --robot URL` builds the same app):
    python -m pendant.remote.proxy --robot http://192.168.1.50:8081 --port 8081
"""

from __future__ import annotations

import argparse
import contextlib
import time
from collections.abc import AsyncIterator, Callable

import httpx
from fastapi import FastAPI
from starlette.requests import Request
from starlette.responses import PlainTextResponse, Response
from starlette.routing import Route

from pendant.config import Settings
from pendant.remote.client import DEFAULT_CONNECT_TIMEOUT_S, RemoteController
from pendant.remote.health import health_router

DEFAULT_PROXY_READ_TIMEOUT_S = 10.0
PROXY_METHODS = ["GET", "PUT", "POST", "DELETE", "PATCH", "HEAD", "OPTIONS"]
BAD_GATEWAY = 502

# Headers that belong to one connection, not to the message (RFC 9110 7.6.1), plus the ones the proxy
# recomputes (host, content-length) or the server in front adds itself (date, server).
_HOP_BY_HOP = frozenset(
    {
        b"connection",
        b"keep-alive",
        b"proxy-authenticate",
        b"proxy-authorization",
        b"proxy-connection",
        b"te",
        b"trailer",
        b"transfer-encoding",
        b"upgrade",
    }
)
_NOT_FORWARDED_UP = _HOP_BY_HOP | {b"host", b"content-length", b"accept-encoding"}
_NOT_FORWARDED_DOWN = _HOP_BY_HOP | {b"content-length", b"date", b"server"}

RequestHook = Callable[[Request], Response | None]
"""Called before each forwarded request (not for /pendant/health), on the event loop: keep it fast.
Return a Response to answer instead of the controller (access control: a token check), None to forward.
An event log can record `request.method`, `request.url.path` and `request.client` here."""


def create_proxy_app(
    robot_url: str,
    *,
    settings: Settings | None = None,
    on_request: RequestHook | None = None,
    connect_timeout: float = DEFAULT_CONNECT_TIMEOUT_S,
    read_timeout: float = DEFAULT_PROXY_READ_TIMEOUT_S,
    transport: httpx.AsyncBaseTransport | None = None,
    started_at: float | None = None,
) -> FastAPI:
    """An ASGI app serving the PULSE API by forwarding to the controller at `robot_url`, plus
    GET /pendant/health. `transport` replaces the network (tests)."""
    robot_url = robot_url.rstrip("/")
    settings = settings if settings is not None else Settings(robot_url=robot_url)
    started_at = started_at if started_at is not None else time.monotonic()
    upstream = httpx.AsyncClient(
        transport=transport,
        timeout=httpx.Timeout(read_timeout, connect=connect_timeout, pool=connect_timeout),
        limits=httpx.Limits(max_connections=32, max_keepalive_connections=16, keepalive_expiry=2.0),
    )
    # The health probe is a blocking client: the health route runs in the thread pool.
    health_probe = RemoteController(robot_url, connect_timeout=connect_timeout, get_retries=0)

    async def forward(request: Request) -> Response:
        if on_request is not None:
            refusal = on_request(request)
            if refusal is not None:
                return refusal
        scope = request.scope
        method: str = scope["method"]
        target = robot_url + scope.get("raw_path", scope["path"].encode()).decode("latin-1")
        if scope["query_string"]:
            target += "?" + scope["query_string"].decode("latin-1")
        headers = [(k, v) for k, v in scope["headers"] if k not in _NOT_FORWARDED_UP]
        # The body is passed through untouched, so it must not arrive compressed.
        headers.append((b"accept-encoding", b"identity"))
        body = await request.body()
        attempts = 2 if method == "GET" else 1
        for attempt in range(attempts):
            try:
                answer = await upstream.request(method, target, content=body, headers=headers)
                break
            except httpx.TimeoutException:
                return _bad_gateway(
                    f"Controller at {robot_url} did not answer {method} {scope['path']} "
                    f"within {read_timeout:g} s"
                )
            except httpx.HTTPError as exc:
                if attempt + 1 < attempts and not isinstance(exc, httpx.TimeoutException):
                    continue
                return _bad_gateway(f"Controller at {robot_url} is unreachable: {exc or type(exc).__name__}")
        response = Response(content=answer.content, status_code=answer.status_code)
        response.raw_headers.extend(
            (k, v) for k, v in answer.headers.raw if k.lower() not in _NOT_FORWARDED_DOWN
        )
        return response

    @contextlib.asynccontextmanager
    async def lifespan(_app: FastAPI) -> AsyncIterator[None]:
        try:
            yield
        finally:
            await upstream.aclose()
            health_probe.close()

    app = FastAPI(
        title="PULSE pendant (proxy to a real controller)",
        docs_url=None,
        redoc_url=None,
        openapi_url=None,
        lifespan=lifespan,
    )
    app.include_router(health_router(settings, health_probe, started_at))
    # A raw Starlette route (no FastAPI parameter parsing) keeps the per-request overhead small.
    app.router.routes.append(Route("/{path:path}", forward, methods=PROXY_METHODS))
    app.state.robot_url = robot_url
    app.state.health_probe = health_probe
    return app


def _bad_gateway(message: str) -> Response:
    return PlainTextResponse(message, status_code=BAD_GATEWAY)


def main(argv: list[str] | None = None) -> int:
    """`python -m pendant.remote.proxy --robot URL [--host H] [--port N]`: the proxy alone, no UI."""
    import uvicorn

    parser = argparse.ArgumentParser(description="Serve the PULSE API as a proxy to a real controller.")
    parser.add_argument("--robot", required=True, help="the controller's URL, e.g. http://192.168.1.50:8081")
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=int, default=8081)
    args = parser.parse_args(argv)
    settings = Settings(host=args.host, api_port=args.port, robot_url=args.robot, no_ui=True)
    app = create_proxy_app(args.robot, settings=settings)
    uvicorn.run(app, host=args.host, port=args.port, log_level="warning", access_log=False)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
