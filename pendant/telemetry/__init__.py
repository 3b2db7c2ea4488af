"""Motor telemetry: one shared reading of GET /status/motors at a modest rate, a rolling 60 s history for the
dashboard's plots, and recordings to MCAP (Foxglove's schemas: the arm in 3D, the cell, the log) and CSV kept
in a folder; an unfinished recording (the pendant was killed) is finished on the next start; the same
channels live over the Foxglove WebSocket protocol (LiveView)."""

from __future__ import annotations

from pendant.telemetry.arm_scene import ArmDrawing, arm_drawing
from pendant.telemetry.channels import ArmState
from pendant.telemetry.history import HISTORY_S, MotorHistory
from pendant.telemetry.live import LiveView
from pendant.telemetry.recorder import CSV_FIELDS, CsvRecorder, csv_header
from pendant.telemetry.recordings import Recording, list_recordings, recordings_dir
from pendant.telemetry.sampler import Telemetry

__all__ = [
    "CSV_FIELDS",
    "HISTORY_S",
    "ArmDrawing",
    "ArmState",
    "CsvRecorder",
    "LiveView",
    "MotorHistory",
    "Recording",
    "Telemetry",
    "arm_drawing",
    "csv_header",
    "list_recordings",
    "recordings_dir",
]
