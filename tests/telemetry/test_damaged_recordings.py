"""Whatever a recording file holds, repair and replay answer in words and in bounded time and memory: a file
cut short is finished up to its last complete chunk; anything else (random bytes, zeros, lengths of 2^62, a
zstd bomb, lz4 garbage, a file cut before its first chunk) is moved to recordings/damaged/ with its bytes
unchanged and a line saying why; replay refuses such a file with a message, never a traceback."""

from __future__ import annotations

import tracemalloc
from pathlib import Path

import pytest
from mcap.reader import make_reader

from pendant.telemetry.mcap_scan import MAX_CHUNK_BYTES, MAX_RECORD_BYTES, Damaged, records
from pendant.telemetry.repair import DAMAGED, finished, repair_all, repair_safely
from pendant.telemetry.replay import ReplayError, load_replay
from tests.support.recordings import CRAFTED, bad_summary_offsets, crafted, make_recording, zstd_bomb

CUT_STEP = 4096
RECORDED_S = 30.0
NAME = "pendant-20270101-000000.mcap"
# Memory one file may cost: a record and a decompressed chunk at most, and as much for the copy being written.
MEMORY_BOUND = 2 * (MAX_RECORD_BYTES + MAX_CHUNK_BYTES)


@pytest.fixture(scope="module")
def unfinished(tmp_path_factory: pytest.TempPathFactory) -> bytes:
    """The bytes a pendant killed after a minute of recording leaves."""
    folder = tmp_path_factory.mktemp("recording")
    make_recording(folder / "live", RECORDED_S, unfinished_copy=folder / NAME)
    return (folder / NAME).read_bytes()


@pytest.fixture(scope="module")
def real(tmp_path_factory: pytest.TempPathFactory) -> bytes:
    """A finished recording of a few seconds."""
    return make_recording(tmp_path_factory.mktemp("finished"), 3.0).read_bytes()


def message_count(path: Path) -> int:
    with path.open("rb") as stream:
        return sum(1 for _ in make_reader(stream).iter_messages(log_time_order=False))


def test_a_recording_cut_at_every_4_kib_boundary_is_finished_or_moved_aside_intact(
    unfinished: bytes, tmp_path: Path
) -> None:
    counts = []
    for cut in range(0, len(unfinished), CUT_STEP):
        folder = tmp_path / f"cut-{cut}"
        folder.mkdir()
        (folder / NAME).write_bytes(unfinished[:cut])
        [note] = repair_all(folder)
        assert NAME.removesuffix(".mcap") in note
        moved = folder / DAMAGED / NAME
        if moved.exists():
            assert moved.read_bytes() == unfinished[:cut], f"cut at {cut}: the bytes moved aside changed"
            assert "could not be repaired" in note and not (folder / NAME).exists(), note
            counts.append(0)
        else:
            assert "repaired" in note and finished(folder / NAME), f"cut at {cut}: {note}"
            counts.append(message_count(folder / NAME))
            assert load_replay(folder / NAME).duration_s >= 0.0
    assert counts == sorted(counts), "a longer piece never gives fewer messages"
    assert counts[-1] > 0, counts


@pytest.mark.parametrize("name", CRAFTED)
def test_a_crafted_file_is_moved_aside_with_its_bytes_and_replay_says_why(name: str, tmp_path: Path) -> None:
    data = crafted(name)
    path = tmp_path / f"pendant-{name}.mcap"
    path.write_bytes(data)
    moved = tmp_path / DAMAGED / path.name
    tracemalloc.start()
    try:
        [note] = repair_all(tmp_path)
        with pytest.raises(ReplayError) as refused:
            load_replay(moved)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < MEMORY_BOUND, f"{name}: {peak / 1e6:.0f} MB"
    assert f"pendant-{name} could not be repaired (" in note and f"{DAMAGED}/pendant-{name}.mcap" in note
    assert moved.read_bytes() == data and not path.exists()
    assert path.name in str(refused.value) and "\n" not in str(refused.value)


