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


def add_freeze_button(server: viser.ViserServer, runner: CommandRunner) -> viser.GuiButtonHandle:
    """The red Freeze button, above everything else so it is always in reach."""
    button = server.gui.add_button("Freeze", color="red", icon=viser.Icon.HAND_STOP, order=-1000.0)
    button.on_click(lambda event: runner.submit("Freeze", lambda c: c.freeze(), event.client))
    return button


def add_robot_commands(server: viser.ViserServer, runner: CommandRunner) -> dict[str, viser.GuiButtonHandle]:
    """Home, Relax, Recover and Pack."""
    actions: dict[str, Callable[[Controller], object]] = {
        "Home": lambda c: c.set_pose(Pose(angles=list(HOME_POSE_DEG)), MotionParams(speed=HOME_SPEED_PERCENT)),
        "Relax": lambda c: c.relax(),
        "Recover": lambda c: c.recover(),
        "Pack": lambda c: c.pack(),
    }
    buttons: dict[str, viser.GuiButtonHandle] = {}
    for label, action in actions.items():
        button = server.gui.add_button(label)
        button.on_click(lambda event, label=label, action=action: runner.submit(label, action, event.client))
        buttons[label] = button
    return buttons
