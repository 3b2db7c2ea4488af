"""Recording the arm's path: timestamps, joints, TCP and IO, sampled from the pendant's 30 Hz reading of
the controller while the operator free-drives or jogs; simplified into at most 100 waypoints on stop.

A finished recording is kept in the data folder (`<data>/recordings/path-YYYYmmdd-HHMMSS.mmm.json`, the
newest MAX_KEPT), so the raw path behind a program's Path step outlives the pendant."""

from __future__ import annotations

import json
import logging
import re
import threading
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path

import numpy as np
import viser.transforms as vtf
from pydantic import BaseModel, Field, ValidationError

from pendant.controller import Pose, Position, SignalLevel
from pendant.kinematics.transforms import position_to_matrix
from pendant.program.files import atomic_write
from pendant.teach.simplify import DEFAULT_TOL_DEG, DEFAULT_TOL_MM, simplify_to

FORMAT = "pulse-pendant-path-recording"
SCHEMA_VERSION = 1
MAX_SAMPLES = 18_000  # ten minutes at 30 Hz (about 4 MB of JSON); the recording stops there
PREFIX = "path-"
MAX_KEPT = 50

_FILE_NAME = re.compile(r"path-[0-9.\-]+\.json")

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class Sample:
    t: float  # seconds since the recording started
    joints_deg: tuple[float, ...]
    tcp: Position  # the controller's GET /position: TCP in the zero point frame (metres, radians)
    outputs: dict[int, SignalLevel]
    inputs: dict[int, SignalLevel]


@dataclass
class Recording:
    started_at: str  # ISO 8601, UTC
    samples: list[Sample] = field(default_factory=list)
    file: str | None = None  # where it was kept (a name in the recordings folder), once finished

    @property
    def duration_s(self) -> float:
        return self.samples[-1].t if self.samples else 0.0

    @property
    def rate_hz(self) -> float:
        return (len(self.samples) - 1) / self.duration_s if self.duration_s > 0 else 0.0

    def to_json(self) -> bytes:
        """The raw recording, as documented in the README ("Path recording")."""
        return json.dumps(
            {
                "format": FORMAT,
                "schema_version": SCHEMA_VERSION,
                "started_at": self.started_at,
                "rate_hz": round(self.rate_hz, 2),
                "samples": [
                    {
                        "t": round(s.t, 4),
                        "joints_deg": [round(v, 4) for v in s.joints_deg],
                        "tcp": s.tcp.model_dump(),
                        "outputs": {str(p): level.value for p, level in s.outputs.items()},
                        "inputs": {str(p): level.value for p, level in s.inputs.items()},
                    }
                    for s in self.samples
                ],
            },
            indent=1,
        ).encode()

    def waypoints(
        self, tol_mm: float = DEFAULT_TOL_MM, tol_deg: float = DEFAULT_TOL_DEG
    ) -> tuple[list[tuple[Pose, Position]], float, float]:
        """The fewest samples (at most 100) whose straight segments keep every sample within the tolerances
        (relaxed if 100 are not enough); returns them and the tolerances used."""
        if len(self.samples) < 2:
            raise ValueError("the recording holds fewer than two samples: nothing moved")
        T = np.stack([position_to_matrix(s.tcp) for s in self.samples])
        kept, tol_mm, tol_deg = simplify_to(
            T[:, :3, 3] * 1000.0, vtf.SO3.from_matrix(T[:, :3, :3]), tol_mm, tol_deg
        )
        chosen = [self.samples[i] for i in kept]
        return [(Pose(angles=list(s.joints_deg)), s.tcp) for s in chosen], tol_mm, tol_deg


class _SampleDocument(BaseModel):
    t: float
    joints_deg: list[float] = Field(min_length=6, max_length=6)
    tcp: Position
    outputs: dict[int, SignalLevel]
    inputs: dict[int, SignalLevel]


