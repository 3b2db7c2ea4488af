"""Rozum's current SDK (pulse-api + pdhttp 1.8.4, aiopdhttp 1.8.4) drives `pendant --no-ui` over real HTTP:
every RobotPulse method and the raw operations it does not wrap, on the simulator and through the proxy
(`pendant --robot URL --no-ui` in front of it)."""

from __future__ import annotations

import asyncio
import math
from collections.abc import Iterator

import httpx
import pytest
from pdhttp import DefaultApi, JointMotionParameters, JointPoses, JointPositions, RobotApi
from pulseapi import (
    MT_LINEAR,
    SIG_HIGH,
    SIG_LOW,
    InterpolationType,
    LinearMotionParameters,
    Point,
    PulseApiException,
    RobotPulse,
    SystemState,
    Versions,
    close_gripper_action,
    create_box_obstacle,
    create_capsule_obstacle,
    create_plane_obstacle,
    create_simple_capsule_obstacle,
    jog,
    output_action,
    pose,
    position,
    tool_info,
    tool_shape,
)

from tests.support.launchers import running_pendant

pytestmark = pytest.mark.sdk

HOME = [0.0, -90.0, 90.0, -90.0, -90.0, 0.0]  # the power-on pose
POS_TOL_M = 1e-4
DOWN = [math.pi, 0.0, 0.0]


@pytest.fixture(scope="module", params=["simulator", "proxy"])
def urls(request: pytest.FixtureRequest) -> Iterator[tuple[str, str]]:
    """(the URL the SDK talks to, the simulator's own URL for /sim controls)."""
    with running_pendant() as sim_url:
        if request.param == "simulator":
            yield sim_url, sim_url
        else:
            with running_pendant("--robot", sim_url) as proxy_url:
                yield proxy_url, sim_url


@pytest.fixture
def robot(urls: tuple[str, str]) -> Iterator[RobotPulse]:
    url, sim_url = urls
    assert httpx.put(f"{sim_url}/sim/reset").status_code == 200
    yield RobotPulse(url)
    httpx.put(f"{sim_url}/sim/reset")


@pytest.fixture
def sim_url(urls: tuple[str, str]) -> str:
    return urls[1]


def xyz(robot: RobotPulse) -> list[float]:
    point = robot.get_position().point
    return [point.x, point.y, point.z]


def raw_api(robot: RobotPulse) -> RobotApi:
    """The generated client RobotPulse wraps, on the same controller: its operations RobotPulse leaves out."""
    api = RobotApi()
    api.api_client.configuration.host = robot.host
    return api


def test_the_quickstart_moves_with_tcp_max_velocity_alone_and_await_stop_waits(robot: RobotPulse) -> None:
    start = xyz(robot)
    target = position([start[0], start[1] + 0.05, start[2]], DOWN)
    # No speed; 2.5 s for the 5 cm, so the MOTION read after it holds behind the timed pass (nice 19).
    robot.run_positions([target], tcp_max_velocity=0.02, motion_type=MT_LINEAR)
    assert robot.status() == SystemState.MOTION
    robot.await_stop()
    assert robot.status() == SystemState.ACTIVE
    assert xyz(robot) == pytest.approx([start[0], start[1] + 0.05, start[2]], abs=POS_TOL_M)
    robot.set_pose(pose(HOME), velocity=80, acceleration=200)  # acceleration up to 200 %
    robot.await_stop()
    assert robot.get_pose().angles == pytest.approx(HOME, abs=1e-6)


def test_reads_carry_a_timestamp(robot: RobotPulse) -> None:
    for reading in (robot.get_pose(), robot.get_position()):
        assert reading.timestamp and reading.timestamp[:2] == "20"


def test_emergency_answers_status_and_failures_and_nothing_else(robot: RobotPulse, sim_url: str) -> None:
    httpx.put(f"{sim_url}/sim/fault/emergency")
    with pytest.raises(PulseApiException) as refused:
        robot.get_pose()
    assert refused.value.status == 503
    assert robot.status() == SystemState.EMERGENCY
    failure = robot.status_failure()[-1]
    assert (failure.type, failure.level) == ("EMCY", "FATAL")
    assert failure._date  # the SDK's own (public) name for the "date" field


