"""The Program tab's shared workspace and the recovery banner, wired into the page: who authors a version,
the activity log, the command runner's gate while a program runs, and what a failed step would have hit."""

from __future__ import annotations

from collections.abc import Callable

from pendant.cell.geometry import CellModel
from pendant.controller import Controller
from pendant.eventlog import EventKind, EventLog
from pendant.kinematics import ArmModel
from pendant.planning.live import ControllerPlanner
from pendant.program import ProgramWorkspace
from pendant.sim import SimController
from pendant.ui.kit.commands import CommandRunner
from pendant.ui.kit.motion_gate import explain_in_error, program_block
from pendant.ui.kit.snapshot import Snapshot
from pendant.ui.page.activity import ActivityLog
from pendant.ui.page.recovery import Recovery
from pendant.ui.page.roles import ControlDesk


def open_program_workspace(
    controller: Controller,
    arm: ArmModel,
    programs_dir: str | None,
    *,
    events: EventLog,
    desk: ControlDesk,
    activity: ActivityLog,
    runner: CommandRunner,
    latest: Callable[[], Snapshot],
    cell: Callable[[], CellModel | None],
) -> tuple[ProgramWorkspace, Recovery]:
    """The workspace every browser's Program tab shows, and the banner's view shared by every browser."""
    programs = ProgramWorkspace.for_controller(controller, programs_dir, ControllerPlanner(arm))
    # Each version's author: the operator's browser (only the operator may save).
    programs.versions.who = lambda: desk.name(desk.operator)
    programs.on_change(lambda change: activity.program_changed(programs, change))
    runner.motion_block = program_block(programs)
    runner.explain = explain_in_error(lambda: latest().motion_status)
    recovery = Recovery(
        events,
        arm,
        simulator=isinstance(controller, SimController),
        cell=cell,
        current_q=lambda: latest().q,
    )
    programs.runner.explain_failure = recovery.explain_step_failure
    if programs.store.restore_problem is not None:
        events.record(EventKind.ERROR, "program", programs.store.restore_problem)
    return programs, recovery
