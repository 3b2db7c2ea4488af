"""The exported script's source, with placeholders pendant.program.export fills in (one pass)."""

TEMPLATE = '''#!/usr/bin/env python3
"""PULSE program "__NAME__", exported by the PULSE teach pendant (__STAMP__).

Runs the taught motion on a PULSE controller through its REST API:

    python this_script.py [CONTROLLER_URL] [--loops N] [--token TOKEN]

CONTROLLER_URL defaults to $PULSE_URL, else __DEFAULT_URL__. --loops 0 repeats until Ctrl-C (which freezes
the arm). Exit status 0 when the program ran to the end, 1 when a step failed or a request was refused (the
HTTP status and the controller's message are printed), 2 on bad arguments.

A PULSE controller needs no token. A teach pendant exposed on the network (`pendant --host 0.0.0.0`) refuses
commands without its access token (401, or 403 for a wrong one): give it with --token or, better, in
$__TOKEN_ENV__, since a command line is visible to every user of the machine (ps). It is sent in the
__TOKEN_HEADER__ header of every request.

Why plain httpx and not Rozum's official SDK (pulse-api): httpx is what the pendant itself speaks with, so
the script runs wherever the pendant is installed, with no second SDK and its own pinned dependencies
(pdhttp) to clash with yours; and every request is right here to read, one call per step, exactly as the
controller's API reference documents it.

Consecutive moves of the same type and speed go in one PUT /poses/run (taught angles) or /positions/run
(TCP positions: linear moves, relative moves, pallet cells), so the arm blends through them; the script then
polls GET /status/motion until the arm is IDLE at the last waypoint, as the pendant's runner does. A
recorded path is one PUT /run/linear/positions (PULSE 1.8: each corner rounded within its blend); a
controller without it (404) gets one PUT /positions/run per waypoint, stopping at each. Loops,
If DI / Else and pallets (the next cell each pass) run as in the pendant; called programs are inlined.
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import httpx

OPERATIONS = __OPERATIONS__

POLL_S = __POLL_S__
START_GRACE_S = __START_GRACE_S__  # a controller may still say IDLE just after accepting a motion
ARRIVAL_TOL_DEG = __TOL_DEG__
ARRIVAL_TOL_M = __TOL_M__
GRIPPER_TIMEOUT_MS = __GRIPPER_TIMEOUT_MS__
PATH_FALLBACK = __PATH_FALLBACK__
FAILED_STATES = ("MOTION_FAILED", "ERROR", "EMERGENCY", "ZERO_GRAVITY")
TOKEN_HEADER = "__TOKEN_HEADER__"
TOKEN_ENV = "__TOKEN_ENV__"
REFUSED = (401, 403)  # an exposed teach pendant without (401) or with a wrong (403) access token


class StepFailed(Exception):
    pass


def call(client: httpx.Client, method: str, path: str, ok: tuple = (), **kwargs) -> httpx.Response:
    """The answer; StepFailed for a refusal (an HTTP status >= 400 not in `ok`)."""
    response = client.request(method, path, **kwargs)
    if response.status_code >= 400 and response.status_code not in ok:
        hint = ""
        if response.status_code in REFUSED:
            hint = f" (give the pendant's access token with --token or ${TOKEN_ENV})"
        raise StepFailed(f"{method} {path} answered {response.status_code}: {message(response)}{hint}")
    return response


def message(response: httpx.Response) -> str:
    """The controller's message: its answers are plain text, sometimes JSON-quoted."""
    return response.text.strip().strip('"')


def text(client: httpx.Client, path: str) -> str:
    return message(call(client, "GET", path))


def where(client: httpx.Client, joint: bool) -> list[float]:
    if joint:
        return [float(a) for a in call(client, "GET", "/pose").json()["angles"]]
    point = call(client, "GET", "/position").json()["point"]
    return [point["x"], point["y"], point["z"]]


def arrived(here: list[float], target: list[float], joint: bool) -> bool:
    if joint:
        return max(abs(a - b) for a, b in zip(here, target)) <= ARRIVAL_TOL_DEG
    return sum((a - b) ** 2 for a, b in zip(here, target)) ** 0.5 <= ARRIVAL_TOL_M


def wait_for_motion(client: httpx.Client, target: list[float] | None, joint: bool, at_least_s: float) -> None:
    """Until the arm is IDLE (at `target`, when given) and `at_least_s` have passed."""
    started = time.monotonic()
    seen_running = False
    while True:
        status = text(client, "/status/motion")
        if status in FAILED_STATES:
            raise StepFailed(f"the controller reports {status}")
        if status == "RUNNING":
            seen_running = True
        elif time.monotonic() - started >= at_least_s:
            if target is None or arrived(where(client, joint), target, joint):
                return
            if seen_running or time.monotonic() - started > START_GRACE_S:
                raise StepFailed("the arm stopped before reaching its waypoint")
        time.sleep(POLL_S)


def run_motion(client: httpx.Client, operation: dict, targets: list, speed: float, motion: str) -> None:
    joint = operation.get("op") == "run_poses"
    body = [{"angles": angles} for angles in targets] if joint else targets
    query = {"speed": speed, "type": motion}
    call(client, "PUT", "/poses/run" if joint else "/positions/run", json=body, params=query)
    last = targets[-1] if joint else [targets[-1]["point"][axis] for axis in "xyz"]
    wait_for_motion(client, last, joint, 0.0)


def run_path(client: httpx.Client, operation: dict) -> None:
    """A recorded path: one blended run; stop-and-go, one linear move per waypoint, without /run/* (404)."""
    targets = operation["targets"]
    parameters = {"interpolationType": "BLEND", "velocity": operation["velocity"]}
    parameters["acceleration"] = operation["acceleration"]
    body = {"positions": targets, "motionParameters": parameters}
    if call(client, "PUT", "/run/linear/positions", ok=(404,), json=body).status_code != 404:
        wait_for_motion(client, [targets[-1]["point"][axis] for axis in "xyz"], False, 0.0)
        return
    print(PATH_FALLBACK, file=sys.stderr)
    query = {"speed": 100, "type": "LINEAR", "tcp_max_velocity": operation["velocity"]}
    for target in targets:
        position = {"point": target["point"], "rotation": target["rotation"]}
        call(client, "PUT", "/positions/run", json=[position], params=query)
        wait_for_motion(client, [target["point"][axis] for axis in "xyz"], False, 0.0)


def gripper(client: httpx.Client, action: str, timeout_ms: int) -> None:
    call(client, "PUT", f"/gripper/{action}", params={"timeout": timeout_ms})
    wait_for_motion(client, None, True, timeout_ms / 1000.0)


def input_is(client: httpx.Client, port: int, level: str) -> bool:
    return text(client, f"/signal/input/{port}") == level


def execute(client: httpx.Client, operation: dict, pallets: dict) -> None:
    kind = operation["op"]
    if kind in ("run_poses", "run_positions"):
        run_motion(client, operation, operation["targets"], operation["speed"], operation["motion"])
        for action in operation.get("actions", []):  # stop-and-set: the arm is at the waypoint now
            if action["target"] == "output":
                call(client, "PUT", f"/signal/output/{action['port']}/{action['value'].lower()}")
            else:
                gripper(client, action["value"], GRIPPER_TIMEOUT_MS)
    elif kind == "run_path":
        run_path(client, operation)
    elif kind == "gripper":
        gripper(client, operation["action"], operation["timeout_ms"])
    elif kind == "output":
        call(client, "PUT", f"/signal/output/{operation['port']}/{operation['level'].lower()}")
    elif kind == "wait_input":
        deadline = time.monotonic() + operation["timeout_ms"] / 1000.0
        while not input_is(client, operation["port"], operation["level"]):
            if time.monotonic() >= deadline:
                port, level, ms = operation["port"], operation["level"], operation["timeout_ms"]
                raise StepFailed(f"DI{port} did not go {level} within {ms} ms")
            time.sleep(POLL_S)
    elif kind == "wait":
        time.sleep(operation["ms"] / 1000.0)
    elif kind == "loop":
        passes = 0
        while operation["body"] and loop_continues(client, operation, passes):
            execute_all(client, operation["body"], pallets)
            passes += 1
    elif kind == "if":
        branch = "then" if input_is(client, operation["port"], operation["level"]) else "else"
        execute_all(client, operation[branch], pallets)
    elif kind == "pallet":
        execute_pallet(client, operation, pallets)
    else:
        raise ValueError(f"unknown operation {kind!r}")


def loop_continues(client: httpx.Client, operation: dict, passes: int) -> bool:
    if operation["mode"] == "times":
        return passes < operation["times"]
    at_level = input_is(client, operation["port"], operation["level"])
    return at_level if operation["mode"] == "while" else not at_level


def execute_pallet(client: httpx.Client, operation: dict, pallets: dict) -> None:
    """The next cell: above it (JOINT), straight down (LINEAR), the body, straight back up."""
    key = operation["steps"][0]
    count = pallets.get(key, 0)
    pallets[key] = count + 1
    cell = operation["cells"][count % len(operation["cells"])]
    above = {**cell, "point": {**cell["point"], "z": cell["point"]["z"] + operation["approach_m"]}}
    speed = operation["speed"]
    run_motion(client, operation, [above], speed, "JOINT")
    run_motion(client, operation, [cell], speed, "LINEAR")
    execute_all(client, operation["body"], pallets)
    run_motion(client, operation, [above], speed, "LINEAR")


def execute_all(client: httpx.Client, operations: list, pallets: dict) -> None:
    for operation in operations:
        try:
            execute(client, operation, pallets)
        except (StepFailed, httpx.HTTPError) as error:
            if getattr(error, "reported", False):
                raise
            numbers = operation["steps"]
            steps = str(numbers[0]) if len(numbers) == 1 else f"{numbers[0]}-{numbers[-1]}"
            print(f"Step {steps} ({operation['what']}) failed: {error}", file=sys.stderr)
            error.reported = True  # the innermost step is the one to name
            raise


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("url", nargs="?", default=os.environ.get("PULSE_URL", "__DEFAULT_URL__"))
    parser.add_argument("--loops", type=int, default=1, help="how many times to run (0: until Ctrl-C)")
    parser.add_argument(
        "--token",
        default=os.environ.get(TOKEN_ENV),
        help=f"access token of a teach pendant exposed on the network (default: ${TOKEN_ENV})",
    )
    args = parser.parse_args(argv)
    if args.loops < 0:
        parser.error("--loops must be >= 0")
    token = (args.token or "").strip()  # an empty variable means no token, as for a real controller
    headers = {TOKEN_HEADER: token} if token else {}
    with httpx.Client(base_url=args.url.rstrip("/"), headers=headers, timeout=10.0) as client:
        loop = 0
        pallets: dict = {}  # pallet step -> passes so far: each pass takes the next cell
        try:
            while args.loops == 0 or loop < args.loops:
                loop += 1
                try:
                    execute_all(client, OPERATIONS, pallets)
                except (StepFailed, httpx.HTTPError):
                    return 1
        except KeyboardInterrupt:
            try:
                call(client, "PUT", "/freeze")
            except (StepFailed, httpx.HTTPError) as error:
                print(f"Interrupted, but the arm could not be frozen: {error}", file=sys.stderr)
                return 1
            print("Interrupted: the arm is frozen", file=sys.stderr)
            return 1
    print(f"Done: {loop} loop(s) of {len(OPERATIONS)} operation(s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
'''
