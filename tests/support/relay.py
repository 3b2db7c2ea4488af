"""A TCP relay on loopback in front of a real server that takes only so many connections at once, as an
embedded controller does: one more is closed at once, unanswered. It counts what it saw."""

from __future__ import annotations

import contextlib
import select
import socket
import threading
from collections.abc import Iterator
from dataclasses import dataclass, field

from .ports import LOOPBACK

CHUNK = 65536


@dataclass
class RelayStats:
    opened: int = 0  # connections accepted and relayed
    refused: int = 0  # connections closed at once: over the cap
    most_at_once: int = 0
    open_now: int = 0
    lock: threading.Lock = field(default_factory=threading.Lock)


@contextlib.contextmanager
def capped_relay(upstream_port: int, max_connections: int) -> Iterator[tuple[str, RelayStats]]:
    """(the relay's base URL, its counts) while it relays to 127.0.0.1:`upstream_port`."""
    stats = RelayStats()
    listener = socket.create_server((LOOPBACK, 0), backlog=512)
    listener.settimeout(0.2)  # the accept loop notices `stopping`
    stopping = threading.Event()

    def pipe(client: socket.socket) -> None:
        try:
            with client, socket.create_connection((LOOPBACK, upstream_port)) as upstream:
                ends = {client: upstream, upstream: client}
                while not stopping.is_set():
                    ready, _, _ = select.select(list(ends), [], [], 0.2)
                    for end in ready:
                        data = end.recv(CHUNK)
                        if not data:
                            return
                        ends[end].sendall(data)
        except OSError:
            pass
        finally:
            with stats.lock:
                stats.open_now -= 1

    def accept() -> None:
        while not stopping.is_set():
            try:
                client, _ = listener.accept()
            except TimeoutError:
                continue
            except OSError:
                return
            client.setblocking(True)
            with stats.lock:
                if stats.open_now >= max_connections:
                    stats.refused += 1
                    client.close()
                    continue
                stats.opened += 1
                stats.open_now += 1
                stats.most_at_once = max(stats.most_at_once, stats.open_now)
            threading.Thread(target=pipe, args=(client,), daemon=True).start()

    acceptor = threading.Thread(target=accept, daemon=True)
    acceptor.start()
    try:
        yield f"http://{LOOPBACK}:{listener.getsockname()[1]}", stats
    finally:
        stopping.set()
        acceptor.join(5)
        listener.close()
