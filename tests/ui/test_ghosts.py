"""One ghost at a time in a browser's 3D view (issue 33), headless: showing the target's ghost hides the
waypoint preview and the replay, and the other way round; a redraw never brings a hidden one back, only the
operator's next ask; the legend names the one shown. With "Every ghost" on, each stays and the legend names
them all; switched off, only the newest stays. (The replay's turn: tests/ui/test_replay_panel.py.)"""

from __future__ import annotations

import numpy as np

from pendant.sim import FakeClock, SimController
from pendant.ui.app import PendantUI
from pendant.ui.page.session import ClientSession
from tests.support.doubles import OPERATOR, FakeBrowser, fire
from tests.support.programs import POSE_A_DEG, POSE_B_DEG, teach
from tests.support.waiting import SAFETY_NET_S

WAIT_S = SAFETY_NET_S


def shown(ui: ClientSession) -> list[str]:
    """The ghosts drawn in this browser's view."""
    replay = ui.dashboard.replay.ghost
    preview = ui.program.waypoints.ghost
    drawn = {
        "target": ui.target_panel.ghost_shown is not None,
        "waypoint": preview is not None and bool(preview.show_visual),
        "replay": replay is not None and replay.q is not None,
    }
    return [kind for kind, on in drawn.items() if on]


def legends(ui: ClientSession) -> list[str]:
    """The legend's lines, as the page shows them over the view (ghost_legend.js), the newest first."""
    assert ui.ghosts.legend is not None
    lines = [part.split('"', 1)[0] for part in ui.ghosts.legend.content.split('data-ghost-legend="')[1:]]
    return [line for line in lines if line]


def legend(ui: ClientSession) -> str:
    return "\n".join(legends(ui))


def record(ui: ClientSession, browser: FakeBrowser) -> None:
    fire(ui.program.record, browser)
    assert ui.program.pending is not None
    ui.program.pending.result(timeout=WAIT_S)


def test_the_target_and_the_waypoint_preview_take_turns_and_the_legend_says_which(
    ui: ClientSession, pendant_ui: PendantUI, sim: SimController, clock: FakeClock
) -> None:
    operator = FakeBrowser(OPERATOR)
    for pose in (POSE_A_DEG, POSE_B_DEG):
        teach(sim, clock, pose, "ignored")
        record(ui, operator)
    target = ui.target_panel
    assert target.set_joint_target(np.radians(POSE_A_DEG)).ok
    assert shown(ui) == ["target"] and legend(ui) == "Ghost: target"

    fire(ui.program.select, operator, "1. Move J to P1 @ 20%")  # the operator looks at a step's waypoint
    assert shown(ui) == ["waypoint"] and legend(ui) == "Ghost: waypoint"
    target.recheck()  # the cell changed: the target is checked again, its ghost stays hidden
    pendant_ui.refresh(with_io=True)
    assert shown(ui) == ["waypoint"]

    assert target.set_joint_target(np.radians(POSE_B_DEG)).ok  # the operator sets a target again
    assert shown(ui) == ["target"] and legend(ui) == "Ghost: target"
    ui.program.redraw_program()  # another browser's edit redraws the tab: the preview stays hidden
    assert shown(ui) == ["target"]

    target.reset_to_current()  # no target: no ghost, no legend
    assert shown(ui) == [] and legend(ui) == ""


def test_every_ghost_on_keeps_them_all_and_off_keeps_the_newest(
    ui: ClientSession, sim: SimController, clock: FakeClock
) -> None:
    operator = FakeBrowser(OPERATOR)
    for pose in (POSE_A_DEG, POSE_B_DEG):
        teach(sim, clock, pose, "ignored")
        record(ui, operator)
    assert ui.ghosts.switch is not None
    fire(ui.ghosts.switch, operator, True)
    target = ui.target_panel
    assert target.set_joint_target(np.radians(POSE_A_DEG)).ok
    fire(ui.program.select, operator, "1. Move J to P1 @ 20%")
    assert shown(ui) == ["target", "waypoint"]
    assert legends(ui) == ["Ghost: waypoint", "Ghost: target"]
    assert target.set_joint_target(np.radians(POSE_B_DEG)).ok  # asked again: the newest, first in the legend
    assert shown(ui) == ["target", "waypoint"]
    assert legends(ui) == ["Ghost: target", "Ghost: waypoint"]

    fire(ui.ghosts.switch, operator, False)  # off: the newest stays
    assert shown(ui) == ["target"] and legends(ui) == ["Ghost: target"]
    fire(ui.program.select, operator, "2. Move J to P2 @ 20%")  # one at a time again
    assert shown(ui) == ["waypoint"] and legends(ui) == ["Ghost: waypoint"]
