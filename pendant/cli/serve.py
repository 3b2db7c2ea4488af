"""`pendant` itself: the files an earlier run left put right, the event log and metrics opened, the API and
the page (and the Foxglove live view) started, the banner printed, then the API served until told to quit;
quitting stops the arm first, and finishes what must be finished (a recording, the kept cell, the log)."""

from __future__ import annotations

import signal
import sys
import threading
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from starlette.types import ASGIApp

from pendant.banner import announce
from pendant.cli import heap
from pendant.cli.apps import (
    access_rules,
    make_api_app,
    make_controller,
    resolve_data_dir,
    start_ui,
    with_access_token,
)
from pendant.config import Settings
from pendant.controller.protocol import Controller
from pendant.controller.stops import StopBus
from pendant.eventlog import EventKind, EventLog
from pendant.flags import parse_settings
from pendant.monitoring import PendantMetrics, open_event_store
from pendant.monitoring.state_watch import StateWatch

if TYPE_CHECKING:
    from pendant.cell.keeper import CellKeeper
    from pendant.telemetry import Telemetry
    from pendant.telemetry.live import LiveView


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


def _open_live_view(settings: Settings) -> LiveView | None:
    """--foxglove-port's server, listening; exits with the reason when it cannot (the port is taken)."""
    if settings.foxglove_port is None:
        return None
    from pendant.telemetry.live import LiveView

    try:
        return LiveView(settings.host, settings.foxglove_port)
    except RuntimeError as error:
        where = f"{settings.host}:{settings.foxglove_port}"
        raise SystemExit(f"pendant: cannot serve the Foxglove live view on {where}: {error}") from None


def serve(argv: Sequence[str] | None = None) -> int:
    """`pendant [flags]`: the page and the API until interrupted (Ctrl-C, SIGTERM); 0 once stopped."""
    settings = with_access_token(parse_settings(argv))
    live = _open_live_view(settings)  # first: a port it cannot have ends the start before anything runs
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
    if live is not None:  # before the sampler: with --no-ui it samples for the live view
        desk.telemetry.attach_live(live)
    sampler = RecordingSampler(controller, desk.telemetry).start() if ui is None else None
    announce(settings, foxglove_port=live.port if live is not None else None)
    from pendant.api.quitting import freeze_on_quit

    on_main_thread = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGTERM, _exit_on_sigterm) if on_main_thread else None
    heap.settle()  # no full garbage collection walks the start-up's objects again: nothing waits on one
    try:
        freeze = freeze_on_quit(controller.freeze, events)  # quitting stops the arm, and any pre-flight

        def on_quit(reason: str) -> None:
            freeze(reason)
            preflights.cancel()

        serve_api(settings, api_app, on_quit)
    finally:
        heap.unsettle()
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
        if live is not None:
            desk.telemetry.stop_live()
        preflights.close()
        if store is not None:
            store.close()
    return 0
