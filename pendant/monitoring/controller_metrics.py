"""The arm's readings as Prometheus gauges, read from the controller when Prometheus scrapes.

One scrape costs a motion status read, one motors read and six IO reads (on a real arm, eight small GETs);
an unreachable or not-responding controller costs one, and only whether it is online and responding is
reported then.
"""

from __future__ import annotations

import time
from collections.abc import Iterator

from prometheus_client.core import GaugeMetricFamily, Metric
from prometheus_client.registry import Collector

from pendant.controller import ControllerError
from pendant.controller.errors import ControllerOffline, Emergency, NotResponding
from pendant.controller.protocol import Controller
from pendant.controller.types import INPUT_PORTS, OUTPUT_PORTS, MotionStatus, SignalLevel

# (metric name, help, MotorStatus field) per joint
MOTOR_GAUGES = (
    ("pulse_joint_angle_degrees", "Joint angle (servo flange), degrees", "angle"),
    ("pulse_motor_rotor_velocity_rpm", "Motor rotor velocity, rpm", "rotorVelocity"),
    ("pulse_motor_current_rms_amperes", "Motor RMS current, A", "rmsCurrent"),
    ("pulse_motor_voltage_volts", "Motor supply voltage, V", "voltage"),
    ("pulse_motor_stator_temperature_celsius", "Stator (winding) temperature, °C", "statorTemperature"),
    ("pulse_motor_servo_temperature_celsius", "Servo board temperature, °C", "servoTemperature"),
    ("pulse_motor_position_error_degrees", "Servo position error, degrees", "positionError"),
)


class ControllerCollector(Collector):
    """Reads the controller once per scrape (blocking: the /metrics route runs in a worker thread)."""

    def __init__(self, controller: Controller) -> None:
        self._controller = controller

    def collect(self) -> Iterator[Metric]:
        online = GaugeMetricFamily(
            "pulse_controller_online",
            "1 when the controller answers at all (as /pendant/health's online); 0 when it cannot be reached",
        )
        responding = GaugeMetricFamily(
            "pulse_controller_responding",
            "0 when the controller answers 500 'Robot does not respond' (the arm does not), else 1",
        )
        latency = GaugeMetricFamily(
            "pulse_controller_latency_seconds", "Round trip of the scrape's motion status read"
        )
        t0 = time.perf_counter()
        status: MotionStatus | None = None
        try:
            status = self._controller.get_motion_status()
        except ControllerOffline:
            online.add_metric([], 0.0)
            yield online
            return
        except NotResponding:
            online.add_metric([], 1.0)
            responding.add_metric([], 0.0)
            yield from (online, responding)
            return
        except Emergency:
            status = MotionStatus.EMERGENCY
        except ControllerError:
            pass
        online.add_metric([], 1.0)
        responding.add_metric([], 1.0)
        latency.add_metric([], time.perf_counter() - t0)
        yield from (online, responding, latency)
        state = GaugeMetricFamily(
            "pulse_motion_state", "1 for the controller's current motion status", labels=["state"]
        )
        for value in MotionStatus:
            state.add_metric([value.value], 1.0 if value is status else 0.0)
        yield state
        if status is MotionStatus.EMERGENCY:  # every other call answers 503
            return
        yield from self._motors()
        yield from self._io()

    def _motors(self) -> Iterator[Metric]:
        try:
            motors = self._controller.get_motors()
        except ControllerError:
            return
        for name, help_text, field in MOTOR_GAUGES:
            family = GaugeMetricFamily(name, help_text, labels=["joint"])
            for i, motor in enumerate(motors):
                family.add_metric([f"J{i + 1}"], float(getattr(motor, field)))
            yield family

    def _io(self) -> Iterator[Metric]:
        for name, ports, read in (
            ("pulse_digital_output", OUTPUT_PORTS, self._controller.get_output),
            ("pulse_digital_input", INPUT_PORTS, self._controller.get_input),
        ):
            family = GaugeMetricFamily(name, f"{name.split('_')[-1]} level, 1 HIGH, 0 LOW", labels=["port"])
            try:
                for port in ports:
                    family.add_metric([str(port)], 1.0 if read(port) == SignalLevel.HIGH else 0.0)
            except ControllerError:
                continue
            yield family