def test_identity_versions_and_the_motors_log(robot: RobotPulse, urls: tuple[str, str]) -> None:
    info = robot.information()
    assert (info.model, info.version) == ("PULSE75", "2.1")
    assert info.arm_serial_number == robot.information().arm_serial_number != "Unknown"
    versions = Versions(urls[0])
    assert len(versions.hardware().motors_version) == 6
    assert len(versions.software().motors_version) == 6
    assert versions.robot_software() == "1.8.2"
    assert DefaultApi(raw_api(robot).api_client).read_motors_log() == 6


def test_tool_info_and_shape_are_one_tool(robot: RobotPulse, urls: tuple[str, str]) -> None:
    robot.change_tool_info(tool_info(position([0, 0, 0.07], [0, 0, 0]), name="CupHolder"))
    shape = tool_shape([create_simple_capsule_obstacle(0.03, Point(0, 0, 0), Point(0, 0, 0.07))])
    robot.change_tool_shape(shape)
    info = robot.get_tool_info()
    assert (info.name, info.tcp.point.z) == ("CupHolder", 0.07)
    assert robot.get_tool_shape().shape[0].radius == 0.03
    tool = httpx.get(f"{urls[0]}/tool").json()  # the reference's view of the same tool
    assert (tool["name"], tool["point"]["z"]) == ("CupHolder", 0.07)


def test_a_move_through_an_obstacle_is_refused_and_nothing_moves(robot: RobotPulse) -> None:
    start = xyz(robot)
    box = create_box_obstacle(
        Point(0.04, 0.04, 0.04), position([start[0], start[1] + 0.1, start[2]], [0, 0, 0]), "box"
    )
    robot.add_to_environment(box)
    robot.add_to_environment(
        create_capsule_obstacle(0.05, Point(0.5, 0.5, 0.2), Point(0.5, 0.5, 0.5), "pole")
    )
    robot.add_to_environment(
        create_plane_obstacle([Point(-0.9, 0.4, 0), Point(-0.9, 0, 0), Point(-0.9, 0, 0.1)], "wall")
    )
    assert [o.name for o in robot.get_all_from_environment()] == ["box", "pole", "wall"]
    assert robot.get_from_environment_by_name("pole").obstacle_type == "CAPSULE"
    params = LinearMotionParameters(
        interpolation_type=InterpolationType.BLEND, velocity=0.3, acceleration=1.0
    )
    through = [position([start[0], start[1] + 0.2, start[2]], DOWN)]
    before = robot.get_pose().angles
    with pytest.raises(PulseApiException) as refused:
        robot.run_linear_positions(through, params)
    touch_box = "\"Collision detected: the arm would touch 'box'\""  # the controller's words, naming it
    assert (refused.value.status, refused.value.body) == (412, touch_box)
    assert robot.get_pose().angles == before and robot.status() == SystemState.ACTIVE
    robot.remove_from_environment_by_name("box")
    robot.run_linear_positions(through, params)
    robot.await_stop()
    assert xyz(robot) == pytest.approx([start[0], start[1] + 0.2, start[2]], abs=POS_TOL_M)
    robot.remove_all_from_environment()
    assert robot.get_all_from_environment() == []


def test_stop_refuses_motion_until_recover(robot: RobotPulse) -> None:
    robot.stop()
    with pytest.raises(PulseApiException) as refused:
        robot.set_pose(pose(HOME), speed=50)
    assert refused.value.status == 412 and "Protective stop" in refused.value.body
    assert robot.status_failure()[-1].type == "STOP_2"
    assert robot.recover() == "SUCCESS"
    robot.set_pose(pose([10.0, *HOME[1:]]), speed=80)
    robot.await_stop()
    assert robot.get_pose().angles[0] == pytest.approx(10.0)


def test_a_bound_input_stops_the_arm_and_unbind_lets_it_be(robot: RobotPulse, sim_url: str) -> None:
    robot.bind_stop(4, SIG_HIGH)
    robot.set_pose(pose([60.0, *HOME[1:]]), speed=5)
    httpx.put(f"{sim_url}/sim/signal/input/4/high")
    stopped = robot.get_pose().angles[0]
    assert 0.0 < stopped < 60.0 and robot.status() == SystemState.ACTIVE
    assert "digital input 4 went HIGH" in robot.status_failure()[-1].message
    robot.recover()
    robot.unbind_stop()
    httpx.put(f"{sim_url}/sim/signal/input/4/low")
    httpx.put(f"{sim_url}/sim/signal/input/4/high")
    # A long, slow move: behind the timed pass (nice 19) a short one home at 100 % had ended before the
    # status was read (CI, 27 Nov).
    robot.set_pose(pose([-60.0, *HOME[1:]]), speed=5)
    assert robot.status() == SystemState.MOTION