def test_a_finished_recording_whose_summary_points_past_its_end_is_replayed_from_its_data(
    real: bytes, tmp_path: Path
) -> None:
    path = tmp_path / NAME
    path.write_bytes(bad_summary_offsets(real))
    assert repair_all(tmp_path) == [] and path.read_bytes() == bad_summary_offsets(real)
    assert load_replay(path).duration_s > 0.0


def test_a_recording_killed_while_writing_its_summary_is_repaired_whole(real: bytes, tmp_path: Path) -> None:
    footer = len(real) - 8 - 29  # the footer record (opcode, length, three fields), then the magic
    summary_start = int.from_bytes(real[footer + 9 : footer + 17], "little")
    path = tmp_path / NAME
    path.write_bytes(real[: summary_start + 10])
    finished_copy = tmp_path / "finished.mcap"
    finished_copy.write_bytes(real)
    [note] = repair_all(tmp_path)
    assert "repaired" in note and finished(path) and not (tmp_path / DAMAGED).exists(), note
    assert message_count(path) == message_count(finished_copy)


def test_random_bytes_after_a_real_start_are_moved_aside_keeping_what_was_readable(
    unfinished: bytes, tmp_path: Path
) -> None:
    cut = len(unfinished) // 2
    damaged = unfinished[:cut] + bytes(range(256)) * 64 + unfinished[cut:]
    path = tmp_path / NAME
    path.write_bytes(damaged)
    note = repair_safely(path)
    assert "could not be repaired" in note and "messages before the damage are kept" in note, note
    assert (tmp_path / DAMAGED / NAME).read_bytes() == damaged
    assert finished(path) and message_count(path) > 0


def test_reading_stops_at_its_time_limit_with_a_message(unfinished: bytes, tmp_path: Path) -> None:
    path = tmp_path / NAME
    path.write_bytes(unfinished)
    note = repair_safely(path, time_limit_s=0.0)
    assert "took longer than 0 s" in note and (tmp_path / DAMAGED / NAME).read_bytes() == unfinished
    with pytest.raises(ReplayError, match="took longer than 0 s"):
        load_replay(tmp_path / DAMAGED / NAME, time_limit_s=0.0)


def test_a_zstd_bomb_is_decompressed_no_further_than_a_chunk(tmp_path: Path) -> None:
    """A chunk that truthfully says it holds MAX_CHUNK_BYTES of zeros: read up to there, then refused."""
    path = tmp_path / NAME
    path.write_bytes(zstd_bomb(MAX_CHUNK_BYTES))
    tracemalloc.start()
    try:
        with path.open("rb") as stream, pytest.raises(Damaged, match="damaged record"):
            list(records(stream, path.stat().st_size, time_limit_s=60.0))
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < MEMORY_BOUND, f"{peak / 1e6:.0f} MB"


@pytest.mark.parametrize("which", ["finished", "unfinished"])
def test_replay_of_a_recording_cut_at_every_4_kib_boundary_plays_or_says_why(
    which: str, real: bytes, unfinished: bytes, tmp_path: Path
) -> None:
    """The replay reader alone, before any repair (a file copied in by hand, a recording cut under it): every
    cut plays (one cut inside a finished file's summary still holds all its data) or is refused in one line
    naming the file, never another exception; the whole file plays if it was finished."""
    data = real if which == "finished" else unfinished
    path = tmp_path / NAME
    for cut in range(0, len(data), CUT_STEP):
        path.write_bytes(data[:cut])
        try:
            load_replay(path)
        except ReplayError as refused:
            assert NAME in str(refused) and "\n" not in str(refused), f"cut at {cut}: {refused}"
    path.write_bytes(data)
    if which == "finished":
        assert load_replay(path).duration_s > 0.0
    else:
        with pytest.raises(ReplayError, match="is not finished"):
            load_replay(path)
