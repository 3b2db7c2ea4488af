"""Finished path recordings are kept in the data folder: one JSON file each (the downloadable format), the
newest 50; a folder that cannot be written costs the copy on disk, never the recording."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from pendant.sim import SimController
from pendant.teach.recording import MAX_KEPT, PathRecorder, Recording


def record(recorder: PathRecorder, sim: SimController, samples: int = 3) -> Recording:
    recorder.start()
    for k in range(samples):
        recorder.add(float(k), np.radians(sim.get_pose().angles), sim.get_position(), {}, {})
    recording = recorder.stop()
    assert recording is not None
    return recording


def test_each_recording_is_kept_as_its_json_and_only_the_newest_are_kept(
    tmp_path: Path, sim: SimController
) -> None:
    recorder = PathRecorder(tmp_path / "recordings")
    first = record(recorder, sim)
    assert first.file is not None and first.file.startswith("path-") and first.file.endswith(".json")
    kept = tmp_path / "recordings" / first.file
    assert kept.read_bytes() == first.to_json() and len(json.loads(kept.read_text())["samples"]) == 3
    for _ in range(MAX_KEPT + 1):
        last = record(recorder, sim)
    files = sorted(p.name for p in (tmp_path / "recordings").glob("path-*.json"))
    assert len(files) == MAX_KEPT and last.file in files and first.file not in files


def test_a_folder_that_cannot_be_written_keeps_the_recording_in_memory(
    tmp_path: Path, sim: SimController
) -> None:
    blocked = tmp_path / "a file, not a folder"
    blocked.write_text("")
    recorder = PathRecorder(blocked)
    recording = record(recorder, sim)
    assert recording.file is None and recorder.last is recording and len(recording.samples) == 3
