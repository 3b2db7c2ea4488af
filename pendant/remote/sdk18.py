"""The operations Rozum's SDK 1.8.4 adds to the reference guide's, as RemoteController speaks them."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any, TypeVar
from urllib.parse import quote

from pydantic import TypeAdapter

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
from pendant.remote.wire import decode_text

T = TypeVar("T")

_FAILURES = TypeAdapter(list[Failure])
_OBSTACLE: TypeAdapter[Obstacle] = TypeAdapter(Obstacle)
_OBSTACLES = TypeAdapter(list[Obstacle])
_COUNT = TypeAdapter(int)


def dump(model: Any) -> Any:
    """A request body as the SDK sends it: wire names, optional fields left out when unset."""
    return model.model_dump(mode="json", by_alias=True, exclude_none=True)


class Pulse18Client(OperationCalls):
    """SDK 1.8.4's operations over RemoteController's transport (one request each, never re-sent)."""

    def _get_model(self, path: str, model: type[Any]) -> Any:
        raise NotImplementedError  # RemoteController's

    def _get_text(self, path: str, convert: Callable[[str], T]) -> T:
        raise NotImplementedError  # RemoteController's

    def clock_time(self) -> float:
        """This machine's clock: the controller stamps its own readings (the proxy passes them through)."""
        return time.time()

    def get_system_state(self) -> SystemState:
        response = self._request("GET", "/status")
        return self._parse(response, "GET /status", lambda body: SystemState(decode_text(body)))

    def get_failures(self) -> list[Failure]:
        return self._parse(
            self._request("GET", "/status/failure"), "GET /status/failure", _FAILURES.validate_json
        )

    def get_robot_info(self) -> RobotInfo:
        return self._get_model("/robot/info", RobotInfo)

    def get_hardware_version(self) -> Version:
        return self._get_model("/version/hardware", Version)

    def get_software_version(self) -> Version:
        return self._get_model("/version/software", Version)

    def get_robot_software_version(self) -> str:
        return self._get_text("/version/software/robot", str)

    def read_motors_log(self) -> int:
        return self._parse(self._request("POST", "/motors-log"), "POST /motors-log", _COUNT.validate_json)

    def get_tool_info(self) -> ToolInfo:
        return self._get_model("/tool/info", ToolInfo)

    def set_tool_info(self, info: ToolInfo) -> ToolInfo:
        response = self._request("POST", "/tool/info", json=dump(info))
        return self._parse(response, "POST /tool/info", ToolInfo.model_validate_json)

    def get_tool_shape(self) -> ToolShape:
        return self._get_model("/tool/shape", ToolShape)

    def set_tool_shape(self, shape: ToolShape) -> ToolShape:
        response = self._request("POST", "/tool/shape", json=dump(shape))
        return self._parse(response, "POST /tool/shape", ToolShape.model_validate_json)

    def add_obstacle(self, obstacle: Obstacle) -> str:
        return self._command("PUT", "/environment", json=dump(obstacle))

    def get_obstacles(self) -> list[Obstacle]:
        return self._parse(self._request("GET", "/environment"), "GET /environment", _OBSTACLES.validate_json)

    def get_obstacle(self, name: str) -> Obstacle:
        path = f"/environment/{quote(name, safe='')}"
        return self._parse(self._request("GET", path), f"GET {path}", _OBSTACLE.validate_json)

    def remove_obstacles(self) -> str:
        return self._command("DELETE", "/environment")

    def remove_obstacle(self, name: str) -> str:
        return self._command("DELETE", f"/environment/{quote(name, safe='')}")

    def enable_gripper(self) -> str:
        return self._command("POST", "/gripper/enable")

    def disable_gripper(self) -> str:
        return self._command("POST", "/gripper/disable")

    def zg_on(self) -> str:
        return self._command("PUT", "/zg/on")

    def zg_off(self) -> str:
        return self._command("PUT", "/zg/off")

    def stop(self) -> str:
        return self._command("POST", "/stop")

    def bind_stop(self, port: int, level: SignalLevel) -> str:
        return self._command("PUT", f"/stop/bind/{port}/{SignalLevel(level).value.lower()}")

    def unbind_stop(self) -> str:
        return self._command("DELETE", "/stop")

    def finish_untwisting(self) -> str:
        return self._command("PUT", "/untwisting/finish")

    def jog(self, vector: JoggingVector) -> str:
        return self._command("PUT", "/jogging", json=dump(JoggingAcceleration(acceleration=vector)))

    def run_linear_positions(self, positions: list[PositionWaypoint], params: LinearMotionParameters) -> str:
        body = LinearPositions(positions=positions, motionParameters=params)
        return str(self.call("PUT /run/linear/positions", json=dump(body)))

    def run_linear_poses(self, poses: list[PoseWaypoint], params: LinearMotionParameters) -> str:
        body = LinearPoses(poses=poses, motionParameters=params)
        return str(self.call("PUT /run/linear/poses", json=dump(body)))

    def run_joint_positions(self, positions: list[PositionWaypoint], params: JointMotionParameters) -> str:
        body = JointPositions(positions=positions, motionParameters=params)
        return str(self.call("PUT /run/joint/positions", json=dump(body)))

    def run_joint_poses(self, poses: list[PoseWaypoint], params: JointMotionParameters) -> str:
        body = JointPoses(poses=poses, motionParameters=params)
        return str(self.call("PUT /run/joint/poses", json=dump(body)))

    def _command(self, method: str, path: str, *, json: Any = None) -> str:
        """A command answering the controller's message (text)."""
        response = self._request(method, path, json=json)
        return self._parse(response, f"{method} {path}", decode_text)
