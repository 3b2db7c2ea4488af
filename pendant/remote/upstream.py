"""A lean asyncio HTTP/1.1 client for the proxy: keep-alive connections to one controller, bytes in and out.

Why not httpx.AsyncClient: the proxy only relays bytes, and httpx's request/response models, URL parsing and
header normalisation cost several hundred microseconds per call, which is most of the proxy's overhead
budget (1 ms). Here a request is one `write` of prebuilt bytes and the answer is parsed by httptools (the C
parser uvicorn uses), so the proxy adds little beyond the extra loopback hop.
"""

from __future__ import annotations

import asyncio
import time
from dataclasses import dataclass, field
from typing import cast

import httptools


class UpstreamError(Exception):
    """No usable answer: the connection failed, was closed, timed out, or the answer was not HTTP."""


class UpstreamConnectError(UpstreamError):
    """The connection could not be opened: nothing was sent."""


class UpstreamTimeout(UpstreamError):
    pass


@dataclass
class UpstreamResponse:
    status: int
    headers: list[tuple[bytes, bytes]]
    body: bytes


@dataclass
class _Exchange:
    """One request's answer as it is parsed."""

    head_only: bool
    done: asyncio.Future[UpstreamResponse]
    headers: list[tuple[bytes, bytes]] = field(default_factory=list)
    body: list[bytes] = field(default_factory=list)


class _Connection(asyncio.Protocol):
    """One keep-alive connection; at most one request in flight."""

    def __init__(self) -> None:
        self.transport: asyncio.Transport | None = None
        self.closed = False
        self.reusable = False
        self.idle_since = 0.0
        self._parser = httptools.HttpResponseParser(self)
        self._exchange: _Exchange | None = None

    # asyncio.Protocol

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        # uvloop's transports are not asyncio.Transport subclasses, but have the same methods.
        self.transport = cast(asyncio.Transport, transport)

    def data_received(self, data: bytes) -> None:
        if self._exchange is None:  # bytes nobody asked for: the connection is out of step
            self.close()
            return
        try:
            self._parser.feed_data(data)
        except httptools.HttpParserUpgrade:
            self._fail(UpstreamError("the controller switched protocols"))
        except httptools.HttpParserError as exc:
            self._fail(UpstreamError(f"the controller sent no valid HTTP answer ({exc})"))

    def connection_lost(self, exc: Exception | None) -> None:
        self.closed = True
        self._fail(UpstreamError("the controller closed the connection without answering"))

    # httptools callbacks

    def on_header(self, name: bytes, value: bytes) -> None:
        if self._exchange is not None:
            self._exchange.headers.append((name, value))

    def on_headers_complete(self) -> None:
        if self._exchange is not None and self._exchange.head_only:
            # A HEAD answer announces a body it does not send; httptools cannot be told so: finish here
            # and retire the connection.
            self.reusable = False
            self._finish(keep_alive=False)

    def on_body(self, body: bytes) -> None:
        if self._exchange is not None:
            self._exchange.body.append(body)

    def on_message_complete(self) -> None:
        self._finish(keep_alive=self._parser.should_keep_alive())

    # Use

    def send(self, request: bytes, head_only: bool) -> asyncio.Future[UpstreamResponse]:
        assert self.transport is not None and self._exchange is None
        done: asyncio.Future[UpstreamResponse] = asyncio.get_running_loop().create_future()
        self._exchange = _Exchange(head_only=head_only, done=done)
        self.reusable = False
        self.transport.write(request)
        return done

    def close(self) -> None:
        self.closed = True
        if self.transport is not None:
            self.transport.close()

    def _finish(self, keep_alive: bool) -> None:
        exchange, self._exchange = self._exchange, None
        if exchange is None or exchange.done.done():
            return
        status = self._parser.get_status_code()
        self.reusable = keep_alive and not self.closed
        self.idle_since = time.monotonic()
        exchange.done.set_result(UpstreamResponse(status, exchange.headers, b"".join(exchange.body)))

    def _fail(self, error: UpstreamError) -> None:
        exchange, self._exchange = self._exchange, None
        if exchange is not None and not exchange.done.done():
            exchange.done.set_exception(error)
        self.close()


