"""The page the browsers load: viser's own, with the pendant's script (client_page.js) in front of it.

viser 1.1.1 serves one self-contained index.html from its websocket server's `process_request`. The pendant
answers requests for the page itself with a copy carrying its script, and hands every other request (the
websocket handshake included) to whatever handled it before, so other hooks compose with this one.
"""

from __future__ import annotations

import gc
import gzip
import http
from collections.abc import Awaitable, Callable
from functools import cache
from pathlib import Path

import viser
from websockets.asyncio.server import Server, ServerConnection
from websockets.datastructures import Headers
from websockets.http11 import Request, Response

PAGE_PATHS = ("/", "/index.html")
SCRIPT_PATH = Path(__file__).with_name("client_page.js")
VISER_PAGE = Path(viser.__file__).resolve().parent / "client" / "build" / "index.html"

ProcessRequest = Callable[[ServerConnection, Request], "Response | Awaitable[Response | None] | None"]


@cache
def page_html() -> bytes:
    """viser's page with the pendant's script as the first thing in <head>, before viser's own."""
    page = VISER_PAGE.read_bytes()
    script = b"<script>" + SCRIPT_PATH.read_bytes() + b"</script>"
    head = page.index(b"<head>") + len(b"<head>")
    return page[:head] + script + page[head:]


@cache
def _page_gzipped() -> bytes:
    return gzip.compress(page_html())


def page_response(request: Request) -> Response | None:
    """The pendant's page for a GET of the page itself; None for anything else (assets, the websocket)."""
    if request.headers.get("Upgrade", "").lower() == "websocket":
        return None
    if request.path.partition("?")[0] not in PAGE_PATHS:
        return None
    zipped = "gzip" in request.headers.get("Accept-Encoding", "")
    body = _page_gzipped() if zipped else page_html()
    headers = Headers(
        {
            "Content-Type": "text/html; charset=utf-8",
            "Content-Length": str(len(body)),
            "Content-Encoding": "gzip" if zipped else "identity",
            "Cache-Control": "no-store",
        }
    )
    return Response(http.HTTPStatus.OK, "OK", headers, body)


def websockets_server(server: viser.ViserServer) -> Server:
    """The websockets server behind `server` (viser keeps no reference to it: found by its port)."""
    port = server.get_port()
    for obj in gc.get_objects():
        if isinstance(obj, Server) and any(s.getsockname()[1] == port for s in obj.server.sockets):
            return obj
    raise RuntimeError(f"no websockets server listening on port {port}")


def chain_process_request(server: viser.ViserServer, hook: Callable[[Request], Response | None]) -> None:
    """Put `hook` in front of the server's request handling: its response wins, None passes on."""
    ws = websockets_server(server)
    previous: ProcessRequest | None = ws.process_request

    async def process_request(connection: ServerConnection, request: Request) -> Response | None:
        response = hook(request)
        if response is not None or previous is None:
            return response
        result = previous(connection, request)
        return await result if isinstance(result, Awaitable) else result

    ws.process_request = process_request


def serve_client_page(server: viser.ViserServer) -> None:
    chain_process_request(server, page_response)
