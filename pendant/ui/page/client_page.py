"""The page the browsers load: viser's own, with the pendant's script (client_page.js) in front of it.

viser 1.1.1 serves one self-contained index.html from its websocket server's `process_request`. The pendant
answers requests for the page itself with a copy carrying its script, and hands every other request (the
websocket handshake included) to viser's handler (`page_first`, installed by ws_guard while the
server is built, behind the Host and Origin guard).
"""

from __future__ import annotations

import asyncio
import gzip
import http
import inspect
from collections.abc import Awaitable, Callable
from functools import cache
from pathlib import Path

import viser
from websockets.asyncio.server import ServerConnection
from websockets.datastructures import Headers
from websockets.http11 import Request, Response

PAGE_PATHS = ("/", "/index.html")
# A page closing with a jog held asks for the stop here too (a keepalive fetch, which outlives the page): it
# does not wait for its worker's last message, which may die with the page, nor for the deadman.
STOP_JOG_PATH = "/pendant-stop-jog"
SCRIPT_PATH = Path(__file__).with_name("client_page.js")
VIEW_FRAMES_PATH = Path(__file__).with_name("view_frames.js")  # the 3D view's pixels off the main thread
REST_FRAMES_PATH = Path(__file__).with_name("rest_frames.js")  # viser's heartbeat frame less often
BANNER_SCRIPT_PATH = Path(__file__).with_name("banner_pin.js")  # the banner stays in sight
ACCESSIBILITY_PATH = Path(__file__).with_name("accessibility.js")  # labels and contrast: a script of its own
PHONE_LAYOUT_PATH = Path(__file__).with_name("phone_layout.js")  # the bottom sheet on a phone
TYPED_FIELDS_PATH = Path(__file__).with_name("typed_fields.js")  # a box's text is sent when committed
TOUCH_LAYOUT_PATH = Path(__file__).with_name("touch_layout.js")  # 44 px targets; the phone's pad and status
JOG_KEYS_PATH = Path(__file__).with_name("jog_keys.js")  # the jog pad: one Tab stop, arrows inside it
GHOST_LEGEND_PATH = Path(__file__).with_name("ghost_legend.js")  # which ghost the 3D view shows
VISER_PAGE = Path(viser.__file__).resolve().parent / "client" / "build" / "index.html"

ProcessRequest = Callable[[ServerConnection, Request], "Response | Awaitable[Response | None] | None"]


@cache
def page_html() -> bytes:
    """viser's page with the pendant's scripts as the first thing in <head>, before viser's own."""
    page = VISER_PAGE.read_bytes()
    script = b"".join(
        b"<script>" + path.read_bytes() + b"</script>"
        for path in (
            SCRIPT_PATH,
            VIEW_FRAMES_PATH,
            REST_FRAMES_PATH,
            BANNER_SCRIPT_PATH,
            ACCESSIBILITY_PATH,
            PHONE_LAYOUT_PATH,
            TYPED_FIELDS_PATH,
            TOUCH_LAYOUT_PATH,
            JOG_KEYS_PATH,
            GHOST_LEGEND_PATH,
        )
    )
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


def stop_jog_response() -> Response:
    headers = Headers({"Content-Length": "0", "Cache-Control": "no-store"})
    return Response(http.HTTPStatus.NO_CONTENT, "No Content", headers, b"")


def page_first(inner: ProcessRequest | None, stop_jog: Callable[[], None] | None = None) -> ProcessRequest:
    """The pendant's page for requests of the page itself, `stop_jog` for a closing page's stop, `inner`
    (viser's, possibly wrapped) for the rest: its files and the websocket handshake. A stop is not a command:
    like Freeze it needs no token (and it only ever stops)."""

    async def process_request(connection: ServerConnection, request: Request) -> Response | None:
        if stop_jog is not None and request.path.partition("?")[0] == STOP_JOG_PATH:
            await asyncio.to_thread(stop_jog)
            return stop_jog_response()
        response = page_response(request)
        if response is not None or inner is None:
            return response
        result = inner(connection, request)
        return await result if inspect.isawaitable(result) else result

    return process_request
