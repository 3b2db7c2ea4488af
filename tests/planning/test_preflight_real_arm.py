"""Pre-flight against a "real" arm: `pendant --no-ui` processes, one as the arm and one as the pendant in
front of it (`--robot`), with a forwarder between them counting what the arm is sent."""

from __future__ import annotations

import collections
import json
import subprocess
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest

from pendant.cell.file import Cell, dump_cell
from pendant.controller.types import MotionParams, MotionStatus, Pose
from pendant.eventlog import EventKind, EventLog
from pendant.planning.gate import RunGate, current_fingerprint
from pendant.planning.preflight import preflight
from pendant.planning.twin import read_seed
from pendant.program.runner import ProgramRunner, RunState
from pendant.remote import RemoteController
from tests.support import preloaded
from tests.support.counting_forwarder import counting_forwarder
from tests.support.launchers import REPO_ROOT, child_env, pendant_command, running_pendant
from tests.support.preflight_scene import BOX_NAME, LEFT_DEG, box_in_the_way, swing_program
from tests.support.waiting import SAFETY_NET_S, wait_until

CYCLE_TIME_TOLERANCE = 0.03  # the bound: within 3 % of the run's
CLI_TIMEOUT_S = 60.0
# The arm's clock: real time, on the simulator's scaled clock (any scale but 1), which stands still while the
# simulator plans a move, as the twin's does: the run's cycle time is then the arm's motion and the runner's
# polling, not how long this loaded machine takes to plan.
ARM_TIME_SCALE = "1.0001"


class Rig:
    def __init__(self, arm_url: str, pendant_url: str, counts: collections.Counter[str]) -> None:
        self.arm_url = arm_url
        self.pendant_url = pendant_url
        self.counts = counts
        self.arm = RemoteController(arm_url)  # straight to the arm: the test's own setup, not counted

    def put_arm_left(self, *, box: bool) -> None:
        arm = self.arm
        arm.remove_obstacles()
        arm.set_pose(Pose(angles=list(LEFT_DEG)), MotionParams(speed=100.0))
        wait_until(lambda: arm.get_motion_status() is MotionStatus.IDLE, timeout_s=SAFETY_NET_S)
        if box:
            arm.add_obstacle(box_in_the_way())

    def state(self) -> tuple[list[float], list[dict[str, object]], dict[int, str]]:
        arm = self.arm
        outputs = {port: arm.get_output(port).value for port in (1, 2)}
        return list(arm.get_pose().angles), [o.model_dump() for o in arm.get_obstacles()], outputs

    def post(self, body: object) -> httpx.Response:
        return httpx.post(f"{self.pendant_url}/pendant/preflight", json=body, timeout=30)


@pytest.fixture(scope="module")
def rig() -> Iterator[Rig]:
    with (
        running_pendant("--time-scale", ARM_TIME_SCALE) as arm_url,
        counting_forwarder(arm_url) as (forwarder, counts),
        running_pendant("--robot", forwarder) as pendant_url,
    ):
        yield Rig(arm_url, pendant_url, counts)


def arm_clock(rig: Rig) -> float:
    return float(httpx.get(f"{rig.arm_url}/sim/clock", timeout=10).json()["time"])


def program_json() -> dict[str, object]:
    return swing_program().model_dump(mode="json")


def test_a_move_through_a_box_fails_there_naming_the_box_and_the_arm_is_sent_only_reads(rig: Rig) -> None:
    rig.put_arm_left(box=True)
    before = rig.state()
    rig.counts.clear()

    answer = rig.post(program_json())

    assert answer.status_code == 200, answer.text
    report = answer.json()
    assert report["ok"] is False
    failure = report["first_failure"]
    assert failure["line"] == 3 and failure["obstacle"] == BOX_NAME
    assert f"'{BOX_NAME}'" in failure["reason"] and "% of the move" in failure["reason"]
    assert report["summary"].startswith("Step 3 (Move J to right")
    assert report["steps"][2]["min_clearance_mm"] <= 0  # where it would touch
    marks = [(s["ok"], s["checked"]) for s in report["steps"]]
    assert marks == [(True, True), (True, True), (False, True), (False, False), (False, False)]
    # The arm was only read: no command reached it, and it is where it was with the cell it had.
    assert rig.counts["GET"] > 0 and set(rig.counts) == {"GET"}, rig.counts
    assert rig.state() == before
    assert rig.arm.get_motion_status() is MotionStatus.IDLE


# A real-time figure (the real run's cycle time on the wall clock): run in front at normal priority, never
# behind at nice 19, where a clean-clone run's arm took 11.29 s for a 10.44 s cycle.
@pytest.mark.measures
def test_without_the_box_it_passes_with_the_cycle_time_of_a_real_run(rig: Rig) -> None:
    rig.put_arm_left(box=False)
    rig.counts.clear()
    report = rig.post(program_json()).json()
    assert report["ok"] is True, report["summary"]
    assert set(rig.counts) == {"GET"}
    assert all(s["ok"] and s["checked"] for s in report["steps"])

    runner = ProgramRunner(RemoteController(rig.arm_url))
    started = arm_clock(rig)
    result = runner.run(swing_program())
    real_cycle = arm_clock(rig) - started

    assert result.state is RunState.FINISHED, result.message
    error = abs(report["cycle_time_s"] - real_cycle) / real_cycle
    assert error <= CYCLE_TIME_TOLERANCE, (report["cycle_time_s"], real_cycle)


