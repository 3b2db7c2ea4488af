"""The `pendant` command: flags -> Settings -> controller -> the API server (and, later, the UI).

    pendant --no-ui [--host 127.0.0.1] [--api-port 8081] [--model pulse75|pulse90]

serves the simulator's PULSE REST API alone, on the controller's own port.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from starlette.types import ASGIApp

from pendant import __version__
from pendant.config import Settings
from pendant.controller.protocol import Controller
from pendant.paths import MODEL_NAMES

_DEFAULTS = Settings()


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
    parser.add_argument("--token", help="access token for the pendant's web UI")
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
    )


def make_controller(settings: Settings) -> Controller:
    """The embedded simulator on the real clock, or a client of the real controller at `--robot`."""
    if settings.robot_url is not None:
        from pendant.remote import RemoteController

        return RemoteController(settings.robot_url)
    from pendant.sim import MonotonicClock, SimController

    return SimController(model=settings.model, clock=MonotonicClock())


def make_api_app(settings: Settings, controller: Controller) -> ASGIApp:
    """The app on the API port: the simulator's PULSE API, or a transparent proxy to the real controller."""
    if settings.robot_url is not None:
        from pendant.remote import create_proxy_app

        return create_proxy_app(settings.robot_url, settings=settings)
    from pendant.api import create_app

    return create_app(controller)


def api_url(settings: Settings) -> str:
    return f"http://{settings.host}:{settings.api_port}"


def announce(settings: Settings) -> None:
    """Print where things are served, first thing, so a user (or a test) knows where to go."""
    source = settings.robot_url or f"simulated {settings.model}"
    print(f"PULSE REST API ({source}): {api_url(settings)}  (docs: {api_url(settings)}/docs)", flush=True)


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
    settings = parse_settings(argv)
    controller = make_controller(settings)
    api_app = make_api_app(settings, controller)
    announce(settings)
    serve_api(settings, api_app)
    return 0


if __name__ == "__main__":
    sys.exit(main())
