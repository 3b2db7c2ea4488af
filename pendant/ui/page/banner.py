"""The banner under Freeze: the one place a browser is told that something is wrong, why, since when, and
which button gets it going again (see recovery.py for what it says). Every tab reads it; none invents its
own error line.

Its buttons are slots: their words and actions follow the shared view. A click acts on what the button
showed when it was pressed, and goes through the page's command runner (so the event log records the
operator's choice, and a viewer is refused as for any command)."""

from __future__ import annotations

import asyncio
import html
import logging
import time
from collections.abc import Callable, Coroutine
from pathlib import Path
from typing import Any

import viser

from pendant.program import ProgramWorkspace
from pendant.sim import SimController
from pendant.ui.kit.cell_state import CellState
from pendant.ui.kit.commands import CommandRunner, client_id, notify_refusal
from pendant.ui.kit.gui_target import GuiTarget
from pendant.ui.page.recovery import Action, BannerView, Recovery
from pendant.ui.program.refusals import USER_ERRORS
from pendant.ui.scene.refused import RefusedPose

log = logging.getLogger(__name__)

BANNER_ORDER = -999.0  # right under Freeze (-1000), above the status
MAX_BUTTONS = 3
_COLOURS: dict[Action, str] = {Action.RECOVER: "red", Action.STOP_PROGRAM: "gray", Action.SIM_RESET: "orange"}


def render_banner(view: BannerView) -> str:
    since = time.strftime("%H:%M:%S", time.localtime(view.since))
    detail = f'<div id="banner-detail">{html.escape(view.detail)}</div>' if view.detail else ""
    return (
        f'<div id="recovery-banner" style="background:{view.colour};color:white;border-radius:6px;'
        'padding:8px 10px;margin:4px 0">'
        f'<div><b id="banner-title" style="font-size:1.15em">{html.escape(view.title)}</b>'
        f' <span id="banner-since" style="opacity:0.85;font-size:0.85em">since {since}</span></div>'
        f'{detail}<div id="banner-next" style="font-weight:bold;margin-top:4px">'
        f"{html.escape(view.next_step)}</div></div>"
    )


class Banner:
    """One browser's banner: hidden while all is well."""

    def __init__(
        self,
        target: GuiTarget,
        recovery: Recovery,
        runner: CommandRunner,
        programs: ProgramWorkspace,
        *,
        sim: SimController | None = None,
        urdf_path: Path | None = None,
        cell_state: Callable[[], CellState] = CellState,
    ) -> None:
        self._recovery = recovery
        self._runner = runner
        self._programs = programs
        self._sim = sim
        self._cell_state = cell_state
        gui = target.gui
        self._html = gui.add_html("", order=BANNER_ORDER, visible=False)
        self.buttons: list[viser.GuiButtonHandle] = []
        for k in range(MAX_BUTTONS):
            button = gui.add_button("", order=BANNER_ORDER + 0.1 * (k + 1), visible=False)
            button.on_click(self._on_click(k))
            self.buttons.append(button)
        self.refused = RefusedPose(target, urdf_path, "/banner_refused")
        self.view: BannerView | None = None  # what this browser shows now
        self._content = ""

    def show(self) -> None:
        view = self._recovery.view
        content = render_banner(view) if view is not None else ""
        if content != self._content:
            self._html.content = content
            self._html.visible = view is not None
            self._content = content
        actions = view.actions if view is not None else ()
        for k, button in enumerate(self.buttons):
            shown = k < len(actions)
            if shown and view is not None:
                label = view.labels[k]
                if button.label != label:
                    button.label = label
                    button.color = _COLOURS.get(actions[k], "green" if k == 0 else None)
            if button.visible != shown:
                button.visible = shown
        self.view = view
        q = self._recovery.refused_q
        if q is None:
            self.refused.hide()
        else:
            self.refused.show(q, self._cell_state().obstacles, self._recovery.refused_obstacles)

    def _on_click(self, index: int) -> Callable[[viser.GuiEvent], Coroutine[Any, Any, None]]:
        """Read on viser's event loop, with the button as it showed when pressed: Stop program goes the way
        Freeze goes (the stop thread, kit/stop_path.py), the rest to a worker thread; neither waits for
        viser's callback pool, which other browsers' clicks can fill."""

        async def clicked(event: viser.GuiEvent) -> None:
            view = self.view
            if view is None or index >= len(view.actions):
                return
            action, label, client = view.actions[index], view.labels[index], event.client
            if action is Action.STOP_PROGRAM:
                handed = self._runner.press(lambda: self.act(action, label, client))
                done = asyncio.wrap_future(handed) if handed is not None else None
            else:
                done = asyncio.get_running_loop().run_in_executor(None, self.act, action, label, client)
            try:  # this click's own task waits; the loop goes on
                if done is not None:
                    await done
            except Exception:
                log.exception("the banner's %s failed", label)

        return clicked

    def act(self, action: Action, label: str, client: viser.ClientHandle | None) -> None:
        """Do what a banner button says (tests call it directly with client None)."""
        runner, programs = self._runner, self._programs
        said = f"{label} (banner)"
        match action:
            case Action.RECOVER:
                runner.submit(said, lambda c: c.recover(), client)
            case Action.LEAVE_FREE_DRIVE:
                runner.submit(said, lambda c: c.zg_off(), client)
            case Action.FINISH_UNTWISTING:
                runner.submit(said, lambda c: c.finish_untwisting(), client)
            case Action.SIM_RESET:
                sim = self._sim
                if sim is not None:
                    runner.submit(said, lambda _: sim.reset(keep_cell=True), client)
            case Action.STOP_PROGRAM:  # stopping is never refused, and never waits behind a command
                runner.submit(
                    said, lambda _: programs.stop(), client, urgent=True, ending=programs.request_stop
                )
            case Action.RETRY | Action.SKIP | Action.RESUME:
                if runner.refusal(client, said) is not None:
                    return
                try:
                    if action is Action.SKIP:
                        programs.start_skip(supervisor=client_id(client))
                    else:
                        programs.start_resume(supervisor=client_id(client))
                except USER_ERRORS as error:
                    notify_refusal(client, f"{label} refused", str(error))
                else:
                    runner.record(said, client)
