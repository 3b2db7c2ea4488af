"""The `pendant` command: flags -> Settings -> controller -> the web UI and the API server.

    pendant [--host 127.0.0.1] [--ui-port 8080] [--api-port 8081] [--model pulse75|pulse90] [--robot URL]
            [--connect-timeout 1] [--read-timeout 3] [--no-ui] [--time-scale K]
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

Bound to loopback (the default) nobody else can reach it. Bound to anything else (`--host 0.0.0.0`) it
has an access token (`--token`, or a fresh one printed at start-up with a ready-to-open URL carrying it):
taking control in the page needs it, and so does every command on the API (header X-Pendant-Token) but a stop.
Both ports answer only to IP addresses, loopback names, the bound name and `--allowed-host` names, and refuse
commands from web pages of other origins (pendant.access.origin).
"""

from __future__ import annotations

import signal
import sys
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

from fastapi import APIRouter
from starlette.types import ASGIApp

from pendant.access import is_loopback_host, new_token
from pendant.access.http_guard import AccessRules
from pendant.access.origin import OriginPolicy
from pendant.access.remote import RemoteControl
from pendant.banner import announce
from pendant.config import Settings
from pendant.controller.protocol import Controller
from pendant.controller.stops import StopBus
from pendant.eventlog import EventKind, EventLog
from pendant.flags import parse_settings
from pendant.monitoring import PendantMetrics, data_dir, open_event_store
from pendant.monitoring.state_watch import StateWatch

if TYPE_CHECKING:
    from pendant.cell.keeper import CellKeeper
    from pendant.planning.worker import PreflightWorker
    from pendant.telemetry import Telemetry
    from pendant.telemetry.recordings_api import RecordingDesk
    from pendant.ui.app import PendantUI


def with_access_token(settings: Settings) -> Settings:
    """An exposed pendant (not bound to loopback) always has a token: --token's, or a fresh random one."""
    if settings.token is None and not is_loopback_host(settings.host):
        return replace(settings, token=new_token())
    return settings


def make_controller(settings: Settings) -> Controller:
    """The embedded simulator on the wall clock (times --time-scale), or a client of the real controller."""
    if settings.robot_url is not None:
        from pendant.remote import RemoteController

        return RemoteController(
            settings.robot_url, connect_timeout=settings.connect_timeout, read_timeout=settings.read_timeout
        )
    from pendant.sim import MonotonicClock, ScaledClock, SimController

    # Real time is the wall clock itself; a scaled one also keeps planning out of simulated time.
    clock = MonotonicClock() if settings.time_scale == 1.0 else ScaledClock(settings.time_scale)
    return SimController(model=settings.model, clock=clock)


def remote_control_default(settings: Settings) -> bool:
    """API clients may move the arm from the start only where nobody else can be surprised: the simulator on
    loopback (scripts work out of the box), or no page at all (--no-ui: there is no operator to decide);
    `--remote-control on|off` says otherwise."""
    if settings.remote_control is not None:
        return settings.remote_control
    if settings.no_ui:
        return True
    return settings.robot_url is None and is_loopback_host(settings.host)


def access_rules(settings: Settings, events: EventLog | None = None) -> AccessRules:
    """The API port's guard for these settings: Host and Origin rules always, the token when there is one,
    and the Remote control switch (shared with the page)."""
    return AccessRules(
        token=settings.token,
        events=events,
        origins=OriginPolicy.for_binding(settings.host, settings.allowed_hosts),
        remote=RemoteControl(remote_control_default(settings)),
    )


