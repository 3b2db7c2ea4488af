"""Recording the motors to CSV: one row per sample, every field of GET /status/motors for the six motors."""

from __future__ import annotations

import csv
import io
import threading

from pendant.controller.types import MotorStatus

CSV_FIELDS: tuple[str, ...] = tuple(MotorStatus.model_fields)
N_MOTORS = 6
MAX_ROWS = 10 * 3600 * 2  # two hours at 10 Hz; recording stops by itself after that


def csv_header() -> list[str]:
    """`time_s`, then `m1_angle`, `m1_rotorVelocity`, ... `m6_positionFeedback` (the controller's names)."""
    return ["time_s"] + [f"m{i + 1}_{field}" for i in range(N_MOTORS) for field in CSV_FIELDS]


class CsvRecorder:
    """Start, feed samples, stop, and hand out the CSV. Times are seconds since the recording started."""

    def __init__(self, max_rows: int = MAX_ROWS) -> None:
        self._rows: list[list[float]] = []
        self._started_at: float | None = None
        self._max_rows = max_rows
        self._lock = threading.Lock()

    @property
    def recording(self) -> bool:
        return self._started_at is not None

    @property
    def row_count(self) -> int:
        return len(self._rows)

    def start(self, now: float) -> None:
        """Begin a new recording (the previous one is discarded)."""
        with self._lock:
            self._rows = []
            self._started_at = now

    def stop(self) -> int:
        """End the recording; returns how many samples it holds (they stay until the next start)."""
        with self._lock:
            self._started_at = None
            return len(self._rows)

    def record(self, now: float, motors: list[MotorStatus]) -> None:
        with self._lock:
            if self._started_at is None:
                return
            row = [now - self._started_at]
            for motor in motors:
                row.extend(getattr(motor, field) for field in CSV_FIELDS)
            self._rows.append(row)
            if len(self._rows) >= self._max_rows:
                self._started_at = None

    def to_csv(self) -> bytes:
        with self._lock:
            rows = list(self._rows)
        out = io.StringIO()
        writer = csv.writer(out, lineterminator="\n")
        writer.writerow(csv_header())
        writer.writerows(
            [f"{value:.6f}" if i == 0 else repr(value) for i, value in enumerate(row)] for row in rows
        )
        return out.getvalue().encode()
