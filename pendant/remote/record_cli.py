"""`pendant record --robot URL --seconds N`: a recording of an arm without a pendant page, the same MCAP and
CSV files as the Dashboard's, in the data folder's recordings/ (for scripts, CI runs, a quick capture)."""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Sequence

from pendant.controller import ControllerError
from pendant.kinematics import ArmModel
from pendant.monitoring import data_dir
from pendant.remote.client import RemoteController
from pendant.telemetry import Telemetry, arm_drawing, recordings_dir
from pendant.telemetry.headless import RecordingSampler
from pendant.telemetry.recordings import RecordingError, RecordingRefused, name_of

MAX_SECONDS = 2 * 3600.0  # the CSV's own limit (two hours at 10 Hz)
EXIT_REFUSED = 2


def _seconds(text: str) -> float:
    value = float(text)
    if not 0 < value <= MAX_SECONDS:
        raise argparse.ArgumentTypeError(f"must be more than 0 and at most {MAX_SECONDS:g}")
    return value


def main(argv: Sequence[str]) -> int:
    parser = argparse.ArgumentParser(prog="pendant record", description=__doc__.splitlines()[0])
    parser.add_argument("--robot", required=True, metavar="URL", help="the arm's PULSE API (or a pendant's)")
    parser.add_argument("--seconds", required=True, type=_seconds, metavar="N", help="how long to record")
    parser.add_argument("--name", help="the recording's name (default: its start time)")
    parser.add_argument("--model", default="pulse75", help="the arm drawn in 3D (default %(default)s)")
    parser.add_argument("--data", metavar="DIR", help="the data folder (default as for `pendant`)")
    args = parser.parse_args(argv)
    controller = RemoteController(args.robot)
    try:
        return _record(controller, args)
    finally:
        controller.close()


def _record(controller: RemoteController, args: argparse.Namespace) -> int:
    try:
        controller.get_robot_id()  # reachable, and a PULSE API
        telemetry = Telemetry(
            controller,
            recordings_folder=recordings_dir(data_dir(args.data)),
            arm=arm_drawing(ArmModel.load(args.model)),
        )
        name = telemetry.start_recording(args.name, exclusive=True)
    except ControllerError as error:
        print(f"pendant record: cannot read the arm at {args.robot}: {error.message}", file=sys.stderr)
        return EXIT_REFUSED
    except (RecordingRefused, RecordingError) as error:
        print(f"pendant record: {error}", file=sys.stderr)
        return EXIT_REFUSED
    sampler = RecordingSampler(controller, telemetry).start()
    try:
        time.sleep(args.seconds)
    except KeyboardInterrupt:
        pass  # Ctrl-C ends the recording early; its files are finished all the same
    finally:
        sampler.stop()
        samples = telemetry.stop_recording()
    files = next(r.files for r in telemetry.recordings() if name_of(r.stem) == name)
    print(f"Recording {name!r}: {samples} samples in " + ", ".join(str(path) for path in files))
    return 0