def make_api_app(
    settings: Settings,
    controller: Controller,
    started_at: float,
    events: EventLog | None = None,
    access: AccessRules | None = None,
    metrics: PendantMetrics | None = None,
    stops: StopBus | None = None,
    preflights: PreflightWorker | None = None,
    recordings: RecordingDesk | None = None,
) -> ASGIApp:
    """The app on the API port: the simulator's PULSE API, or a transparent proxy to the real controller;
    both also answer GET /pendant/health, POST /pendant/plan, GET /metrics and (with a stored log)
    GET /pendant/events.
    `access`: its guard (default: `access_rules(settings, events)`); `preflights`: the process pre-flights
    run in (default: one of the app's own)."""
    from pendant.kinematics import ArmModel
    from pendant.monitoring import add_monitoring
    from pendant.planning.api import plan_router
    from pendant.remote import health_router

    access = access if access is not None else access_rules(settings, events)
    store = events  # GET /pendant/events: from disk, or from memory when the data folder cannot hold the log
    if settings.robot_url is not None:
        from pendant.remote import RemoteController, create_proxy_app

        assert isinstance(controller, RemoteController)
        proxy = create_proxy_app(
            settings.robot_url,
            settings=settings,
            controller=controller,
            started_at=started_at,
            access=access,
            metrics=metrics,
            store=store,
            stops=stops,
        )
        proxy.include_router(plan_router(controller, ArmModel.load(settings.model)))
        proxy.include_router(_preflight_router(settings, controller, preflights))
        if recordings is not None:
            from pendant.telemetry.recordings_api import recordings_router

            proxy.include_router(recordings_router(recordings))
        return proxy
    from pendant.api import create_app

    app = create_app(controller, access=access, stops=stops)
    app.include_router(health_router(settings, controller, started_at))
    app.include_router(
        plan_router(controller, getattr(controller, "arm", None) or ArmModel.load(settings.model))
    )
    app.include_router(_preflight_router(settings, controller, preflights))
    if recordings is not None:
        from pendant.telemetry.recordings_api import recordings_router

        app.include_router(recordings_router(recordings))
    if metrics is None:
        metrics = PendantMetrics(controller, mode="sim", model=settings.model, robot_url=None)
    add_monitoring(app, metrics, store)
    return app


def _preflight_router(
    settings: Settings, controller: Controller, preflights: PreflightWorker | None
) -> APIRouter:
    """POST /pendant/preflight: the program checked on a twin of this controller (nothing moves)."""
    from pendant.planning.router import preflight_router
    from pendant.program import programs_dir

    folder = Path(settings.programs_dir) if settings.programs_dir else programs_dir()
    return preflight_router(controller, settings.model, folder, preflights)


def start_ui(
    settings: Settings,
    controller: Controller,
    events: EventLog | None = None,
    access: AccessRules | None = None,
    metrics: PendantMetrics | None = None,
    stops: StopBus | None = None,
) -> PendantUI:
    """The pendant's page on its own port (viser serves it from its own thread), sharing the API's Host and
    Origin rules and Remote control switch."""
    access = access if access is not None else access_rules(settings, events)
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
        origins=access.origins,
        remote=access.remote,
        attempts=access.attempts,
        data_dir=str(resolve_data_dir(settings)),
        metrics=metrics,
        stops=stops,
    ).start()


def clean_up_after_a_crash(settings: Settings) -> list[Path]:
    """Orphaned temporary files of the programs and recordings folders go (said on stderr); returns the
    unfinished recordings (the pendant was killed), for repair_in_background once the event log is open."""
    from pendant.program import programs_dir
    from pendant.stale_files import remove_stale_temporaries
    from pendant.telemetry.recordings import recordings_dir
    from pendant.telemetry.repair import unfinished

    programs = Path(settings.programs_dir) if settings.programs_dir else programs_dir()
    recordings = recordings_dir(resolve_data_dir(settings))
    for path in remove_stale_temporaries([programs, recordings]):
        print(f"Removed a temporary file left by an earlier run: {path}", file=sys.stderr)
    return unfinished(recordings) if recordings.is_dir() else []


def repair_recordings(paths: list[Path], events: EventLog) -> None:
    """Finish (or move to recordings/damaged/) each unfinished recording in a thread of its own: the pendant
    serves meanwhile, whatever the files hold. Each one's line goes to the event log (which logs it too)."""
    from pendant.telemetry.repair import repair_in_background

    if paths:
        repair_in_background(paths, lambda note: events.record(EventKind.ERROR, "pendant", note))


def _keep_sim_cell(settings: Settings, controller: Controller, events: EventLog) -> CellKeeper | None:
    """The simulator's cell, tool and base: put back as they were, kept in the data folder from now on."""
    if settings.robot_url is not None:
        return None  # a real controller keeps its own
    from pendant.cell.keeper import keep_cell

    keeper, restored = keep_cell(controller, resolve_data_dir(settings), fresh=settings.fresh_cell)
    if restored is not None:
        print(restored.message, file=sys.stderr, flush=True)
        if restored.trouble:
            events.record(EventKind.ERROR, "pendant", restored.message)
    return keeper


def _headless_telemetry(settings: Settings, controller: Controller, events: EventLog) -> Telemetry:
    """With --no-ui, the recorder the API's recordings use (the page's has the same folder and drawing)."""
    from pendant.kinematics import ArmModel
    from pendant.telemetry import Telemetry, arm_drawing, recordings_dir

    arm = getattr(controller, "arm", None) or ArmModel.load(settings.model)
    telemetry = Telemetry(
        controller, recordings_folder=recordings_dir(resolve_data_dir(settings)), arm=arm_drawing(arm)
    )
    events.on_record(telemetry.log_event)
    return telemetry


