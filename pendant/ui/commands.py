"""Robot commands from the page: each runs off the UI thread, and a refusal shows the controller's message."""

from __future__ import annotations

import logging
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor

import viser

from pendant.controller import Controller, ControllerError, MotionParams, Pose

log = logging.getLogger(__name__)

HOME_POSE_DEG = (0.0, -90.0, 0.0, -90.0, -90.0, 0.0)
HOME_SPEED_PERCENT = 20.0


class CommandRunner:
    """Sends commands to the controller on a worker thread so a slow controller never blocks the page."""

    def __init__(self, controller: Controller) -> None:
        self._controller = controller
        self._pool = ThreadPoolExecutor(max_workers=2, thread_name_prefix="pendant-command")

    def submit(
        self, label: str, action: Callable[[Controller], object], client: viser.ClientHandle | None
    ) -> Future[object]:
        def run() -> object:
            try:
                return action(self._controller)
            except ControllerError as error:
                log.warning("%s refused: %s", label, error.message)
                if client is not None:
                    client.add_notification(
                        title=f"{label} refused", body=error.message, color="red", auto_close_seconds=8.0
                    )
                raise

        return self._pool.submit(run)

    def shutdown(self) -> None:
        self._pool.shutdown(wait=False, cancel_futures=True)


def add_robot_commands(server: viser.ViserServer, runner: CommandRunner) -> dict[str, viser.GuiButtonHandle]:
    """Freeze (red, first), then Relax, Recover, Pack and Home."""
    buttons: dict[str, viser.GuiButtonHandle] = {}

    def bind(label: str, action: Callable[[Controller], object], **style: object) -> None:
        button = server.gui.add_button(label, **style)  # type: ignore[arg-type]

        @button.on_click
        def _(event: viser.GuiEvent) -> None:
            runner.submit(label, action, event.client)

        buttons[label] = button

    bind("Freeze", lambda c: c.freeze(), color="red", icon=viser.Icon.HAND_STOP)
    with server.gui.add_folder("Robot"):
        bind("Home", lambda c: c.set_pose(Pose(angles=list(HOME_POSE_DEG)), MotionParams(speed=HOME_SPEED_PERCENT)))
        bind("Relax", lambda c: c.relax())
        bind("Recover", lambda c: c.recover())
        bind("Pack", lambda c: c.pack())
    return buttons
