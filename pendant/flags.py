"""The `pendant` command's flags, parsed and checked into Settings (argparse exits with a usage message on a
bad one)."""

from __future__ import annotations

import argparse
import math
from collections.abc import Sequence

from pendant import __version__
from pendant.access import TOKEN_HEADER
from pendant.access.token import token_problem
from pendant.config import ENVIRONMENT_MAPS, Settings
from pendant.paths import MODEL_NAMES

_DEFAULTS = Settings()


def _seconds(text: str) -> float:
    """A timeout flag: a finite number of seconds above zero (zero or inf would mean "wait forever")."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number of seconds") from None
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"{text!r} must be a number of seconds above 0")
    return value


def parse_settings(argv: Sequence[str] | None = None) -> Settings:
    """The command line as Settings (argparse exits with a usage message on bad flags)."""
    parser = argparse.ArgumentParser(
        prog="pendant",
        description="PULSE teach pendant: a browser UI and the PULSE REST API, simulated or of a real arm.",
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    parser.add_argument("--host", default=_DEFAULTS.host, help="address to serve on (default %(default)s)")
    parser.add_argument(
        "--api-port", type=int, default=_DEFAULTS.api_port, help="PULSE REST API port (default %(default)s)"
    )
    parser.add_argument(
        "--ui-port", type=int, default=_DEFAULTS.ui_port, help="web UI port (default %(default)s)"
    )
    parser.add_argument(
        "--model", choices=MODEL_NAMES, default=_DEFAULTS.model, help="simulated arm (default %(default)s)"
    )
    parser.add_argument("--robot", metavar="URL", help="a real controller, e.g. http://192.168.0.10:8081")
    parser.add_argument(
        "--connect-timeout",
        type=_seconds,
        default=_DEFAULTS.connect_timeout,
        metavar="S",
        help="with --robot: seconds to wait for a connection to the controller (default %(default)g)",
    )
    parser.add_argument(
        "--read-timeout",
        type=_seconds,
        default=_DEFAULTS.read_timeout,
        metavar="S",
        help="with --robot: seconds to wait for the controller's answer (default %(default)g)",
    )
    parser.add_argument(
        "--command-timeout",
        type=_seconds,
        default=_DEFAULTS.command_timeout,
        metavar="S",
        help="with --robot: seconds a command through the API waits for the controller (default %(default)g)",
    )
    parser.add_argument(
        "--allowed-host",
        action="append",
        default=[],
        metavar="NAME",
        help="a host name the pendant answers to besides IP addresses and localhost (repeatable; "
        "'.example.com' allows its subdomains); other names are refused (DNS rebinding)",
    )
    parser.add_argument(
        "--remote-control",
        choices=("on", "off"),
        help="whether API clients may move the arm at start-up (the operator can switch it in the page); "
        "default on for the simulator on loopback and with --no-ui, off otherwise",
    )
    parser.add_argument(
        "--token",
        help=f"access token to take control in the page and for API commands ({TOKEN_HEADER} header); "
        "generated when --host is not a loopback address",
    )
    parser.add_argument(
        "--programs",
        metavar="DIR",
        help="folder of taught programs (default: $PENDANT_PROGRAMS_DIR, else ./programs)",
    )
    parser.add_argument(
        "--data",
        metavar="DIR",
        help="folder of the event log and recordings (default: $PENDANT_DATA_DIR, else pendant-data/ "
        "beside the programs folder)",
    )
    parser.add_argument(
        "--foxglove-port",
        type=int,
        metavar="PORT",
        help="serve a live view for Foxglove (Foxglove WebSocket protocol, the recordings' channels) on "
        "--host at PORT, e.g. 8765 (default: off)",
    )
    parser.add_argument("--no-ui", action="store_true", help="serve the PULSE REST API only")
    parser.add_argument(
        "--fresh-cell",
        action="store_true",
        help="simulator: start with no obstacle and the default tool and base instead of the cell kept in "
        "the data folder (the kept one is replaced at the first change)",
    )
    parser.add_argument(
        "--time-scale",
        type=float,
        default=_DEFAULTS.time_scale,
        metavar="K",
        help="the simulator's time runs K times the wall clock, e.g. 100 for tests (default %(default)g); "
        "the page's jog deadman and program wait steps keep wall-clock time",
    )
    parser.add_argument(
        "--environment-map",
        choices=ENVIRONMENT_MAPS,
        help="light the 3D view with one of viser's HDR environment maps (soft reflections), not lights "
        "alone; in software WebGL each page load then costs ~10 s of CPU and shows its view after ~7 s "
        "(default: lights)",
    )
    args = parser.parse_args(argv)
    for port in (args.api_port, args.ui_port, args.foxglove_port):
        if port is not None and not 0 <= port <= 65535:
            parser.error(f"port {port} is out of range 0-65535")
    if args.token is not None and (problem := token_problem(args.token)) is not None:
        parser.error(f"--token: {problem}")
    if args.time_scale != 1.0:
        _check_time_scale_flag(parser, args)
    return Settings(
        host=args.host,
        ui_port=args.ui_port,
        api_port=args.api_port,
        model=args.model,
        robot_url=args.robot,
        no_ui=args.no_ui,
        token=args.token,
        programs_dir=args.programs,
        data_dir=args.data,
        connect_timeout=args.connect_timeout,
        read_timeout=args.read_timeout,
        command_timeout=args.command_timeout,
        allowed_hosts=tuple(args.allowed_host),
        remote_control=None if args.remote_control is None else args.remote_control == "on",
        time_scale=args.time_scale,
        fresh_cell=args.fresh_cell,
        environment_map=args.environment_map,
        foxglove_port=args.foxglove_port,
    )


def _check_time_scale_flag(parser: argparse.ArgumentParser, args: argparse.Namespace) -> None:
    if args.robot is not None:
        # A real arm keeps its own time. With the page, motions follow the scale while the jog deadman and
        # a program's wait steps keep the wall clock: fine for tests of the page, not for judging its feel.
        parser.error("--time-scale is for the simulator alone: use it without --robot")
    from pendant.sim.clock import check_time_scale  # the simulator's package: imported only when needed

    try:
        check_time_scale(args.time_scale)
    except ValueError as error:
        parser.error(str(error))