def resolve_data_dir(settings: Settings) -> Path:
    return data_dir(settings.data_dir, settings.programs_dir)


def api_url(settings: Settings) -> str:
    return f"http://{settings.host}:{settings.api_port}"


def serve_api(settings: Settings, app: ASGIApp, on_quit: Callable[[str], None] | None = None) -> None:
    """Serve the API app until interrupted (blocks): uvicorn with the connection guards of
    pendant.api.serving (idle and slow connections closed, a cap that always leaves room for a stop);
    `on_quit` first when told to quit (SIGTERM, SIGINT, shutdown)."""
    from pendant.api.serving import serve

    serve(app, settings.host, settings.api_port, on_quit)


def _exit_on_sigterm(signum: int, frame: object) -> None:
    """uvicorn hands SIGTERM back once it has stopped serving, and by default it would end the process
    there: exit through main's `finally` instead, as Ctrl-C does (a recording is finished, the log closed)."""
    raise SystemExit(128 + signum)


def main(argv: Sequence[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else list(argv)
    if args[:1] == ["check"]:
        from pendant.readiness import check_main

        return check_main(args[1:])
    if args[:1] == ["run"]:  # `pendant run PROGRAM.json ...`: a saved program, no browser
        from pendant.kinematics import ArmModel
        from pendant.planning.live import ControllerPlanner
        from pendant.program.headless import main as run_program

        return run_program(args[1:], lambda model: ControllerPlanner(ArmModel.load(model)))
    if args[:1] in (["diff"], ["history"]):  # a program's changes and versions (docs/history.md)
        from pendant.program import history_cli

        return (history_cli.diff_main if args[0] == "diff" else history_cli.history_main)(args[1:])
    if args[:1] == ["record"]:  # `pendant record --robot URL --seconds N`: a recording, no page
        from pendant.remote.record_cli import main as record

        return record(args[1:])
    if args[:1] == ["preflight"]:  # `pendant preflight PROGRAM.json ...`: checked on the twin, nothing moves
        from pendant.planning.command import main as preflight_program

        return preflight_program(args[1:])
    settings = with_access_token(parse_settings(argv))
    started_at = time.monotonic()
    controller = make_controller(settings)
    # One log for the page and the API (who sent what), kept on disk; one set of metrics for both.
    unfinished = clean_up_after_a_crash(settings)
    store, storage_problem = open_event_store(resolve_data_dir(settings))
    if storage_problem is not None:
        print(storage_problem, file=sys.stderr, flush=True)
    events = EventLog(store=store, storage_problem=storage_problem)
    repair_recordings(unfinished, events)
    keeper = _keep_sim_cell(settings, controller, events)
    metrics = PendantMetrics(
        controller,
        mode="robot" if settings.robot_url else "sim",
        model=settings.model,
        robot_url=settings.robot_url,
    )
    metrics.watch(events)
    access = access_rules(settings, events)  # one switch and one set of rules for both ports
    stops = StopBus()  # the API's stops end the page's held jog
    from pendant.planning.worker import PreflightWorker
    from pendant.telemetry.headless import RecordingSampler
    from pendant.telemetry.recordings_api import RecordingDesk

    preflights = PreflightWorker()  # quitting ends a running pre-flight at once (its own process)
    desk = RecordingDesk(events=events)  # POST /pendant/recordings: the page's recorder, or one of its own
    api_app = make_api_app(
        settings, controller, started_at, events, access, metrics, stops, preflights, recordings=desk
    )
    ui = None if settings.no_ui else start_ui(settings, controller, events, access, metrics, stops)
    # Without the page's refresh loop, a thread of its own logs the arm's state changes.
    watch = StateWatch(controller, events, metrics).start() if ui is None else None
    desk.telemetry = ui.telemetry if ui is not None else _headless_telemetry(settings, controller, events)
    sampler = RecordingSampler(controller, desk.telemetry).start() if ui is None else None
    announce(settings)
    from pendant.api.quitting import freeze_on_quit

    on_main_thread = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGTERM, _exit_on_sigterm) if on_main_thread else None
    try:
        freeze = freeze_on_quit(controller.freeze, events)  # quitting stops the arm, and any pre-flight

        def on_quit(reason: str) -> None:
            freeze(reason)
            preflights.cancel()

        serve_api(settings, api_app, on_quit)
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)
        if ui is not None:
            ui.stop()
        if watch is not None:
            watch.stop()
        if keeper is not None:
            keeper.stop()  # the cell as it is now, for the next start
        if sampler is not None:
            sampler.stop()
            desk.telemetry.stop_recording()  # a recording still running is finished, readable
        preflights.close()
        if store is not None:
            store.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
