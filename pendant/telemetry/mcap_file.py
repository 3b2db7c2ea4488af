"""A recording as an MCAP file written with Foxglove's SDK, which Foxglove opens as it is: the channels of
channels.ArmChannels (the arm in 3D, the cell, the TCP's course, the event log, the JSON series), the URDF
attached. Log times are wall-clock ns.

Chunks are flushed to disk at least every FLUSH_PERIOD_S, so a pendant killed with -9 leaves a file readable
up to its last flush (repair.py finishes it on the next start)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import foxglove
from foxglove.mcap import MCAPWriteOptions

from pendant import __version__
from pendant.controller.types import MotorStatus, Position
from pendant.telemetry.arm_scene import ArmDrawing
from pendant.telemetry.channels import ArmChannels

FLUSH_PERIOD_S = 1.0  # at most this much of a recording is lost to a kill -9


class McapFile(ArmChannels):
    """One recording being written. Not thread-safe: the caller (Telemetry) holds its lock."""

    def __init__(self, path: Path, arm: ArmDrawing | None = None, start_ns: int = 0) -> None:
        self.path = path
        context = foxglove.Context()
        options = MCAPWriteOptions(profile="", compression_threads=0)
        self._writer = foxglove.open_mcap(path, context=context, writer_options=options)
        self._writer.write_metadata("pendant", {"library": f"pulse-pendant {__version__}"})
        super().__init__(context, arm)
        if arm is not None:
            self._writer.attach(
                log_time=start_ns,
                create_time=start_ns,
                name=arm.urdf.name,
                media_type="application/xml",
                data=arm.urdf.read_bytes(),
            )
            self.write_arm(start_ns)
        self._flushed_ns = start_ns

    def write_sample(
        self,
        time_ns: int,
        motors: Sequence[MotorStatus],
        tcp: Position | None,
        outputs: Sequence[float],
        inputs: Sequence[float],
        motion_status: str | None,
    ) -> None:
        super().write_sample(time_ns, motors, tcp, outputs, inputs, motion_status)
        if time_ns - self._flushed_ns >= FLUSH_PERIOD_S * 1e9:
            self.flush(time_ns)

    def flush(self, time_ns: int) -> None:
        """Finish the current chunk and write it to disk: readable from here on, whatever happens next."""
        self._writer.flush()
        self._flushed_ns = time_ns

    def close(self) -> None:
        self._writer.close()
