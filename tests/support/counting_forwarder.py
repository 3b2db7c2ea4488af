"""A forwarding HTTP server that counts the requests it passes to the arm, by method (real HTTP, loopback)."""

from __future__ import annotations

import collections
import contextlib
import threading
import urllib.error
import urllib.request
from collections.abc import Iterator
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer

from tests.support.ports import LOOPBACK
from tests.support.waiting import SAFETY_NET_S

HOP_HEADERS = {"connection", "keep-alive", "transfer-encoding", "host", "content-length"}


@contextlib.contextmanager
def counting_forwarder(upstream: str) -> Iterator[tuple[str, collections.Counter[str]]]:
    """(its URL, the count of requests by method) while it forwards everything to `upstream`."""
    counts: collections.Counter[str] = collections.Counter()
    lock = threading.Lock()

    class Forward(BaseHTTPRequestHandler):
        def _forward(self) -> None:
            with lock:
                counts[self.command] += 1
            length = int(self.headers.get("Content-Length") or 0)
            body = self.rfile.read(length) if length else None
            headers = {k: v for k, v in self.headers.items() if k.lower() not in HOP_HEADERS}
            request = urllib.request.Request(upstream + self.path, body, headers, method=self.command)
            try:
                with urllib.request.urlopen(request, timeout=SAFETY_NET_S) as answer:
                    status, data, answer_headers = answer.status, answer.read(), answer.headers
            except urllib.error.HTTPError as error:
                status, data, answer_headers = error.code, error.read(), error.headers
            self.send_response(status)
            for key, value in answer_headers.items():
                if key.lower() not in HOP_HEADERS:
                    self.send_header(key, value)
            self.send_header("Content-Length", str(len(data)))
            self.end_headers()
            self.wfile.write(data)

        do_GET = do_PUT = do_POST = do_DELETE = _forward

        def log_message(self, format: str, *args: object) -> None:
            pass

    server = ThreadingHTTPServer((LOOPBACK, 0), Forward)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://{LOOPBACK}:{server.server_address[1]}", counts
    finally:
        server.shutdown()
        server.server_close()
