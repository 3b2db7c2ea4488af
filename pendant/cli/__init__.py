"""The `pendant` command: flags -> Settings -> controller -> the web UI and the API server.

    pendant [--host 127.0.0.1] [--ui-port 8080] [--api-port 8081] [--model pulse75|pulse90] [--robot URL]
            [--connect-timeout 1] [--read-timeout 3] [--no-ui] [--time-scale K] [--foxglove-port PORT]
    pendant check URL [--timeout S]
    pendant run PROGRAM.json [--robot URL] [--loops N]
    pendant diff A.json B.json
    pendant history PROGRAM [--programs DIR]
    pendant preflight PROGRAM.json [--robot URL] [--cell CELL.json] [--input N=HIGH ...] [--json]

serves the pendant's page and the PULSE REST API (the simulator's, or a proxy to the real arm at --robot);
with --no-ui, the API alone on the controller's own port; the simulator's clock runs K times the wall
clock with --time-scale K. `pendant check URL` waits until a PULSE API answers at URL (for CI scripts).
`pendant run PROGRAM.json` runs a saved program without a browser (pendant.program.headless).
`pendant diff` and `pendant history` show a program's changes and versions (pendant.program.history_cli).

The package: subcommands.py names the subcommands (each in the package that does its work), apps.py builds
the controller, the API app and the page from Settings, serve.py runs them until told to quit.

Bound to loopback (the default) nobody else can reach it. Bound to anything else (`--host 0.0.0.0`) it
has an access token (`--token`, or a fresh one printed at start-up with a ready-to-open URL carrying it):
taking control in the page needs it, and so does every command on the API (header X-Pendant-Token) but a stop.
Both ports answer only to IP addresses, loopback names, the bound name and `--allowed-host` names, and refuse
commands from web pages of other origins (pendant.access.origin).
"""

from __future__ import annotations

import sys
from collections.abc import Sequence

from pendant.banner import announce
from pendant.cli.apps import (
    access_rules,
    make_api_app,
    make_controller,
    remote_control_default,
    resolve_data_dir,
    start_ui,
    with_access_token,
)
from pendant.cli.serve import serve
from pendant.cli.subcommands import SUBCOMMANDS
from pendant.flags import parse_settings

__all__ = [
    "access_rules",
    "announce",
    "main",
    "make_api_app",
    "make_controller",
    "parse_settings",
    "remote_control_default",
    "resolve_data_dir",
    "start_ui",
    "with_access_token",
]


def main(argv: Sequence[str] | None = None) -> int:
    """`pendant SUBCOMMAND ...` runs that subcommand; anything else serves the page and the API."""
    args = sys.argv[1:] if argv is None else list(argv)
    subcommand = SUBCOMMANDS.get(args[0]) if args else None
    if subcommand is not None:
        return subcommand(args[1:])
    return serve(argv)
