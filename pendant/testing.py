"""pytest plugin: the `pulse_sim` fixture, a simulated PULSE controller for tests of robot code.

Active wherever the package is installed (a `pytest11` entry point), or with `pytest -p pendant.testing`.

    def test_pick(pulse_sim):
        run_my_robot_code(pulse_sim.url)         # any client: Rozum's SDK, httpx, your own
        pulse_sim.fault("error")                  # emergency, no_response, motion_failed, overheat, ...
        pulse_sim.set_input(1, "high")
        pulse_sim.at(2.0, "emergency")            # at simulated time 2 s
        pulse_sim.on_waypoint(2, "error")         # when the current run reaches its 2nd waypoint
        pulse_sim.on_command(3, "no_response")    # when the 3rd command arrives
        pulse_sim.record("pick", tmp_path)        # an MCAP + CSV of the test's run, finished at its end

One simulator serves per session (per xdist worker) and model, over real HTTP on a free loopback port,
reset to its power-on state before each test (well under a millisecond). Options, on the command line, in
the ini file, or per test with `@pytest.mark.pulse_sim(...)`: model (pulse75, pulse90), time scale
(simulated seconds per wall second, default 10) and a cell file.

This module is imported by every pytest run where the package is installed: it imports nothing heavy until
a test asks for the fixture.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pytest

if TYPE_CHECKING:
    from pendant.sim.script import ScriptedEvent
    from pendant.simserver import SimServer

DEFAULT_MODEL = "pulse75"
DEFAULT_TIME_SCALE = 10.0
# Every fault kind the fixture knows; those the simulator does not have yet are refused with a message.
FAULT_KINDS = ("error", "emergency", "no_response", "motion_failed", "overheat", "twisted", "protective_stop")
# Kinds played by a simulator method rather than a `Fault` member, when the simulator has that method.
FAULT_METHODS = {
    "overheat": "overheat",  # as PUT /sim/fault/overheat
    "protective_stop": "stop",  # POST /stop, as the PULSE 1.8 simulator names it
}
ENVIRONMENT_PATH = "/environment"
MARKER = "pulse_sim"
_OPTIONS = {
    "model": ("--pulse-sim-model", "pulse_sim_model", "simulated arm: pulse75 or pulse90", DEFAULT_MODEL),
    "time_scale": (
        "--pulse-sim-time-scale",
        "pulse_sim_time_scale",
        "simulated seconds per wall-clock second (0.1 to 1000)",
        str(DEFAULT_TIME_SCALE),
    ),
    "cell": ("--pulse-sim-cell", "pulse_sim_cell", "cell file (obstacles) applied before each test", None),
}

Action = str | Callable[[], object]


class PulseSimError(Exception):
    """What the fixture cannot do: an unknown or not yet simulated fault, a cell it cannot apply."""


def pytest_addoption(parser: pytest.Parser) -> None:
    group = parser.getgroup("pulse_sim", "PULSE simulator fixture (pendant.testing)")
    for flag, ini, help_text, default in _OPTIONS.values():
        group.addoption(flag, default=None, help=help_text)
        parser.addini(ini, help_text, default=default)


def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line(
        "markers", f"{MARKER}(model=None, time_scale=None, cell=None): options of the pulse_sim fixture"
    )


@pytest.hookimpl(tryfirst=True)
def pytest_runtest_call(item: pytest.Item) -> None:
    # The test's simulated time starts with the test function (or its first request, if a fixture sends one).
    handle = getattr(item, "funcargs", {}).get("pulse_sim")
    if isinstance(handle, PulseSim):
        handle.begin()


def _option(request: pytest.FixtureRequest, name: str) -> Any:
    marker = request.node.get_closest_marker(MARKER)
    if marker is not None and marker.kwargs.get(name) is not None:
        return marker.kwargs[name]
    flag, ini, _, _ = _OPTIONS[name]
    value = request.config.getoption(flag)
    return value if value is not None else request.config.getini(ini)


class PulseSim:
    """What a test gets: the simulator's URL and the outside world to play (faults, inputs, a hand)."""

    def __init__(self, server: SimServer, time_scale: float) -> None:
        self._server = server
        self.url: str = server.url
        self.model: str = server.model
        self.time_scale = time_scale
        self.events: list[ScriptedEvent] = []
        self._recording: tuple[Any, Any] | None = None  # (Telemetry, RecordingSampler) while recording

    def record(self, name: str | None = None, folder: str | Path | None = None) -> Path:
        """Record the arm from now to the end of the test (or `stop_recording()`): the pendant's MCAP and
        CSV files, `folder/pendant-NAME.mcap` (default folder: the pendant's data folder's recordings/,
        default name: the start time). Log times follow the simulated clock. The .mcap's path."""
        from pendant.monitoring import data_dir
        from pendant.telemetry import Telemetry, arm_drawing, recordings_dir
        from pendant.telemetry.headless import RecordingSampler

        if self._recording is not None:
            raise PulseSimError("pulse_sim.record(): this test is already recording")
        sim = self._server.sim
        target = Path(folder) if folder is not None else recordings_dir(data_dir(None))
        telemetry = Telemetry(sim, self._server.clock.now, recordings_folder=target, arm=arm_drawing(sim.arm))
        started = telemetry.start_recording(name, exclusive=True)
        self._recording = (telemetry, RecordingSampler(sim, telemetry).start())
        return target / f"pendant-{started}.mcap"

    def stop_recording(self) -> int:
        """Finish the test's recording (done for you at its end); the number of samples, 0 if none."""
        if self._recording is None:
            return 0
        telemetry, sampler = self._recording
        self._recording = None
        sampler.stop()
        return int(telemetry.stop_recording())

    def begin(self) -> None:
        """Start the test's simulated time now (done for you when the test function starts)."""
        self._server.begin()

    @property
    def controller(self) -> Any:
        """The simulator itself (`pendant.sim.SimController`), in this process."""
        return self._server.sim

    @property
    def time(self) -> float:
        """Simulated seconds since the test started."""
        return self._server.clock.now() - self.origin

    @property
    def origin(self) -> float:
        """The simulator clock's reading (GET /sim/clock `time`) when the test started: its time 0."""
        return self._server.script.origin

    def fault(self, kind: str) -> None:
        """Make the controller fail now: error, emergency, no_response, motion_failed, overheat, twisted,
        protective_stop (see `fault_kinds()` for those this simulator has)."""
        self._fault_action(kind)()

    def fault_kinds(self) -> list[str]:
        """The fault kinds this simulator can play."""
        return [kind for kind in FAULT_KINDS if self._fault_or_none(kind) is not None]

    def set_input(self, port: int, level: str | bool) -> None:
        """Drive digital input `port` (1-4) HIGH or LOW, as a sensor wired to the control box would."""
        from pendant.controller.types import SignalLevel

        if isinstance(level, bool):
            signal = SignalLevel.HIGH if level else SignalLevel.LOW
        else:
            signal = SignalLevel(str(level).upper())
        self._server.sim.set_input(port, signal)

    def move_by_hand(self, angles: Sequence[float]) -> None:
        """Put the relaxed arm (ZERO_GRAVITY, after PUT /relax) at six joint angles in degrees."""
        from pendant.controller.types import Pose

        self._server.sim.move_by_hand(Pose(angles=list(angles)))

    def at(self, t: float, action: Action) -> ScriptedEvent:
        """`action` (a fault kind, or a function of no arguments) at simulated time `t` s of this test."""
        return self._keep(self._server.script.at(t, self._action(action), f"at t={t:g} s: {action}"))

    def on_waypoint(self, k: int, action: Action) -> ScriptedEvent:
        """`action` when the run moving now (else the next one sent) reaches its k-th waypoint (from 1)."""
        script = self._server.script
        return self._keep(script.on_waypoint(k, self._action(action), f"at waypoint {k}: {action}"))

    def on_command(self, n: int, action: Action) -> ScriptedEvent:
        """`action` when the n-th command (PUT/POST/DELETE) of this test arrives, before it is handled."""
        script = self._server.script
        return self._keep(script.on_command(n, self._action(action), f"on command {n}: {action}"))

    def _keep(self, event: ScriptedEvent) -> ScriptedEvent:
        self.events.append(event)
        return event

    def _action(self, action: Action) -> Callable[[], object]:
        return self._fault_action(action) if isinstance(action, str) else action

    def _fault_action(self, kind: str) -> Callable[[], object]:
        name = kind.strip().lower().replace(" ", "_").replace("-", "_")
        action = self._fault_or_none(name)
        if action is not None:
            return action
        have = ", ".join(self.fault_kinds())
        if name in FAULT_KINDS:
            raise PulseSimError(
                f"fault {kind!r} is not in this simulator yet (it has: {have}); TWISTED and the protective "
                "stop come with the PULSE 1.8 operations (issue #11)"
            )
        raise PulseSimError(f"unknown fault {kind!r}: choose from {have}")

    def _fault_or_none(self, name: str) -> Callable[[], object] | None:
        from pendant.sim import Fault

        sim = self._server.sim
        member = Fault.__members__.get(name.upper())
        if member is not None:
            return lambda: sim.inject_fault(member)
        method_name = FAULT_METHODS.get(name)
        method = getattr(sim, method_name, None) if method_name is not None else None
        return method if callable(method) else None

    def apply_cell(self, path: str | Path) -> None:
        """Put the cell file's obstacles in the simulator's environment (through its own API)."""
        import httpx

        document = json.loads(Path(path).read_text(encoding="utf-8"))
        obstacles = document.get("obstacles", []) if isinstance(document, dict) else document
        with httpx.Client(base_url=self.url, timeout=10.0) as client:
            for obstacle in obstacles:
                response = client.put(ENVIRONMENT_PATH, json=obstacle)
                if response.status_code != 200:  # a refusal, or a simulator without /environment (404)
                    raise PulseSimError(f"cell {str(path)!r}: obstacle refused: {response.text[:200]}")


