"""One reading of the motors for everybody: the refresh loop calls `sample()` a few times a second.

A recording writes each sample to an MCAP file as it comes (joints, TCP, motors, IO, and the events logged
meanwhile) and keeps the CSV rows; stopping closes the MCAP and writes the CSV beside it, in the recordings
folder, where both stay to be downloaded later.
"""

from __future__ import annotations

import threading
import time
from collections import deque
from collections.abc import Callable
from pathlib import Path

from pendant.controller import Controller, ControllerError
from pendant.controller.types import MotorStatus
from pendant.eventlog import Event
from pendant.telemetry.arm_scene import ArmDrawing
from pendant.telemetry.channels import ArmState
from pendant.telemetry.history import HistoryWindow, MotorHistory
from pendant.telemetry.live import LiveView
from pendant.telemetry.mcap_file import McapFile
from pendant.telemetry.recorder import CsvRecorder
from pendant.telemetry.recordings import (
    MAX_KEPT,
    Recording,
    RecordingError,
    RecordingRefused,
    list_recordings,
    name_of,
    named_stem,
    new_stem,
    prune,
)

SAMPLE_HZ = 10.0
PENDING_EVENTS_MAX = 1000  # events waiting for the next sample to be written to the MCAP


class Telemetry:
    """Reads GET /status/motors once per call and feeds the shared history and the recording (its files go
    to `recordings_folder`, created when the first recording starts)."""

    def __init__(
        self,
        controller: Controller,
        now: Callable[[], float] = time.monotonic,
        *,
        recordings_folder: Path,
        wall_now: Callable[[], float] = time.time,
        arm: ArmDrawing | None = None,
    ) -> None:
        self._controller = controller
        self._arm = arm  # draws the arm in the recording's 3D channels
        self._now = now
        self._wall_now = wall_now
        self.history = MotorHistory()
        self.long_history = MotorHistory.long()
        self.recorder = CsvRecorder()
        self.recordings_folder = recordings_folder
        self.mcap: McapFile | None = None
        self.live: LiveView | None = None  # the Foxglove live view (--foxglove-port), fed every sample
        self.last_stem: str | None = None
        self.latest: list[MotorStatus] | None = None
        self.seq = 0  # counts samples: the dashboard redraws only when it moved
        self._wall_offset = 0.0  # wall clock minus `now`, fixed at the recording's start
        self._pending_events: deque[Event] = deque(maxlen=PENDING_EVENTS_MAX)
        self._lock = threading.Lock()

    def sample(self, state: ArmState | None = None) -> list[MotorStatus] | None:
        """Read the motors once; None (and nothing recorded) when the controller cannot answer."""
        try:
            motors = self._controller.get_motors()
        except ControllerError:
            self.latest = None
            return None
        now = self._now()
        with self._lock:
            self.history.append(now, motors)
            self.long_history.append(now, motors)
            self.recorder.record(now, motors)
            self.latest = motors
            self.seq += 1
            if self.mcap is not None:
                self._write_mcap(now, motors, state or ArmState())
        if self.live is not None:
            self.live.publish(motors, state or ArmState())
        return motors

    def log_event(self, event: Event) -> None:
        """An event to go into the running recording's /events channel (any thread; written at the next
        sample, by the refresh loop)."""
        if self.mcap is not None:
            self._pending_events.append(event)
        if self.live is not None:
            self.live.log_event(event)

    def _write_mcap(self, now: float, motors: list[MotorStatus], state: ArmState) -> None:
        assert self.mcap is not None
        time_ns = int((now + self._wall_offset) * 1e9)
        while self._pending_events:
            self.mcap.write_event(self._pending_events.popleft())
        self.mcap.write_state(time_ns, motors, state)
        if not self.recorder.recording:  # the CSV reached its limit: so does the MCAP
            self._close_files()

    @property
    def arm(self) -> ArmDrawing | None:
        """What draws the arm in the 3D channels (the live view draws it the same way)."""
        return self._arm

    def attach_live(self, live: LiveView) -> None:
        """Feed the Foxglove live view every sample from now on, the arm drawn as in the recordings."""
        live.channels.arm = self._arm
        self.live = live

    def stop_live(self) -> None:
        live, self.live = self.live, None
        if live is not None:
            live.stop()

    @property
    def running(self) -> str | None:
        """The name of the recording being written, if any."""
        return name_of(self.last_stem) if self.mcap is not None and self.last_stem is not None else None

    def start_recording(self, name: str | None = None, *, exclusive: bool = False) -> str:
        """Start a recording (named `name`, else by its start time) and return its name. The Dashboard's
        button finishes a running one first; `exclusive` (scripts) refuses instead (RecordingRefused)."""
        if self._arm is not None:
            _ = self._arm.meshes  # read once, outside the lock: the samples go on while the URDF is read
        with self._lock:
            if exclusive and self.running is not None:
                raise RecordingRefused(
                    409, f"Recording {self.running!r} is running: stop it first (one recording at a time)"
                )
            stem = None if name is None else named_stem(self.recordings_folder, name)
            self._close_files()
            now, wall = self._now(), self._wall_now()
            try:
                self.recordings_folder.mkdir(parents=True, exist_ok=True)
                prune(self.recordings_folder, keep=MAX_KEPT - 1)  # room for this one
                stem = stem or new_stem(self.recordings_folder, wall)
                self.mcap = McapFile(
                    self.recordings_folder / f"{stem}.mcap", self._arm, start_ns=int(wall * 1e9)
                )
            except OSError as error:
                reason = error.strerror or str(error)
                raise RecordingError(
                    f"Cannot record in {self.recordings_folder} ({reason}): make that folder writable or "
                    "free space on its disk, or start the pendant with --data DIR"
                ) from error
            self.last_stem = stem
            self.recorder.start(now)
            self._wall_offset = wall - now
            self._pending_events.clear()
            return name_of(stem)

    def stop_recording(self) -> int:
        with self._lock:
            rows = self.recorder.stop()
            self._close_files()
            return rows

    def _close_files(self) -> None:
        """Finish the MCAP and write the CSV beside it (the lock is held)."""
        if self.mcap is None:
            return
        self.mcap.close()
        self.mcap = None
        if self.last_stem is not None:
            (self.recordings_folder / f"{self.last_stem}.csv").write_bytes(self.recorder.to_csv())

    def window(self, seconds: float) -> HistoryWindow:
        """The last `seconds` of the motors: at full rate within a minute, at 2 Hz up to an hour."""
        history = self.history if seconds <= self.history.seconds else self.long_history
        return history.window(seconds)

    def recordings(self) -> list[Recording]:
        """The recordings in the folder, newest first (see recordings.list_recordings)."""
        return list_recordings(self.recordings_folder)
