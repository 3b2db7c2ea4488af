"""A recording as an MCAP file written with Foxglove's SDK, which Foxglove opens as it is: the arm in 3D
(/tf: foxglove.FrameTransforms of every link; /arm: foxglove.SceneUpdate of the links' meshes, locked to their
frames), the cell (/cell), the TCP's course (/tcp_path), the event log (/events: foxglove.Log), and JSON
series for plots: /joints, /tcp, /motors, /io, /program (the step running), each message built from its model
in messages.py, whose JSON schema the channel carries. Log times are wall-clock ns.

Chunks are flushed to disk at least every FLUSH_PERIOD_S, so a pendant killed with -9 leaves a file readable
up to its last flush (repair.py finishes it on the next start)."""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path

import foxglove
import numpy as np
from foxglove.channels import FrameTransformsChannel, LogChannel, SceneUpdateChannel
from foxglove.mcap import MCAPWriteOptions
from pydantic import BaseModel

from pendant import __version__
from pendant.controller.cell_types import Obstacle
from pendant.controller.types import MotorStatus, Position
from pendant.eventlog import Event
from pendant.telemetry import foxglove_scene
from pendant.telemetry.arm_scene import ArmDrawing
from pendant.telemetry.messages import CHANNELS, Io, Joints, MotorReading, Motors, ProgramStep, Tcp

FLUSH_PERIOD_S = 1.0  # at most this much of a recording is lost to a kill -9
TCP_LINK = "tcp"  # the URDF's frame at the flange's TCP: its course is drawn as /tcp_path
PATH_PIECE_SAMPLES = 10  # the TCP's course is written a second at a time (at 10 samples a second)


class McapFile:
    """One recording being written. Not thread-safe: the caller (Telemetry) holds its lock."""

    def __init__(self, path: Path, arm: ArmDrawing | None = None, start_ns: int = 0) -> None:
        self.path = path
        self._context = foxglove.Context()
        options = MCAPWriteOptions(profile="", compression_threads=0)
        self._writer = foxglove.open_mcap(path, context=self._context, writer_options=options)
        self._writer.write_metadata("pendant", {"library": f"pulse-pendant {__version__}"})
        self._json = {
            topic: foxglove.Channel(
                topic,
                schema=foxglove.Schema(name=name, encoding="jsonschema", data=json.dumps(schema).encode()),
                message_encoding="json",
                context=self._context,
            )
            for topic, (name, schema) in CHANNELS.items()
        }
        self._tf = FrameTransformsChannel("/tf", context=self._context)
        self._arm_channel = SceneUpdateChannel("/arm", context=self._context)
        self._cell = SceneUpdateChannel("/cell", context=self._context)
        self._path = SceneUpdateChannel("/tcp_path", context=self._context)
        self._events = LogChannel("/events", context=self._context)
        self._arm = arm
        if arm is not None:
            self._writer.attach(
                log_time=start_ns,
                create_time=start_ns,
                name=arm.urdf.name,
                media_type="application/xml",
                data=arm.urdf.read_bytes(),
            )
            self._arm_channel.log(foxglove_scene.arm_meshes(start_ns, arm.meshes), log_time=start_ns)
        self._path_points: list[tuple[float, float, float]] = []
        self._path_pieces = 0
        self._flushed_ns = start_ns
        self._program: tuple[int, str, str] | None = None
        self.messages = 0

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
        if self._arm is not None and len(motors) == 6:
            q = np.radians([m.angle for m in motors])
            poses = self._arm.link_poses(q)
            self._tf.log(foxglove_scene.frame_transforms(time_ns, poses), log_time=time_ns)
            self.messages += 1
            if TCP_LINK in poses:
                x, y, z = (float(v) for v in poses[TCP_LINK][:3, 3])
                self._add_path_point(time_ns, (x, y, z))
        if time_ns - self._flushed_ns >= FLUSH_PERIOD_S * 1e9:
            self.flush(time_ns)

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

    def flush(self, time_ns: int) -> None:
        """Finish the current chunk and write it to disk: readable from here on, whatever happens next."""
        self._writer.flush()
        self._flushed_ns = time_ns

    def close(self) -> None:
        self._writer.close()
