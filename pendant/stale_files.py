"""Temporary files left by a pendant that died mid-write (an atomic save's `.NAME.XXXX.tmp`, a recording
repair's `.mcap.tmp`): removed on start once old enough that no other pendant can still be writing them."""

from __future__ import annotations

import logging
import time
from collections.abc import Iterable
from pathlib import Path

log = logging.getLogger(__name__)

STALE_AFTER_S = 60.0  # an atomic write takes milliseconds: a minute-old temporary file is an orphan
PATTERNS = (".*.tmp", "*.mcap.tmp")


def remove_stale_temporaries(folders: Iterable[Path], now: float | None = None) -> list[Path]:
    """Delete orphaned temporary files directly in `folders`; the ones removed (missing folders skipped,
    files that cannot be removed left, with a warning)."""
    cutoff = (time.time() if now is None else now) - STALE_AFTER_S
    removed = []
    for folder in folders:
        if not folder.is_dir():
            continue
        for pattern in PATTERNS:
            for path in folder.glob(pattern):
                try:
                    if path.is_file() and path.stat().st_mtime < cutoff:
                        path.unlink()
                        removed.append(path)
                except OSError as error:
                    log.warning("could not remove the stale temporary file %s: %s", path, error)
    return removed
