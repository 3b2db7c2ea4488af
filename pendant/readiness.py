"""`pendant check URL [--timeout S]`: wait until a PULSE API answers at URL (CI scripts, service containers).

"Answers" means the controller's own reply to GET /status/motion: a motion status (200), or its 500 / 503
error (a controller in a fault is up, and says so). A proxy's 502 or anything else is "not yet".
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from collections.abc import Sequence

import httpx

from pendant.controller.errors import MSG_EMERGENCY, MSG_NOT_RESPONDING
from pendant.controller.types import MotionStatus

DEFAULT_TIMEOUT_S = 30.0
POLL_S = 0.05
PROBE_TIMEOUT_S = 1.0
PROBE_PATH = "/status/motion"
_MOTION_STATUSES = {status.value for status in MotionStatus}
_ERROR_ANSWERS = {500: MSG_NOT_RESPONDING, 503: MSG_EMERGENCY}
# A misbehaving server's body is quoted in the message only this far.
MAX_QUOTED_CHARS = 200


def pulse_answer(response: httpx.Response) -> str | None:
    """The controller's answer (a motion status or its error message), or None if this is not a PULSE API."""
    try:
        text = json.loads(response.text)
    except ValueError:
        return None
    if response.status_code == 200 and text in _MOTION_STATUSES:
        return str(text)
    if _ERROR_ANSWERS.get(response.status_code) == text:
        return str(text)
    return None


def wait_for_pulse_api(url: str, timeout_s: float) -> tuple[bool, str]:
    """(True, its answer) once a PULSE API answers at `url`; (False, the last thing seen) on timeout."""
    probe = url.rstrip("/") + PROBE_PATH
    deadline = time.monotonic() + timeout_s
    last = "nothing tried"
    # What a server that answered said, kept when a later probe fails: "it is not a PULSE API" is the news,
    # not the one probe that timed out after it.
    answered = ""
    with httpx.Client(timeout=PROBE_TIMEOUT_S) as client:
        while True:
            try:
                response = client.get(probe)
                answer = pulse_answer(response)
                if answer is not None:
                    return True, answer
                last = answered = (
                    f"HTTP {response.status_code} {response.text[:MAX_QUOTED_CHARS]!r}, not a PULSE answer"
                )
            except httpx.HTTPError as error:
                last = f"{type(error).__name__}: {error}"[:MAX_QUOTED_CHARS]
            if time.monotonic() + POLL_S >= deadline:
                return False, last if last == answered or not answered else f"{last}; before that {answered}"
            time.sleep(POLL_S)  # a real server starting up, on the wall clock


def _timeout(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number of seconds") from None
    if not 0 < value < 86400:
        raise argparse.ArgumentTypeError(f"{text!r} must be between 0 and 86400 seconds")
    return value


def check_main(argv: Sequence[str]) -> int:
    parser = argparse.ArgumentParser(
        prog="pendant check", description="Exit 0 once a PULSE REST API answers at URL; 1 on timeout."
    )
    parser.add_argument("url", metavar="URL", help="e.g. http://127.0.0.1:8081")
    parser.add_argument(
        "--timeout",
        type=_timeout,
        default=DEFAULT_TIMEOUT_S,
        metavar="S",
        help="seconds to wait (default %(default)g)",
    )
    args = parser.parse_args(argv)
    if not args.url.startswith(("http://", "https://")):
        parser.error(f"URL must start with http:// or https:// (got {args.url!r})")
    ok, what = wait_for_pulse_api(args.url, args.timeout)
    if ok:
        print(f"PULSE API at {args.url} answers: {what}", flush=True)
        return 0
    print(
        f"pendant check: no PULSE API answered at {args.url} within {args.timeout:g} s ({what})",
        file=sys.stderr,
    )
    return 1
