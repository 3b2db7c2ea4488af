"""`pulse_sim.record()`: a user's test records its run (the pendant's MCAP and CSV), finished at the test's
end whatever its outcome; a user project run by pytest in a subprocess, as a user would."""

from __future__ import annotations

import json
from pathlib import Path

from mcap.reader import make_reader

from tests.support.user_project import run_project

TESTS = """
import time

import httpx

POSE = {"angles": [10.0, -90.0, 90.0, -90.0, -90.0, 0.0]}


def test_move(pulse_sim):
    path = pulse_sim.record("pick", "recs")
    assert path.name == "pendant-pick.mcap"
    assert httpx.put(pulse_sim.url + "/pose?speed=50", json=POSE).status_code == 200
    time.sleep(1.0)  # ten simulated seconds: the move is over


def test_fails_while_recording(pulse_sim):
    pulse_sim.record("failing", "recs")
    time.sleep(0.5)
    assert False, "a failing test"


def test_a_taken_name(pulse_sim):
    pulse_sim.record("pick", "recs")
"""


def joints(mcap: Path) -> list[list[float]]:
    with mcap.open("rb") as stream:
        return [
            json.loads(message.data)["position_deg"]
            for _, channel, message in make_reader(stream).iter_messages()
            if channel.topic == "/joints"
        ]


def test_a_test_records_its_run_and_the_file_is_finished_whatever_its_outcome(tmp_path: Path) -> None:
    run = run_project(tmp_path, {"pytest.ini": "[pytest]\n", "test_robot.py": TESTS})
    output = run.stdout + run.stderr
    assert "1 passed" in output and "2 failed" in output, output
    assert "already exists" in output, "a name taken by an earlier recording is refused"
    moved = joints(tmp_path / "recs" / "pendant-pick.mcap")
    assert len(moved) >= 5 and abs(moved[-1][0] - 10.0) < 0.5, moved[-1:]
    assert (tmp_path / "recs" / "pendant-pick.csv").exists()
    assert joints(tmp_path / "recs" / "pendant-failing.mcap"), "finished at the failing test's end"
