"""JSON of a program file read without holding the interpreter for long (issue #32).

The page reads program files (Upload, Load, a Call's program, a version from the history) in the server's
process, beside the threads that send Freeze. `json.loads` is one call into C that holds the GIL until the
whole document is built: 50-76 ms of CPU for a 4.7 MB program, longer for a file of many small objects, and a
Freeze pressed meanwhile waits for it. A document over C_JSON_BYTES is parsed by json's own Python scanner
instead (its strings still in C, one at a time): several times slower, but the other threads get their turn
every few milliseconds. The garbage collector is kept off meanwhile: the hundreds of thousands of objects of
a big file would otherwise set off a full collection, one more call that holds every thread (120 ms,
measured), for a tree that has no cycles and goes as soon as it is read. A program the pendant saved is
under C_JSON_BYTES (docs/limits.md: ~1.6 MB at most for 2,000 steps), so it loads as fast as before.
"""

from __future__ import annotations

import contextlib
import gc
import json
import json.scanner
import threading
from collections.abc import Iterator
from typing import Any

# json.loads in C below this: ~5-8 ms of CPU for 470 kB, ~11 ms for 1 MB (measured on this machine).
C_JSON_BYTES = 1_000_000

_collector = threading.Lock()
_readers = 0  # big documents being read now (the collector is off while any is)
_was_enabled = False


def loads(data: bytes) -> Any:
    """`json.loads(data)`, in small steps for a big document: the same result and the same errors."""
    if not is_big(data):
        return json.loads(data)
    text = data.decode(json.detect_encoding(data), "surrogatepass")  # as json.loads decodes bytes
    decoder = json.JSONDecoder()
    decoder.scan_once = json.scanner.py_make_scanner(decoder)  # type: ignore[attr-defined]  # Python's
    with collector_off():
        return decoder.decode(text)


def is_big(data: bytes) -> bool:
    """Read a bit at a time, with the collector off (see the module)."""
    return len(data) > C_JSON_BYTES


@contextlib.contextmanager
def collector_off() -> Iterator[None]:
    """No automatic garbage collection in this block (the first reader turns it off, the last one back on
    as it found it; blocks may nest); collection counts fall back as the objects read are freed, so none
    is owed after if they are freed inside it."""
    global _readers, _was_enabled
    with _collector:
        if _readers == 0:
            _was_enabled = gc.isenabled()
            gc.disable()
        _readers += 1
    try:
        yield
    finally:
        with _collector:
            _readers -= 1
            if _readers == 0 and _was_enabled:
                gc.enable()
