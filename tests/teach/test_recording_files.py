"""Finished path recordings are kept in the data folder: one JSON file each (the downloadable format), the
newest 50, read back for a Path step simplified again; a folder that cannot be written costs the copy on
disk, never the recording."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from pendant.sim import SimController
from pendant.teach.recording import MAX_KEPT, PathRecorder, Recording, read_recording


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


def test_a_kept_recording_reads_back_as_it_was_and_other_names_are_refused(
    tmp_path: Path, sim: SimController
) -> None:
    recorder = PathRecorder(tmp_path)
    recording = record(recorder, sim)
    assert recording.file is not None
    again = read_recording(tmp_path, recording.file)
    assert again.to_json() == recording.to_json() and again.file == recording.file
    for name in ("../secret.json", "program.json", "path-1/../../x.json"):
        with pytest.raises(ValueError, match="not the name of a kept path recording"):
            read_recording(tmp_path, name)
    with pytest.raises(ValueError, match="no longer kept"):
        read_recording(tmp_path, "path-20000101-000000.000.json")
    (tmp_path / "path-20000101-000000.001.json").write_text('{"format": "something else"}')
    with pytest.raises(ValueError, match="cannot be read"):
        read_recording(tmp_path, "path-20000101-000000.001.json")
