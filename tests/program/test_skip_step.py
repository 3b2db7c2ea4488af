"""Skip step: a failed run goes on at the step after the one that failed (that step is not done), which the
banner offers beside Retry."""

from __future__ import annotations

import numpy as np

from pendant.controller.cell_types import BoxObstacle
from pendant.controller.types import Point, Position, Rotation
from pendant.program import MoveStep, Program, ProgramRunner, RunState, Waypoint
from pendant.sim import SimController
from tests.support.programs import move, program_of

ANGLE_TOL_DEG = 1e-6
BOX_SIDE_M = 0.08


def box_at(name: str, xyz: np.ndarray) -> BoxObstacle:
    return BoxObstacle(
        obstacleType="BOX",
        name=name,
        sides=Point(x=BOX_SIDE_M, y=BOX_SIDE_M, z=BOX_SIDE_M),
        centerPosition=Position(
            point=Point(x=float(xyz[0]), y=float(xyz[1]), z=float(xyz[2])),
            rotation=Rotation(roll=0, pitch=0, yaw=0),
        ),
    )


def test_skip_goes_on_after_the_failed_step(
    sim: SimController, runner: ProgramRunner, waypoints: dict[str, Waypoint]
) -> None:
    a, b, c = waypoints["A"], waypoints["B"], waypoints["C"]
    # Different speeds: three separate requests, so only the move to B is refused.
    program = program_of(move(a, speed=50.0), move(b, speed=40.0), move(c, speed=30.0))
    sim.add_obstacle(box_at("Box", sim.arm.fk(np.radians(b.pose.angles))[:3, 3]))
    failed = runner.run(program)
    assert failed.state is RunState.FAILED and failed.failed_step == 1, failed.message
    assert "Collision detected" in failed.message
    assert np.allclose(sim.get_pose().angles, a.pose.angles, atol=ANGLE_TOL_DEG)  # stopped at A

    done = runner.skip()
    assert done.state is RunState.FINISHED, done.message
    assert np.allclose(sim.get_pose().angles, c.pose.angles, atol=ANGLE_TOL_DEG)  # B skipped, C reached


def test_skip_without_a_failed_run_does_nothing(runner: ProgramRunner) -> None:
    assert runner.skip().state is RunState.IDLE


def test_the_runner_names_the_failure_with_its_hook(
    sim: SimController, runner: ProgramRunner, waypoints: dict[str, Waypoint]
) -> None:
    a, b = waypoints["A"], waypoints["B"]
    sim.add_obstacle(box_at("Box", sim.arm.fk(np.radians(b.pose.angles))[:3, 3]))

    def explain(program: Program, line: int, last: int, reason: str) -> str:
        step = program.steps[line]
        assert isinstance(step, MoveStep)
        return f"{reason} ({step.waypoint})"

    runner.explain_failure = explain
    failed = runner.run(program_of(move(a, speed=50.0), move(b, speed=40.0)))
    # The hook's words end the message: the controller's reason (which names the box), then the hook's "(B)".
    assert failed.message.endswith("'Box' (B)") and "Collision detected" in failed.message, failed.message
