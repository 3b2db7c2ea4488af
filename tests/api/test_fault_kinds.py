"""The one table of fault kinds (pendant.sim.fault_kinds): every fault the simulator knows is in it, and every
kind is served at /sim/fault/{name}, documented there, and does what it says."""

from __future__ import annotations

from fastapi.testclient import TestClient

from pendant.api import create_app
from pendant.sim import FakeClock, Fault, SimController
from pendant.sim.fault_kinds import FAULT_KINDS
from pendant.ui.robot.sim_panel import FAULT_LABELS


def test_every_simulator_fault_is_a_kind_of_the_table() -> None:
    assert {kind.fault for kind in FAULT_KINDS if kind.fault is not None} == set(Fault)
    assert len({kind.name for kind in FAULT_KINDS}) == len(FAULT_KINDS)


def test_every_kind_is_served_and_documented() -> None:
    app = create_app(SimController("pulse75", FakeClock()))
    schema = app.openapi()
    parameter = schema["paths"]["/sim/fault/{fault}"]["put"]["parameters"][0]
    assert set(schema["components"]["schemas"]["FaultName"]["enum"]) == {kind.name for kind in FAULT_KINDS}
    for kind in FAULT_KINDS:
        assert f"{kind.name}: {kind.description}" in parameter["schema"]["description"]
        with TestClient(create_app(SimController("pulse75", FakeClock()))) as client:
            assert client.put(f"/sim/fault/{kind.name}").status_code == 200, kind
            if kind.fault is Fault.EMERGENCY:
                assert client.get("/pose").status_code == 503
            if kind.fault is Fault.ERROR:
                assert client.get("/status/motion").text == '"ERROR"'
    assert client.put("/sim/fault/meltdown").status_code == 412


def test_the_panels_buttons_are_the_tables() -> None:
    assert FAULT_LABELS == {
        Fault.ERROR: "Inject ERROR",
        Fault.EMERGENCY: "Inject EMERGENCY",
        Fault.NO_RESPONSE: "Inject no response",
    }
