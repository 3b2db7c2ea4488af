"""A program as a standalone Python script that drives a PULSE controller over HTTP with the same motion.

The script executes the runner's grouping (pendant.program.plan): consecutive moves of one type and speed
are one PUT /poses/run or /positions/run, and it waits for each motion the way the runner does (polling
GET /status/motion and the pose). It needs only Python and httpx. In front of a teach pendant exposed on the
network it sends the pendant's access token (--token or $PULSE_PENDANT_TOKEN) with every request.
"""

from __future__ import annotations

import pprint
import re
from datetime import UTC, datetime

from pendant.access.token import TOKEN_HEADER
from pendant.controller.types import DEFAULT_GRIPPER_TIMEOUT_MS, MotionType, Position
from pendant.program.blended import FALLBACK_NOTE, PATH_ACCELERATION_M_S2
from pendant.program.describe import describe_step
from pendant.program.export_template import TEMPLATE
from pendant.program.files import rounded
from pendant.program.geometry import MM
from pendant.program.models import GripperStep, OutputStep, Program, WaitInputStep, WaitStep
from pendant.program.motion import ARRIVAL_TOL_DEG, ARRIVAL_TOL_M, POLL_S, START_GRACE_S
from pendant.program.plan import Branch, Loader, Loop, MoveGroup, Node, Pallet, Single, compile_program

DEFAULT_URL = "http://127.0.0.1:8081"
TOKEN_ENV = "PULSE_PENDANT_TOKEN"
Operation = dict[str, object]


def program_operations(program: Program, load: Loader | None = None) -> list[Operation]:
    """The program as a tree of controller operations (plain data: str, int, float, list, dict): the same
    plan the runner executes (pendant.program.plan), with Call steps inlined by `load`."""
    return [_operation(node) for node in compile_program(program, load)]


def _operations(nodes: tuple[Node, ...]) -> list[Operation]:
    return [_operation(node) for node in nodes]


def _operation(node: Node) -> Operation:
    match node:
        case MoveGroup() if node.path:
            return _path(node)
        case MoveGroup():
            numbers = sorted({t.line + 1 for t in node.targets})
            what = "; ".join(
                f"Move {'J' if node.motion is MotionType.JOINT else 'L'} to {t.name}" for t in node.targets
            )
            operation: Operation = {
                "op": "run_poses" if node.by_angles else "run_positions",
                "steps": numbers,
                "what": f"{what} @ {node.speed:g}%",
                "speed": node.speed,
                "motion": node.motion.value,
                "targets": [
                    (
                        [float(a) for a in t.pose.angles]
                        if t.pose is not None
                        else _position(t.expect_position())
                    )
                    for t in node.targets
                ],
            }
            actions = [a.model_dump(mode="json") for a in node.targets[-1].actions]
            if actions:  # stop-and-set: done once the arm is at the last waypoint
                operation["actions"] = actions
            return rounded(operation)
        case Single():
            return _single(node)
        case Loop():
            return {
                "op": "loop",
                "steps": [node.line + 1],
                "what": f"Loop {node.mode.value}",
                "mode": node.mode.value,
                "times": node.times,
                "port": node.port,
                "level": node.level.value,
                "body": _operations(node.body),
            }
        case Branch():
            return {
                "op": "if",
                "steps": [node.line + 1],
                "what": f"If DI{node.port} {node.level.value}",
                "port": node.port,
                "level": node.level.value,
                "then": _operations(node.then),
                "else": _operations(node.otherwise),
            }
        case Pallet():
            return {
                "op": "pallet",
                "steps": [node.line + 1],
                "what": f"Pallet {node.name}",
                "name": node.name,
                "speed": node.speed,
                "approach_m": node.approach_m,
                "cells": [_position(cell) for cell in node.cells],
                "body": _operations(node.body),
            }
    raise TypeError(f"not a plan node: {node!r}")


def _path(node: MoveGroup) -> Operation:
    """A recorded path's run: one PUT /run/linear/positions, each corner rounded within its blend (m)."""
    targets, velocity = node.targets, node.velocity_m_s
    assert velocity is not None, "a path's group has its velocity"
    return rounded(
        {
            "op": "run_path",
            "steps": [node.line + 1],
            "what": f"Path {targets[0].name} .. {targets[-1].name} @ {velocity / MM:g} mm/s",
            "velocity": velocity,
            "acceleration": PATH_ACCELERATION_M_S2,
            "targets": [{**_position(t.expect_position()), "blend": t.blend_mm * MM} for t in targets],
        }
    )


def _position(position: Position) -> Operation:
    return rounded(position.model_dump(mode="json"))


def _single(node: Single) -> Operation:
    step, base = node.step, {"steps": [node.line + 1], "what": describe_step(node.step)}
    match step:
        case GripperStep():
            return {"op": "gripper", **base, "action": step.action.value, "timeout_ms": step.timeout_ms}
        case OutputStep():
            return {"op": "output", **base, "port": step.port, "level": step.level.value}
        case WaitInputStep():
            return {
                "op": "wait_input",
                **base,
                "port": step.port,
                "level": step.level.value,
                "timeout_ms": step.timeout_ms,
            }
        case WaitStep():
            return {"op": "wait", **base, "ms": step.ms}
    raise TypeError(f"not a single step: {step!r}")


def export_script(program: Program, load: Loader | None = None) -> str:
    """Python source of a script running `program` on the controller given by argv or $PULSE_URL."""
    values = {
        "__NAME__": docstring_safe(program.name),
        "__STAMP__": datetime.now(UTC).strftime("%Y-%m-%d %H:%M UTC"),
        "__DEFAULT_URL__": DEFAULT_URL,
        "__TOKEN_HEADER__": TOKEN_HEADER,
        "__TOKEN_ENV__": TOKEN_ENV,
        "__OPERATIONS__": pprint.pformat(program_operations(program, load), width=110, sort_dicts=False),
        "__POLL_S__": repr(POLL_S),
        "__START_GRACE_S__": repr(START_GRACE_S),
        "__TOL_DEG__": repr(ARRIVAL_TOL_DEG),
        "__TOL_M__": repr(ARRIVAL_TOL_M),
        "__GRIPPER_TIMEOUT_MS__": repr(DEFAULT_GRIPPER_TIMEOUT_MS),
        "__PATH_FALLBACK__": repr(FALLBACK_NOTE),
    }
    # One pass: a name that happens to read "__OPERATIONS__" stays a name, never a place to paste into.
    placeholders = re.compile("|".join(map(re.escape, values)))
    return placeholders.sub(lambda match: values[match.group(0)], TEMPLATE)


def docstring_safe(text: str) -> str:
    """`text` as it may stand inside the script's docstring: no quote or backslash that could end or bend
    it, no control character, NUL or lone surrogate that would stop the script from compiling or saving."""
    return "".join(c if c.isprintable() and c not in '"\\' else "?" for c in text)