# Requests in flight to the controller at once; more wait their turn here (a stop never waits). Unbounded, 64
# clients opened 64 connections and closed all but 16 after each answer: a controller that caps its
# connections (the simulator's cap is 64 on a small open-file limit) closed kept-alive ones the proxy was
# about to use, and the churn of new connections left thousands of sockets in TIME_WAIT: 502s (issue #32).
MAX_IN_FLIGHT = 16


class UpstreamPool:
    """Keep-alive connections to one `host:port`, reused most recent first. Use from one event loop.

    At most `max_in_flight` requests are sent at once (others queue, first come first served), so at most
    that many connections are open, all of them kept; a request marked `urgent` (a stop) skips the queue."""

    def __init__(
        self,
        host: str,
        port: int,
        connect_timeout: float,
        read_timeout: float,
        keepalive_expiry: float = 2.0,
        max_in_flight: int = MAX_IN_FLIGHT,
    ) -> None:
        self.host, self.port = host, port
        self.connect_timeout, self.read_timeout = connect_timeout, read_timeout
        self.keepalive_expiry, self.max_idle = keepalive_expiry, max_in_flight
        self._host_header = host.encode() if port in (80, 443) else f"{host}:{port}".encode()
        self._idle: list[_Connection] = []
        self._turns = asyncio.Semaphore(max_in_flight)

    async def request(
        self,
        method: str,
        target: bytes,
        headers: list[tuple[bytes, bytes]],
        body: bytes,
        read_timeout: float | None = None,
        *,
        fresh: bool = False,
        urgent: bool = False,
    ) -> UpstreamResponse:
        """Send one request (`target`: path and query, raw) and return the whole answer; `read_timeout`
        (seconds) overrides the pool's for this request. `fresh`: on a new connection (a retry after a
        kept-alive one turned out dead); `urgent`: now, not after the requests waiting their turn."""
        if urgent:
            return await self._send(method, target, headers, body, read_timeout, fresh)
        async with self._turns:
            return await self._send(method, target, headers, body, read_timeout, fresh)

    async def _send(
        self,
        method: str,
        target: bytes,
        headers: list[tuple[bytes, bytes]],
        body: bytes,
        read_timeout: float | None,
        fresh: bool,
    ) -> UpstreamResponse:
        read_timeout = read_timeout if read_timeout is not None else self.read_timeout
        connection = await self._connection(fresh)
        head = [method.encode("ascii"), b" ", target, b" HTTP/1.1\r\nhost: ", self._host_header, b"\r\n"]
        for name, value in headers:
            head += (name, b": ", value, b"\r\n")
        if body or method not in ("GET", "HEAD", "DELETE", "OPTIONS"):
            head += (b"content-length: ", str(len(body)).encode(), b"\r\n")
        head.append(b"\r\n")
        done = connection.send(b"".join(head) + body, head_only=method == "HEAD")
        try:
            async with asyncio.timeout(read_timeout):
                response = await done
        except TimeoutError:
            connection.close()
            raise UpstreamTimeout(f"no answer within {read_timeout:g} s") from None
        if connection.reusable and len(self._idle) < self.max_idle:
            self._idle.append(connection)
        else:
            connection.close()
        return response

    async def aclose(self) -> None:
        idle, self._idle = self._idle, []
        for connection in idle:
            connection.close()

    async def _connection(self, fresh: bool) -> _Connection:
        now = time.monotonic()
        while self._idle and not fresh:
            connection = self._idle.pop()
            if not connection.closed and now - connection.idle_since < self.keepalive_expiry:
                return connection
            connection.close()
        loop = asyncio.get_running_loop()
        try:
            async with asyncio.timeout(self.connect_timeout):
                _transport, connection = await loop.create_connection(_Connection, self.host, self.port)
        except TimeoutError:
            raise UpstreamConnectError(f"no connection within {self.connect_timeout:g} s") from None
        except OSError as exc:
            raise UpstreamConnectError(exc.strerror or str(exc)) from exc
        return connection
