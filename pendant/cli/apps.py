"""What `pendant` serves, built from Settings: the controller (the simulator or a real arm's client), the
API port's app and its guard, the page. Bound to loopback nobody else can reach them; elsewhere they have an
access token (with_access_token)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

from fastapi import APIRouter
from starlette.types import ASGIApp

from pendant.access import is_loopback_host, new_token
from pendant.access.http_guard import AccessRules
from pendant.access.origin import OriginPolicy
from pendant.access.remote import RemoteControl
from pendant.config import Settings
from pendant.controller.protocol import Controller
from pendant.controller.stops import StopBus
from pendant.eventlog import EventLog
from pendant.monitoring import PendantMetrics, data_dir

if TYPE_CHECKING:
    from pendant.planning.worker import PreflightWorker
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
        environment_map=settings.environment_map,
    ).start()


def resolve_data_dir(settings: Settings) -> Path:
    """The event log's and recordings' folder: --data, else $PENDANT_DATA_DIR, else beside the programs."""
    return data_dir(settings.data_dir, settings.programs_dir)
