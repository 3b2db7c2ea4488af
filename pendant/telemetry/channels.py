"""The channels a recording and the live Foxglove view share, on one Foxglove context: the arm in 3D (/tf:
foxglove.FrameTransforms of every link; /arm: foxglove.SceneUpdate of the links' meshes, locked to their
frames), the cell (/cell), the TCP's course (/tcp_path), the event log (/events: foxglove.Log), and JSON
series for plots: /joints, /tcp, /motors, /io, /program (the step running), each message built from its model
in messages.py, whose JSON schema the channel carries. Whatever sinks the context has (an MCAP file, a
WebSocket server) get the same messages. Log times are wall-clock ns."""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import foxglove
import numpy as np
from foxglove.channels import FrameTransformsChannel, LogChannel, SceneUpdateChannel
from pydantic import BaseModel

from pendant.controller.cell_types import Obstacle
from pendant.controller.types import INPUT_PORTS, OUTPUT_PORTS, MotorStatus, Position, SignalLevel
from pendant.eventlog import Event
from pendant.telemetry import foxglove_scene
from pendant.telemetry.arm_scene import ArmDrawing
from pendant.telemetry.messages import CHANNELS, Io, Joints, MotorReading, Motors, ProgramStep, Tcp

TCP_LINK = "tcp"  # the URDF's frame at the flange's TCP: its course is drawn as /tcp_path
PATH_PIECE_SAMPLES = 10  # the TCP's course is written a second at a time (at 10 samples a second)


@dataclass(frozen=True)
class ArmState:
    """What the page last read besides the motors, for the /tcp, /io, /cell and /program channels."""

    tcp: Position | None = None
    outputs: Mapping[int, SignalLevel] = field(default_factory=dict)
    inputs: Mapping[int, SignalLevel] = field(default_factory=dict)
    motion_status: str | None = None
    obstacles: tuple[Obstacle, ...] | None = None  # the cell, when the page has read it
    program: tuple[int, str, str] | None = None  # the step running: line (1-based), its text, the run state


def _levels(levels: Mapping[int, SignalLevel], ports: tuple[int, ...]) -> list[float]:
    return [1.0 if levels.get(p) == SignalLevel.HIGH else 0.0 for p in ports]


class ArmChannels:
    """The channels on `context`, and the arm's samples written to them. Not thread-safe: its owner holds a
    lock (the Foxglove channels themselves may be logged to from any thread)."""

    def __init__(self, context: foxglove.Context, arm: ArmDrawing | None = None) -> None:
        self._context = context  # kept: a context that is collected closes its channels
        self._json = {
            topic: foxglove.Channel(
                topic,
                schema=foxglove.Schema(name=name, encoding="jsonschema", data=json.dumps(schema).encode()),
                message_encoding="json",
                context=context,
            )
            for topic, (name, schema) in CHANNELS.items()
        }
        self._tf = FrameTransformsChannel("/tf", context=context)
        self.arm_channel = SceneUpdateChannel("/arm", context=context)
        self._cell = SceneUpdateChannel("/cell", context=context)
        self._path = SceneUpdateChannel("/tcp_path", context=context)
        self._events = LogChannel("/events", context=context)
        self.arm = arm  # draws the arm on /tf and /arm (None: those stay empty)
        self._path_points: list[tuple[float, float, float]] = []
        self._path_pieces = 0
        self._program: tuple[int, str, str] | None = None
        self.cell_written: tuple[Obstacle, ...] | None = None
        self.messages = 0

    def write_state(self, time_ns: int, motors: Sequence[MotorStatus], state: ArmState) -> None:
        """One sample: the cell when it changed, the program step when it changed, the motors and the rest."""
        if state.obstacles is not None and state.obstacles != self.cell_written:
            self.write_cell(time_ns, state.obstacles)
            self.cell_written = state.obstacles
        if state.program is not None:
            self.write_program(time_ns, *state.program)
        self.write_sample(
            time_ns,
            motors,
            state.tcp,
            _levels(state.outputs, OUTPUT_PORTS),
            _levels(state.inputs, INPUT_PORTS),
            state.motion_status,
        )

    def write_arm(self, time_ns: int) -> None:
        """The links' meshes on /arm (locked to their /tf frames: written once, they follow the arm)."""
        if self.arm is not None:
            self.arm_channel.log(foxglove_scene.arm_meshes(time_ns, self.arm.meshes), log_time=time_ns)
            self.messages += 1

    def write(self, topic: str, time_ns: int, message: BaseModel) -> None:
        self._json[topic].log(message.model_dump(), log_time=time_ns)
        self.messages += 1

    def write_event(self, event: Event) -> None:
        self._events.log(foxglove_scene.log(event), log_time=int(event.wall_time * 1e9))
        self.messages += 1

    def write_cell(self, time_ns: int, obstacles: Sequence[Obstacle]) -> None:
        self._cell.log(foxglove_scene.cell(time_ns, obstacles), log_time=time_ns)
        self.messages += 1

    def write_program(self, time_ns: int, line: int, step: str, state: str) -> None:
        """The step running, written when it changes."""
        if self._program != (line, step, state):
            self._program = (line, step, state)
            self.write("/program", time_ns, ProgramStep(line=line, step=step, state=state))

    def write_sample(
        self,
        time_ns: int,
        motors: Sequence[MotorStatus],
        tcp: Position | None,
        outputs: Sequence[float],
        inputs: Sequence[float],
        motion_status: str | None,
    ) -> None:
        joints = Joints(
            name=[f"J{i + 1}" for i in range(len(motors))],
            position_deg=[m.angle for m in motors],
            velocity_rpm=[m.rotorVelocity for m in motors],
        )
        self.write("/joints", time_ns, joints)
        readings = [MotorReading.model_validate(m.model_dump()) for m in motors]
        self.write("/motors", time_ns, Motors(motors=readings))
        if tcp is not None:
            self.write("/tcp", time_ns, Tcp(**tcp.point.model_dump(), **tcp.rotation.model_dump()))
        io = Io(outputs=list(outputs), inputs=list(inputs), motion_status=motion_status or "")
        self.write("/io", time_ns, io)
        if self.arm is not None and len(motors) == 6:
            q = np.radians([m.angle for m in motors])
            poses = self.arm.link_poses(q)
            self._tf.log(foxglove_scene.frame_transforms(time_ns, poses), log_time=time_ns)
            self.messages += 1
            if TCP_LINK in poses:
                x, y, z = (float(v) for v in poses[TCP_LINK][:3, 3])
                self._add_path_point(time_ns, (x, y, z))

    def _add_path_point(self, time_ns: int, point: tuple[float, float, float]) -> None:
        self._path_points.append(point)
        if len(self._path_points) >= PATH_PIECE_SAMPLES:
            self._write_path_piece(time_ns)

    def _write_path_piece(self, time_ns: int) -> None:
        if len(self._path_points) >= 2:
            update = foxglove_scene.tcp_path(time_ns, self._path_pieces, self._path_points)
            self._path.log(update, log_time=time_ns)
            self._path_pieces += 1
            self.messages += 1
        self._path_points = self._path_points[-1:]  # the next piece starts where this one ended