class _RecordingDocument(BaseModel):
    format: str = Field(pattern=f"^{FORMAT}$")
    schema_version: int = Field(ge=SCHEMA_VERSION, le=SCHEMA_VERSION)
    started_at: str
    samples: list[_SampleDocument] = Field(max_length=MAX_SAMPLES)


def read_recording(folder: Path, name: str) -> Recording:
    """A kept recording, read back (ValueError saying why when it is not there or not one)."""
    if not _FILE_NAME.fullmatch(name):
        raise ValueError(f"{name!r} is not the name of a kept path recording")
    try:
        document = _RecordingDocument.model_validate_json((folder / name).read_bytes())
    except FileNotFoundError as error:
        raise ValueError(f"the recording {name} is no longer kept (the newest {MAX_KEPT} are)") from error
    except (OSError, ValidationError) as error:
        raise ValueError(f"the recording {name} cannot be read: {error}") from error
    samples = [
        Sample(s.t, tuple(s.joints_deg), s.tcp, dict(s.outputs), dict(s.inputs)) for s in document.samples
    ]
    return Recording(document.started_at, samples, name)


class PathRecorder:
    """Fed every reading of the controller; keeps them while recording. Thread-safe: the refresh loop
    feeds it, the page starts and stops it."""

    def __init__(self, folder: Path | None = None) -> None:
        self._folder = folder  # where finished recordings are kept (None: in memory only)
        self._lock = threading.Lock()
        self._recording: Recording | None = None
        self._t0 = 0.0
        self._last_t: float | None = None
        self.last: Recording | None = None  # the last finished recording, for download

    @property
    def folder(self) -> Path | None:
        return self._folder

    @property
    def active(self) -> bool:
        return self._recording is not None

    @property
    def samples(self) -> int:
        with self._lock:
            return len(self._recording.samples) if self._recording is not None else 0

    def start(self) -> None:
        with self._lock:
            self._recording = Recording(started_at=datetime.now(UTC).isoformat(timespec="milliseconds"))
            self._last_t = None

    def add(
        self,
        taken_at: float,
        q_rad: np.ndarray | None,
        tcp: Position | None,
        outputs: dict[int, SignalLevel],
        inputs: dict[int, SignalLevel],
    ) -> None:
        """One reading (monotonic seconds); ignored unless recording, or when it holds no pose."""
        with self._lock:
            recording = self._recording
            if recording is None or q_rad is None or tcp is None or taken_at == self._last_t:
                return
            if not recording.samples:
                self._t0 = taken_at
            self._last_t = taken_at
            joints = tuple(float(v) for v in np.degrees(q_rad))
            recording.samples.append(Sample(taken_at - self._t0, joints, tcp, dict(outputs), dict(inputs)))
            full = len(recording.samples) >= MAX_SAMPLES
            if full:
                self.last, self._recording = recording, None
        if full:
            self._keep(recording)

    def stop(self) -> Recording | None:
        with self._lock:
            recording, self._recording = self._recording, None
            if recording is not None:
                self.last = recording
        if recording is not None:
            self._keep(recording)
        return recording if recording is not None else self.last

    def _keep(self, recording: Recording) -> None:
        """Write it to the recordings folder (atomically) and drop the oldest beyond MAX_KEPT; a full disk
        costs the copy on disk, never the recording in memory or the step made from it."""
        if self._folder is None or not recording.samples:
            return
        stamp = datetime.fromisoformat(recording.started_at).strftime("%Y%m%d-%H%M%S.%f")[:-3]
        name = f"{PREFIX}{stamp}.json"
        k = 1
        while (self._folder / name).exists():
            k += 1
            name = f"{PREFIX}{stamp}-{k}.json"
        try:
            self._folder.mkdir(parents=True, exist_ok=True)
            atomic_write(self._folder / name, recording.to_json())
            kept = sorted(self._folder.glob(f"{PREFIX}*.json"), key=lambda p: (p.stat().st_mtime_ns, p.name))
            for old in kept[:-MAX_KEPT]:
                old.unlink(missing_ok=True)
        except OSError as error:
            log.warning("path recording not kept on disk: %s", error)
            return
        recording.file = name
