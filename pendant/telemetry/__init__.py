"""Motor telemetry: one shared reading of GET /status/motors at a modest rate, a rolling 60 s history for the
dashboard's plots, and recording to CSV."""

from __future__ import annotations

from pendant.telemetry.history import HISTORY_S, MotorHistory
from pendant.telemetry.recorder import CSV_FIELDS, CsvRecorder, csv_header
from pendant.telemetry.sampler import Telemetry

__all__ = ["CSV_FIELDS", "HISTORY_S", "CsvRecorder", "MotorHistory", "Telemetry", "csv_header"]
