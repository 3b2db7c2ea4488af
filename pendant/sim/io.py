"""The control box's digital IO and the gripper's end positions."""

from __future__ import annotations

from pendant.controller.errors import PreconditionFailed
from pendant.controller.types import INPUT_PORTS, OUTPUT_PORTS, SignalLevel

GRIPPER_OPEN, GRIPPER_CLOSED = 1.0, 0.0
POWER_ON_GRIPPER = GRIPPER_OPEN


def check_port(port: int, ports: tuple[int, ...], kind: str) -> int:
    if port not in ports:
        choices = ", ".join(str(p) for p in ports[:-1]) + f" or {ports[-1]}"
        raise PreconditionFailed(f"{kind} port must be {choices} (got {port})")
    return port


class IOBoard:
    """Digital outputs (set by commands) and inputs (driven by the simulated cell), all LOW at power-on."""

    def __init__(self) -> None:
        self.outputs = dict.fromkeys(OUTPUT_PORTS, SignalLevel.LOW)
        self.inputs = dict.fromkeys(INPUT_PORTS, SignalLevel.LOW)

    def output(self, port: int) -> SignalLevel:
        return self.outputs[check_port(port, OUTPUT_PORTS, "output")]

    def input(self, port: int) -> SignalLevel:
        return self.inputs[check_port(port, INPUT_PORTS, "input")]

    def set_output(self, port: int, level: SignalLevel) -> None:
        self.outputs[check_port(port, OUTPUT_PORTS, "output")] = SignalLevel(level)

    def set_input(self, port: int, level: SignalLevel) -> None:
        self.inputs[check_port(port, INPUT_PORTS, "input")] = SignalLevel(level)