def test_free_drive_on_and_off(robot: RobotPulse, sim_url: str) -> None:
    robot.zg_on()
    assert robot.status() == SystemState.ZERO_GRAVITY
    moved = [20.0, *HOME[1:]]
    assert httpx.put(f"{sim_url}/sim/pose", json={"angles": moved}).status_code == 200  # a hand moves it
    robot.zg_off()
    assert robot.status() == SystemState.ACTIVE and robot.get_pose().angles == pytest.approx(moved)


def test_gripper_power_and_fractional_timeouts(robot: RobotPulse) -> None:
    robot.disable_gripper()
    with pytest.raises(PulseApiException) as refused:
        robot.close_gripper(timeout=250.5)
    assert refused.value.status == 412 and "disabled" in refused.value.body
    robot.enable_gripper()
    robot.close_gripper(timeout=250.5)
    robot.open_gripper()
    robot.await_stop()
    assert robot.status() == SystemState.ACTIVE


def test_jogging_moves_the_tcp_until_a_zero_vector(robot: RobotPulse) -> None:
    start = xyz(robot)
    robot.jogging(jog(y=1))
    assert robot.status() == SystemState.JOGGING
    robot.jogging(jog())
    assert robot.status() == SystemState.ACTIVE
    stopped = xyz(robot)
    assert stopped[1] > start[1] and stopped[0] == pytest.approx(start[0], abs=1e-6)
    assert xyz(robot) == stopped


def test_actions_set_outputs_at_their_waypoints(robot: RobotPulse) -> None:
    start = xyz(robot)
    targets = [
        position([start[0], start[1] + 0.03, start[2]], DOWN, actions=[output_action(1, SIG_HIGH)]),
        position([start[0], start[1] + 0.06, start[2]], DOWN, actions=[close_gripper_action()]),
    ]
    robot.run_positions(targets, speed=100, motion_type=MT_LINEAR)
    assert robot.get_digital_output(1) == SIG_LOW  # not there yet
    robot.await_stop()
    assert robot.get_digital_output(1) == SIG_HIGH


def test_joint_runs_the_sdk_does_not_wrap(robot: RobotPulse) -> None:
    params = JointMotionParameters(interpolation_type="SPLINE", velocity=100, acceleration=100)
    raw_api(robot).run_joint_poses(JointPoses([pose([10.0, *HOME[1:]]), pose([20.0, *HOME[1:]])], params))
    robot.await_stop()
    assert robot.get_pose().angles[0] == pytest.approx(20.0)
    start = xyz(robot)
    target = position([start[0], start[1], start[2] + 0.05], DOWN)
    raw_api(robot).run_joint_positions(JointPositions([target], params))
    robot.await_stop()
    assert xyz(robot)[2] == pytest.approx(start[2] + 0.05, abs=POS_TOL_M)


def test_untwisting_leaves_twisted(robot: RobotPulse, sim_url: str) -> None:
    httpx.put(f"{sim_url}/sim/fault/twisted")
    assert robot.status() == SystemState.TWISTED
    with pytest.raises(PulseApiException):
        robot.set_pose(pose(HOME), speed=50)
    assert raw_api(robot).stop_untwisting().startswith("Untwisting finished")
    assert robot.status() == SystemState.ACTIVE


def test_the_async_client_reads_and_moves(robot: RobotPulse, urls: tuple[str, str]) -> None:
    import aiopdhttp

    async def drive() -> tuple[str, list[float], str]:
        configuration = aiopdhttp.Configuration()
        configuration.host = urls[0]
        api = aiopdhttp.RobotApi(aiopdhttp.ApiClient(configuration))
        try:
            before = await api.status()
            await api.set_pose(aiopdhttp.Pose([15.0, *HOME[1:]]), speed=100)
            while await api.status() == "MOTION":
                await asyncio.sleep(0.05)
            return before, (await api.get_pose()).angles, await api.status()
        finally:
            await api.api_client.rest_client.pool_manager.close()

    before, angles, after = asyncio.run(drive())
    assert (before, after) == ("ACTIVE", "ACTIVE")
    assert angles[0] == pytest.approx(15.0)
