"""The code examples of pulse-api 1.8.4's own README (read from its installed metadata) run against the
simulator over real HTTP, and do what they say.

The simulator runs on a fake clock in this process (served by uvicorn on loopback); the examples' sleeps
(theirs and RobotPulse.await_stop's) advance that clock instead of waiting, so a jog of 19 s or a run at
1 cm/s takes no wall time. Where an example's own text has a bug, the test names it and fixes it minimally:
example 7 fails on a NameError of its own, example 11 shows a deliberate 400; every other one runs as
printed, from the simulator's power-on pose, and the test reads back what it prints.
"""

from __future__ import annotations

import ast
import contextlib
import email.message
import importlib.metadata
import io
import math
import re
import time
from collections.abc import Callable, Iterator
from typing import Any

import pytest

from pendant.api import create_app
from pendant.controller.types import SignalLevel
from pendant.sim import FakeClock, SimController
from tests.support.threads import serve_in_thread

pytestmark = pytest.mark.sdk

README_HOST = 'host = "http://127.0.0.1:8081"'
SETTLE_S = 600.0  # fake seconds to let whatever an example left running finish (1 cm/s runs included)


def readme_examples() -> list[str]:
    metadata = importlib.metadata.metadata("pulse-api")
    assert metadata["Version"] == "1.8.4"
    assert isinstance(metadata, email.message.Message)  # what importlib.metadata gives for a wheel's METADATA
    text = str(metadata.get_payload() or metadata["Description"])
    return re.findall(r"```python\n(.*?)```", text, re.S)


EXAMPLES = readme_examples()


def printed(out: str, headers: list[str]) -> list[Any]:
    """The values an example printed, in order, each header of `headers` checked where it stands: the SDK's
    models print as Python literals (pprint: a value's further lines are indented), read back here."""
    pattern = "|".join(re.escape(h) for h in headers)
    pieces = re.split(rf"^({pattern})\n", out, flags=re.M)
    assert pieces[0] == "" and pieces[1::2] == headers, out
    return [
        ast.literal_eval(value) for piece in pieces[2::2] for value in re.split(r"\n(?=\S)", piece.strip())
    ]


@pytest.fixture(scope="module")
def served() -> Iterator[tuple[SimController, FakeClock, str]]:
    clock = FakeClock()
    sim = SimController(clock=clock)
    with serve_in_thread(create_app(sim)) as url:
        yield sim, clock, url


@pytest.fixture
def run(
    served: tuple[SimController, FakeClock, str], monkeypatch: pytest.MonkeyPatch
) -> Callable[[str], str]:
    sim, clock, url = served
    sim.reset()
    real_sleep = time.sleep

    def fake_sleep(seconds: float) -> None:
        clock.advance(seconds)
        real_sleep(0)

    monkeypatch.setattr(time, "sleep", fake_sleep)

    def run_example(code: str) -> str:
        assert README_HOST in code
        output = io.StringIO()
        with contextlib.redirect_stdout(output):
            exec(compile(code.replace(README_HOST, f'host = "{url}"'), "README", "exec"), {})
        clock.advance(SETTLE_S)
        return output.getvalue()

    return run_example


def test_the_readme_has_its_thirteen_examples() -> None:
    assert len(EXAMPLES) == 13


def test_quickstart_runs_its_loop_body(run: Callable[[str], str], served: Any) -> None:
    sim = served[0]
    # The example loops forever (`while True`) until an exception: one pass is the example.
    out = run(EXAMPLES[0].replace("while True:", "for _ in range(1):"))
    assert "Exception" not in out
    assert sim.get_pose().angles == pytest.approx([10, -90, 0, -90, -90, 0], abs=1e-6)


def test_connecting(run: Callable[[str], str]) -> None:
    assert run(EXAMPLES[1]) == ""


def test_motion_and_jogging(run: Callable[[str], str], served: Any) -> None:
    sim = served[0]
    out = run(EXAMPLES[2])
    pose, position, motors = printed(out, ["Current pose:", "Current position:"])
    assert pose["angles"] == pytest.approx([0, -90, 90, -90, -90, 0], abs=1e-6)  # its pose target
    point, rotation = position["point"], position["rotation"]
    assert [point["x"], point["y"], point["z"]] == pytest.approx([-0.42, -0.12, 0.35], abs=1e-6)
    assert abs(rotation["roll"]) == pytest.approx(math.pi, abs=1e-6)  # its position target: TCP down
    assert len(motors) == 6 and all(m["rotor_velocity"] == 0.0 for m in motors)  # frozen: at rest
    assert sim.get_system_state().value == "ACTIVE"  # the last jog() (all zero) ended jogging