class _Servers:
    """One simulator per model, started when a test first asks for it, stopped at the end of the session."""

    def __init__(self) -> None:
        self._by_model: dict[str, SimServer] = {}

    def get(self, model: str) -> SimServer:
        if model not in self._by_model:
            from pendant.simserver import SimServer

            self._by_model[model] = SimServer(model=model).start()
        return self._by_model[model]

    def stop(self) -> None:
        for server in self._by_model.values():
            server.stop()
        self._by_model.clear()


@pytest.fixture(scope="session")
def _pulse_sim_servers() -> Iterator[_Servers]:
    servers = _Servers()
    try:
        yield servers
    finally:
        servers.stop()


@pytest.fixture
def pulse_sim(request: pytest.FixtureRequest, _pulse_sim_servers: _Servers) -> Iterator[PulseSim]:
    """A simulated PULSE controller in its power-on state, at `pulse_sim.url`."""
    time_scale = float(_option(request, "time_scale"))
    server = _pulse_sim_servers.get(str(_option(request, "model")))
    server.reset(time_scale)
    handle = PulseSim(server, time_scale)
    cell = _option(request, "cell")
    if cell:
        handle.apply_cell(Path(str(request.config.rootpath), str(cell)))
    try:
        yield handle
    finally:
        handle.stop_recording()  # a recording of the test is finished, readable, whatever its outcome
    errors = server.script.errors
    server.reset(time_scale)  # nothing scripted outlives its test
    if errors:
        raise PulseSimError("; ".join(f"{event.description}: {error}" for event, error in errors))
