"""Recordings for tests that need a big one: written with the pendant's own recorder (McapFile), or a sparse
file of a given size (for what only reads the bytes, such as a download)."""

from __future__ import annotations

import os
from pathlib import Path

from pendant.telemetry.mcap_file import McapFile
from pendant.telemetry.messages import Joints

SAMPLE_PERIOD_NS = 100_000_000  # 10 Hz, as the pendant samples
TWO_HOURS = 72_000  # samples: the longest recording the pendant makes (telemetry.recorder.MAX_ROWS)
STEP_EVERY = 100  # samples between program step changes
MARK_EVERY = 64 * 1024 * 1024  # a sparse file's bytes that are not zero: one block this often


def write_long_recording(path: Path, samples: int = TWO_HOURS) -> Path:
    """A finished recording of `samples` joint readings with a program stepping through five moves."""
    mcap = McapFile(path)
    try:
        for i in range(samples):
            time_ns = i * SAMPLE_PERIOD_NS
            angles = [(i * 0.01 + 10.0 * j) % 180.0 for j in range(6)]
            joints = Joints(name=[f"J{j + 1}" for j in range(6)], position_deg=angles, velocity_rpm=[0.0] * 6)
            mcap.write("/joints", time_ns, joints)
            if i % STEP_EVERY == 0:
                line = i // STEP_EVERY % 5 + 1
                mcap.write_program(time_ns, line, f"Move J to P{line}", "running")
    finally:
        mcap.close()
    return path


def write_sparse_file(path: Path, size: int) -> Path:
    """`size` bytes, mostly holes, with a block of distinct bytes every MARK_EVERY (so a copy can be told
    from a file of zeros)."""
    with path.open("wb") as file:
        file.truncate(size)
        for offset in range(0, size, MARK_EVERY):
            file.seek(offset)
            file.write(os.urandom(min(4096, size - offset)))
    return path
