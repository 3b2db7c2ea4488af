"""The Program tab's "Run" folder: Run (or Resume a paused run), Run from the selected step, Step, Pause,
Stop, the loop count and the progress. A failed step is the banner's (page/banner.py): it says why, and its
Retry / Skip / Stop program buttons are the way on; here the run's line only points there."""

from __future__ import annotations

import viser

from pendant.program import RunState
from pendant.ui.kit.commands import client_id, notify_refusal
from pendant.ui.kit.stop_path import on_stop_press
from pendant.ui.kit.typed_field import FieldInvalid, NumberField
from pendant.ui.program.host import ProgramHost
from pendant.ui.program.refusals import USER_ERRORS


class RunSection:
    def __init__(self, host: ProgramHost) -> None:
        self._host = host
        self.locked = False  # a viewer's panel: Run and Step stay disabled whatever the run state
        gui = host.target.gui
        with gui.add_folder("Run"):
            self.loops = NumberField(
                gui, "Loops", 1, low=0, high=100_000, decimals=0, integer=True, hint="0: until Stop"
            )
            self.run = gui.add_button("Run", color="green", icon=viser.Icon.PLAYER_PLAY)
            self.run_from = gui.add_button(
                "Run from selected step",
                icon=viser.Icon.PLAYER_SKIP_FORWARD,
                hint="Start at the selected line",
            )
            self.step = gui.add_button("Step", icon=viser.Icon.PLAYER_TRACK_NEXT)
            self.pause = gui.add_button("Pause", icon=viser.Icon.PLAYER_PAUSE)
            self.stop = gui.add_button("Stop", color="red", icon=viser.Icon.PLAYER_STOP)
            self.progress = gui.add_progress_bar(0.0, animated=False)
            self.status = gui.add_markdown("Ready")
        commands = host.commands
        self.run.on_click(lambda e: self._start("Run", e.client))
        self.run_from.on_click(lambda e: self._start("Run from", e.client))
        self.step.on_click(lambda e: self._start("Step", e.client))

        # Stopping (and pausing) is always allowed (no gate) and goes the way Freeze goes: read on viser's
        # event loop, sent on the urgent thread (kit/stop_path.py).
        def pause(client: viser.ClientHandle | None) -> object:
            return commands.submit(
                "Pause", lambda _: host.shared.pause(), client, urgent=True, announce=False
            )

        def stop(client: viser.ClientHandle | None) -> object:
            shared = host.shared
            return commands.submit(
                "Stop", lambda _: shared.stop(), client, urgent=True, ending=shared.request_stop
            )

        self.pause.on_click(on_stop_press(commands, pause))
        self.stop.on_click(on_stop_press(commands, stop))

    def start(self, label: str, client: viser.ClientHandle | None) -> None:
        self._start(label, client)

    def _start(self, label: str, client: viser.ClientHandle | None) -> None:
        host = self._host
        if not host.allowed(client, label) or not host.run_allowed(label, client):
            return
        shared = host.shared
        state = shared.progress.state
        supervisor = client_id(client)  # this browser watches the run: it pauses if the page goes away
        try:
            loops = int(self.loops.value) if label != "Step" else 1
        except FieldInvalid as error:  # empty or letters: no run of a count the operator did not type
            notify_refusal(client, f"{label} refused", error.message)
            return
        try:
            if label == "Step":
                shared.start_step(supervisor)
            elif label == "Run" and state is RunState.PAUSED:
                shared.start_resume(supervisor)
            elif label == "Run from":
                shared.start_run(loops=loops, start_line=host.need_selection(), supervisor=supervisor)
            else:
                shared.start_run(loops=loops, supervisor=supervisor)
        except USER_ERRORS as error:
            notify_refusal(client, f"{label} refused", str(error))
        else:
            host.commands.record(f"Program: {label} {shared.program.name!r}", client)

    def redraw(self) -> None:
        progress = self._host.shared.progress
        self.progress.value = round(100.0 * progress.progress, 1)
        self.progress.color = {"failed": "red", "paused": "orange", "finished": "green"}.get(
            progress.state.value
        )
        text = progress.message
        if progress.state in (RunState.FAILED, RunState.STOPPED) and progress.failed_step is not None:
            text = f"**Stopped at step {progress.failed_step + 1}**: the banner above says why and what next"
        self.status.content = f"{text}\n\n{progress.notice}" if progress.notice else text
        self.run.label = "Resume" if progress.state is RunState.PAUSED else "Run"
        running = progress.state is RunState.RUNNING
        self.run.disabled = self.step.disabled = self.run_from.disabled = running or self.locked
        self.pause.disabled = not running
