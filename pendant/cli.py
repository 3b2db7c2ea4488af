"""The `pendant` command: flags -> Settings -> controller -> the web UI and the API server.

    pendant [--host 127.0.0.1] [--ui-port 8080] [--api-port 8081] [--model pulse75|pulse90] [--robot URL]
            [--connect-timeout 1] [--read-timeout 3]

serves the pendant's page and the PULSE REST API (the simulator's, or a proxy to the real arm at --robot);
with --no-ui, the API alone on the controller's own port.

    pendant run PROGRAM.json [--robot URL] [--loops N]

runs a saved program without a browser (pendant.program.headless).

Bound to loopback (the default) nobody else can reach it. Bound to anything else (`--host 0.0.0.0`) it
has an access token (`--token`, or a fresh one printed at start-up with a ready-to-open URL carrying it):
taking control in the page needs it, and so does every PUT/POST on the API (header X-Pendant-Token).
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from collections.abc import Sequence
from dataclasses import replace
from typing import TYPE_CHECKING

from starlette.types import ASGIApp

from pendant import __version__
from pendant.access import TOKEN_HEADER, is_loopback_host, new_token, ui_url
from pendant.config import Settings
from pendant.controller.protocol import Controller
from pendant.eventlog import EventLog
from pendant.paths import MODEL_NAMES

if TYPE_CHECKING:
    from pendant.ui.app import PendantUI

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
        "--token",
        help=f"access token to take control in the page and for API commands ({TOKEN_HEADER} header); "
        "generated when --host is not a loopback address",
    )
    parser.add_argument(
        "--programs",
        metavar="DIR",
        help="folder of taught programs (default: $PENDANT_PROGRAMS_DIR, else ./programs)",
    )
    parser.add_argument("--no-ui", action="store_true", help="serve the PULSE REST API only")
    args = parser.parse_args(argv)
    for port in (args.api_port, args.ui_port):
        if not 0 <= port <= 65535:
            parser.error(f"port {port} is out of range 0-65535")
    return Settings(
        host=args.host,
        ui_port=args.ui_port,
        api_port=args.api_port,
        model=args.model,
        robot_url=args.robot,
        no_ui=args.no_ui,
        token=args.token,
        programs_dir=args.programs,
        connect_timeout=args.connect_timeout,
        read_timeout=args.read_timeout,
    )


def with_access_token(settings: Settings) -> Settings:
    """An exposed pendant (not bound to loopback) always has a token: --token's, or a fresh random one."""
    if settings.token is None and not is_loopback_host(settings.host):
        return replace(settings, token=new_token())
    return settings


def make_controller(settings: Settings) -> Controller:
    """The embedded simulator on the real clock, or a client of the real controller at `--robot`."""
    if settings.robot_url is not None:
        from pendant.remote import RemoteController

        return RemoteController(
            settings.robot_url, connect_timeout=settings.connect_timeout, read_timeout=settings.read_timeout
        )
    from pendant.sim import MonotonicClock, SimController

    return SimController(model=settings.model, clock=MonotonicClock())


def make_api_app(
    settings: Settings, controller: Controller, started_at: float, events: EventLog | None = None
) -> ASGIApp:
    """The app on the API port: the simulator's PULSE API, or a transparent proxy to the real controller;
    both also answer GET /pendant/health. With a token, commands need it; `events` logs every command."""
    from pendant.remote import health_router

    if settings.robot_url is not None:
        from pendant.access.http_guard import proxy_request_hook
        from pendant.remote import RemoteController, create_proxy_app

        assert isinstance(controller, RemoteController)
        return create_proxy_app(
            settings.robot_url,
            settings=settings,
            controller=controller,
            started_at=started_at,
            on_request=proxy_request_hook(settings.token, events),
        )
    from pendant.api import create_app

    app = create_app(controller, token=settings.token, events=events)
    app.include_router(health_router(settings, controller, started_at))
    return app


def start_ui(settings: Settings, controller: Controller, events: EventLog | None = None) -> PendantUI:
    """The pendant's page on its own port (viser serves it from its own thread)."""
    from pendant.kinematics import ArmModel
    from pendant.ui.app import PendantUI

    source = f"robot {settings.robot_url}" if settings.robot_url else "simulator"
    return PendantUI(
        controller,
        ArmModel.load(settings.model),
        host=settings.host,
        port=settings.ui_port,
        mode_line=f"{source} · {settings.model}",
        token=settings.token,
        events=events,
        programs_dir=settings.programs_dir,
    ).start()


def api_url(settings: Settings) -> str:
    return f"http://{settings.host}:{settings.api_port}"


def announce(settings: Settings) -> None:
    """Print where things are served, first thing, so a user (or a test) knows where to go."""
    if not settings.no_ui:
        print(f"PULSE pendant: http://{settings.host}:{settings.ui_port}", flush=True)
    source = settings.robot_url or f"simulated {settings.model}"
    print(f"PULSE REST API ({source}): {api_url(settings)}  (docs: {api_url(settings)}/docs)", flush=True)
    if settings.token is not None:
        print(f"Access token: {settings.token}", flush=True)
        if not settings.no_ui:
            print("Open the pendant (and take control) with this URL:", flush=True)
            print(f"    {ui_url(settings.host, settings.ui_port, settings.token)}", flush=True)
        print(f"API commands (PUT/POST) need the header  {TOKEN_HEADER}: {settings.token}", flush=True)


def serve_api(settings: Settings, app: ASGIApp) -> None:
    """Serve the API app with uvicorn until interrupted (blocks; uvloop and httptools when installed)."""
    import uvicorn

    uvicorn.run(
        app,
        host=settings.host,
        port=settings.api_port,
        access_log=False,  # a log line per request would cost more than the request itself
        log_level="warning",
    )


def main(argv: Sequence[str] | None = None) -> int:
    args = list(sys.argv[1:] if argv is None else argv)
    if args[:1] == ["run"]:  # `pendant run PROGRAM.json ...`: a saved program, no browser
        from pendant.program.headless import main as run_program

        return run_program(args[1:])
    settings = with_access_token(parse_settings(args))
    started_at = time.monotonic()
    controller = make_controller(settings)
    events = EventLog()  # one log for the page and the API: who sent what
    api_app = make_api_app(settings, controller, started_at, events)
    ui = None if settings.no_ui else start_ui(settings, controller, events)
    announce(settings)
    try:
        serve_api(settings, api_app)
    finally:
        if ui is not None:
            ui.stop()
    return 0


if __name__ == "__main__":
    sys.exit(main())