def test_linear_runs_with_blends(run: Callable[[str], str], served: Any) -> None:
    sim = served[0]
    run(EXAMPLES[3])
    assert sim.get_pose().angles == pytest.approx([130, -85, -109, -56, 90, 8], abs=1e-6)


def test_free_drive(run: Callable[[str], str], served: Any) -> None:
    run(EXAMPLES[4])
    assert served[0].get_system_state().value == "ACTIVE"


def test_gripper_and_io(run: Callable[[str], str], served: Any) -> None:
    sim = served[0]
    out = run(EXAMPLES[5])
    assert out == "Input port 1 is inactive\n"
    assert sim.get_output(1) is SignalLevel.HIGH and sim.gripper_opening() == 1.0
    sim.set_input(4, SignalLevel.HIGH)  # bind_stop(4, SIG_HIGH) is in force
    assert sim.get_failures()[-1].type.value == "STOP_2"


def test_actions(run: Callable[[str], str], served: Any) -> None:
    sim = served[0]
    code = EXAMPLES[6]
    with pytest.raises(NameError, match="pose"):  # its bug: `pose` and `math` are not imported
        run(code)
    # Its other bug: the actions are passed where `blend` goes; as the SDK means it, they are `actions=`.
    fixed = "import math\nfrom pulseapi import pose\n" + code
    fixed = re.sub(
        r"\], \[(output_action|close_gripper_action|\n\s+open_gripper_action)", r"], actions=[\1", fixed
    )
    assert fixed.count("actions=[") == 4
    run(fixed)
    assert sim.get_output(1) is SignalLevel.LOW and sim.gripper_opening() == 1.0


def test_tool(run: Callable[[str], str], served: Any) -> None:
    out = run(EXAMPLES[7])
    headers = ["Current tool info", "Current tool shape", "New tool info", "New tool shape"]
    info, shape, new_info, new_shape = printed(out, headers)
    assert (info["name"], info["tcp"]["point"], shape) == ("flange", {"x": 0, "y": 0, "z": 0}, {"shape": []})
    assert (new_info["name"], new_info["tcp"]["point"]) == ("CupHolder", {"x": 0.0, "y": 0.0, "z": 0.07})
    assert new_shape["shape"] == [
        {"begin": {"x": 0.0, "y": 0.0, "z": 0.0}, "finish": {"x": 0.0, "y": 0.0, "z": 0.07}, "radius": 0.03}
    ]
    assert served[0].get_tool_shape().shape[0].radius == 0.03


def test_base(run: Callable[[str], str], served: Any) -> None:
    run(EXAMPLES[8])
    point = served[0].get_base().point
    assert (point.x, point.y, point.z) == (0.05, 0.05, 0.0)


def test_environment_runs_unchanged_with_its_wall_touching_the_arm(
    run: Callable[[str], str], served: Any
) -> None:
    sim = served[0]
    # Unchanged, from the power-on pose: its wall (the plane x = -0.5 m) reaches 13 mm into the wrist. A
    # controller takes it (the arm may back out of it, see docs/environment.md), so the example runs through.
    assert sim.get_pose().angles == [0.0, -90.0, 90.0, -90.0, -90.0, 0.0]
    out = run(EXAMPLES[9])
    headers = ["Current environment", "New environment", "Get example box"]
    headers += ["Environment without box", "Empty environment"]
    before, added, box, without_box, empty = printed(out, headers)
    box_, capsule, plane = (
        {"name": f"example_{kind.lower()}", "obstacle_type": kind} for kind in ("BOX", "CAPSULE", "PLANE")
    )
    assert (before, added, box, without_box, empty) == (
        [],
        [box_, capsule, plane],
        box_,
        [capsule, plane],
        [],
    )
    assert sim.get_obstacles() == []
    assert sim.get_pose().angles == [0.0, -90.0, 90.0, -90.0, -90.0, 0.0]  # nothing moved


def test_error_handling(run: Callable[[str], str]) -> None:
    # It sends a pose to set_position: the controller refuses the body (400) and the handler runs.
    out = run(EXAMPLES[10])
    assert out.startswith("Exception (400)") and "Incorrect format of input Message" in out


def test_recover(run: Callable[[str], str]) -> None:
    assert run(EXAMPLES[11]) == "Recover result: SUCCESS\n"


def test_versions(run: Callable[[str], str]) -> None:
    out = run(EXAMPLES[12])
    assert out.count("motors_version") == 2 and out.endswith("1.8.2\n")
