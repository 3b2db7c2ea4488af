"""One save at a time per programs folder, across threads and processes (two pendants, a pendant and
`pendant run` on the same folder): an flock on the folder itself, held while a save writes its file and
records its commit. Without it, two saves of one program at the same moment could each write the file and
then commit the other's bytes (one version lost, silently) or race on HEAD (one refused).

The folder's own descriptor is locked, not a lock file: nothing new appears in the folder or in `git status`,
and it works before the folder has a .git. The lock goes with the descriptor, so a killed process never
leaves it held."""

from __future__ import annotations

import contextlib
import fcntl
import os
import time
from collections.abc import Iterator
from pathlib import Path

LOCK_WAIT_S = (
    30.0  # a save and its commit take milliseconds; a folder locked longer is held by a stuck process
)
_POLL_S = 0.01


class FolderBusy(OSError):
    """Another save held the folder for longer than LOCK_WAIT_S."""


@contextlib.contextmanager
def saving(folder: Path, wait_s: float = LOCK_WAIT_S) -> Iterator[None]:
    """Hold the folder's save lock (creating the folder if needed) for the block."""
    folder.mkdir(parents=True, exist_ok=True)
    fd = os.open(folder, os.O_RDONLY)
    try:
        deadline = time.monotonic() + wait_s
        while True:
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                break
            except BlockingIOError:
                if time.monotonic() > deadline:
                    raise FolderBusy(f"another save has held {folder} for more than {wait_s:g} s") from None
                time.sleep(_POLL_S)  # a real other process: no clock of ours can stand in for this wait
        yield
    finally:
        os.close(fd)  # releases the lock
