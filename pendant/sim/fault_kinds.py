"""The faults the simulator can play, declared once: the /sim/fault/{fault} path and its documentation, and
the simulator panel's buttons, read this table. Adding a kind: one `FaultKind` here (and, for a new behaviour,
its member of `Fault` in pendant.sim.states)."""

from __future__ import annotations

from dataclasses import dataclass

from pendant.sim.states import Fault


@dataclass(frozen=True)
class FaultKind:
    """`name` as in the path; `fault` the simulator's Fault it injects (None: `overheat`, which is played by
    the thermal model, not the state machine); `label` the panel's button (None: API only)."""

    name: str
    fault: Fault | None
    description: str
    label: str | None = None


FAULT_KINDS: tuple[FaultKind, ...] = (
    FaultKind(
        "error",
        Fault.ERROR,
        "the arm stops, frozen, status ERROR (PUT /recover brings it back).",
        "Inject ERROR",
    ),
    FaultKind(
        "emergency",
        Fault.EMERGENCY,
        "status EMERGENCY, every PULSE call answers 503 until /sim/reset.",
        "Inject EMERGENCY",
    ),
    FaultKind(
        "no_response",
        Fault.NO_RESPONSE,
        "every PULSE call answers 500 until /sim/reset.",
        "Inject no response",
    ),
    FaultKind("motion_failed", Fault.MOTION_FAILED, "the running motion fails, status MOTION_FAILED."),
    FaultKind(
        "overheat",
        None,
        "the stator windings jump to 110 °C, then cool as the thermal model says (about 80 s above 80 °C).",
    ),
    FaultKind(
        "twisted",
        Fault.TWISTED,
        "GET /status says TWISTED, motion answers 412 until PUT /untwisting/finish.",
    ),
)
FAULT_KINDS_BY_NAME: dict[str, FaultKind] = {kind.name: kind for kind in FAULT_KINDS}


def fault_kinds_description() -> str:
    """Every kind and what it does, for the API's documentation."""
    return " ".join(f"{kind.name}: {kind.description}" for kind in FAULT_KINDS)