def test_the_gate_refuses_run_until_a_preflight_passes_and_logs_an_override(rig: Rig) -> None:
    rig.put_arm_left(box=True)
    controller = RemoteController(rig.pendant_url)
    events = EventLog()
    gate = RunGate(required=True, events=events)
    program = swing_program()
    print_ = current_fingerprint(program, controller)
    assert not gate.decide(print_).allowed  # never checked

    gate.record_check(print_, preflight(program, read_seed(controller)))
    refused = gate.decide(print_)
    assert not refused.allowed and BOX_NAME in refused.reason  # checked, and it fails

    rig.arm.remove_obstacles()  # the cell changed: that check no longer speaks for this program
    print_ = current_fingerprint(program, controller)
    assert gate.last_check(print_) is None and not gate.decide(print_).allowed
    gate.record_check(print_, preflight(program, read_seed(controller)))
    assert gate.decide(print_).allowed

    edited = program.model_copy(update={"steps": program.steps[:-1]})
    edited_print = current_fingerprint(edited, controller)
    assert not gate.decide(edited_print).allowed  # any edit needs a new check

    gate.override(edited_print, "browser #2 (10.0.0.7)", edited.name)
    assert gate.decide(edited_print).allowed
    logged = [e for e in events.recent() if e.kind is EventKind.COMMAND]
    assert logged and logged[-1].source == "browser #2 (10.0.0.7)"
    assert "without a passing pre-flight" in logged[-1].message


def test_the_simulators_gate_is_open() -> None:
    assert RunGate(required=False).decide("anything").allowed


def run_cli(*args: str) -> subprocess.CompletedProcess[str]:
    return preloaded.run(
        pendant_command("preflight", *args),
        cwd=REPO_ROOT,
        env=child_env(),
        capture_output=True,
        text=True,
        timeout=CLI_TIMEOUT_S,
    )


def test_cli_exit_codes(rig: Rig, tmp_path: Path) -> None:
    rig.put_arm_left(box=False)
    program = tmp_path / "swing.json"
    program.write_text(json.dumps(program_json()))
    cell = tmp_path / "boxed.cell.json"
    cell.write_bytes(dump_cell(Cell(obstacles=[box_in_the_way()])))
    before = rig.state()

    passing = run_cli(str(program), "--robot", rig.pendant_url)
    assert passing.returncode == 0, passing.stderr
    assert "All 5 steps pass" in passing.stdout

    failing = run_cli(str(program), "--robot", rig.pendant_url, "--cell", str(cell), "--json")
    assert failing.returncode == 1, failing.stderr
    report = json.loads(failing.stdout)
    assert report["first_failure"]["line"] == 3 and report["first_failure"]["obstacle"] == BOX_NAME
    assert rig.state() == before  # the cell file was checked against, not put on the arm

    calls_nobody = tmp_path / "calls.json"
    calls_nobody.write_text(json.dumps({"schema_version": 2, "steps": [{"kind": "call", "program": "gone"}]}))
    not_a_cell = tmp_path / "not.cell.json"
    not_a_cell.write_text('{"obstacles": "a wall"}')
    refused = {
        "not a program": run_cli(str(cell)),
        "no such file": run_cli(str(tmp_path / "missing.json")),
        "a missing call": run_cli(str(calls_nobody)),
        "not a cell": run_cli(str(program), "--cell", str(not_a_cell)),
        "a bad input flag": run_cli(str(program), "--input", "7=HIGH"),
    }
    for what, result in refused.items():
        assert result.returncode == 2, (what, result.stdout, result.stderr)
        assert result.stderr.strip(), what
    assert "gone" in refused["a missing call"].stderr
    assert "not a cell file" in refused["not a cell"].stderr
    assert rig.state() == before


def test_the_route_refuses_what_is_not_a_program_with_the_reason(rig: Rig) -> None:
    garbage = httpx.post(f"{rig.pendant_url}/pendant/preflight", content=b"{not json", timeout=SAFETY_NET_S)
    assert garbage.status_code == 400 and "not JSON" in garbage.json()
    missing = rig.post({"program": {"schema_version": 2, "steps": [{"kind": "call", "program": "gone"}]}})
    assert missing.status_code == 400 and "gone" in missing.json()
    bad_input = rig.post({"program": program_json(), "inputs": {"9": "HIGH"}})
    assert bad_input.status_code == 400
    # The simulator's own API answers the same route (sim mode).
    assert httpx.post(f"{rig.arm_url}/pendant/preflight", json=program_json(), timeout=30).status_code == 200
