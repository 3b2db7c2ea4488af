"""Tiny misbehaving servers on 127.0.0.1 for the fault tests."""

from __future__ import annotations

import socketserver
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager

Handler = Callable[[bytes], bytes | None]  # request head -> bytes to send (None: say nothing)


@contextmanager
def raw_server(handler: Handler) -> Iterator[str]:
    """A TCP server that reads each request head and answers whatever `handler` returns, raw; the URL."""
    release = threading.Event()

    class _Handler(socketserver.BaseRequestHandler):
        def handle(self) -> None:
            self.request.settimeout(5.0)
            try:
                while not release.is_set():
                    head = b""
                    while b"\r\n\r\n" not in head:
                        chunk = self.request.recv(4096)
                        if not chunk:
                            return
                        head += chunk
                    answer = handler(head)
                    if answer is None:  # hang: hold the connection until the test ends
                        release.wait(10.0)
                        return
                    self.request.sendall(answer)
            except OSError:
                return

    class _Server(socketserver.ThreadingTCPServer):
        daemon_threads = True
        allow_reuse_address = True

    server = _Server(("127.0.0.1", 0), _Handler)
    thread = threading.Thread(target=server.serve_forever, kwargs={"poll_interval": 0.05}, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}"
    finally:
        release.set()
        server.shutdown()
        server.server_close()


def http_answer(status: str, body: bytes, content_type: str = "text/plain") -> bytes:
    return (
        f"HTTP/1.1 {status}\r\ncontent-type: {content_type}\r\ncontent-length: {len(body)}\r\n\r\n".encode()
        + body
    )


def request_path(head: bytes) -> str:
    return head.split(b" ", 2)[1].decode()
