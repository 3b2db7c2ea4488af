"""The operations Rozum's SDK 1.8.4 adds to the reference guide's, as RemoteController speaks them: each a
thin wrapper naming its operations-table row (`call`: pendant.remote.calls)."""

from __future__ import annotations

import time
from typing import Any

from pendant.controller.cell_types import Obstacle, ToolInfo, ToolShape
from pendant.controller.system_types import (
    Failure,
    JoggingAcceleration,
    JoggingVector,
    JointMotionParameters,
    JointPoses,
    JointPositions,
    LinearMotionParameters,
    LinearPoses,
    LinearPositions,
    PoseWaypoint,
    PositionWaypoint,
    RobotInfo,
    SystemState,
    Version,
)
from pendant.controller.types import SignalLevel
from pendant.remote.calls import OperationCalls


def dump(model: Any) -> Any:
    """A request body as the SDK sends it: wire names, optional fields left out when unset."""
    return model.model_dump(mode="json", by_alias=True, exclude_none=True)


class Pulse18Client(OperationCalls):
    """SDK 1.8.4's operations over RemoteController's transport (one request each, never re-sent)."""

    def clock_time(self) -> float:
        """This machine's clock: the controller stamps its own readings (the proxy passes them through)."""
        return time.time()

    def get_system_state(self) -> SystemState:
        return self.call("GET /status")

    def get_failures(self) -> list[Failure]:
        return self.call("GET /status/failure")

    def get_robot_info(self) -> RobotInfo:
        return self.call("GET /robot/info")

    def get_hardware_version(self) -> Version:
        return self.call("GET /version/hardware")

    def get_software_version(self) -> Version:
        return self.call("GET /version/software")

    def get_robot_software_version(self) -> str:
        return self.call("GET /version/software/robot")

    def read_motors_log(self) -> int:
        return self.call("POST /motors-log")

    def get_tool_info(self) -> ToolInfo:
        return self.call("GET /tool/info")

    def set_tool_info(self, info: ToolInfo) -> ToolInfo:
        return self.call("POST /tool/info", json=dump(info))

    def get_tool_shape(self) -> ToolShape:
        return self.call("GET /tool/shape")

    def set_tool_shape(self, shape: ToolShape) -> ToolShape:
        return self.call("POST /tool/shape", json=dump(shape))

    def add_obstacle(self, obstacle: Obstacle) -> str:
        return self.call("PUT /environment", json=dump(obstacle))

    def get_obstacles(self) -> list[Obstacle]:
        return self.call("GET /environment")

    def get_obstacle(self, name: str) -> Obstacle:
        return self.call("GET /environment/{obstacle}", path={"obstacle": name})

    def remove_obstacles(self) -> str:
        return self.call("DELETE /environment")

    def remove_obstacle(self, name: str) -> str:
        return self.call("DELETE /environment/{obstacle}", path={"obstacle": name})

    def enable_gripper(self) -> str:
        return self.call("POST /gripper/enable")

    def disable_gripper(self) -> str:
        return self.call("POST /gripper/disable")

    def zg_on(self) -> str:
        return self.call("PUT /zg/on")

    def zg_off(self) -> str:
        return self.call("PUT /zg/off")

    def stop(self) -> str:
        return self.call("POST /stop")

    def bind_stop(self, port: int, level: SignalLevel) -> str:
        return self.call(f"PUT /stop/bind/{{port}}/{SignalLevel(level).value.lower()}", path={"port": port})

    def unbind_stop(self) -> str:
        return self.call("DELETE /stop")

    def finish_untwisting(self) -> str:
        return self.call("PUT /untwisting/finish")

    def jog(self, vector: JoggingVector) -> str:
        return self.call("PUT /jogging", json=dump(JoggingAcceleration(acceleration=vector)))

    def run_linear_positions(self, positions: list[PositionWaypoint], params: LinearMotionParameters) -> str:
        body = LinearPositions(positions=positions, motionParameters=params)
        return self.call("PUT /run/linear/positions", json=dump(body))

    def run_linear_poses(self, poses: list[PoseWaypoint], params: LinearMotionParameters) -> str:
        body = LinearPoses(poses=poses, motionParameters=params)
        return self.call("PUT /run/linear/poses", json=dump(body))

    def run_joint_positions(self, positions: list[PositionWaypoint], params: JointMotionParameters) -> str:
        body = JointPositions(positions=positions, motionParameters=params)
        return self.call("PUT /run/joint/positions", json=dump(body))

    def run_joint_poses(self, poses: list[PoseWaypoint], params: JointMotionParameters) -> str:
        body = JointPoses(poses=poses, motionParameters=params)
        return self.call("PUT /run/joint/poses", json=dump(body))
