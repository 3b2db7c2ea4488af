"""What the Program tab's sections (file, run, step form, waypoints) use of the panel that holds them.

The sections type their host as this Protocol rather than as ProgramPanel, so they do not import panel.py
(which imports them): no import circle, not even for the type checker.
"""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import Future
from typing import Protocol

import viser

from pendant.cell.geometry import CellModel
from pendant.controller import Controller
from pendant.program import ProgramWorkspace
from pendant.program.tree import Line
from pendant.ui.kit.commands import CommandRunner
from pendant.ui.kit.gui_target import GuiTarget
from pendant.ui.scene.ghost_stage import GhostStage
from pendant.ui.scene.shared_urdf import SharedUrdf


class ProgramHost(Protocol):
    target: GuiTarget
    shared: ProgramWorkspace  # the one program every browser edits
    commands: CommandRunner
    selected: int | None  # the selected step's line in the list
    syncing: bool  # set while redrawing: viser calls back for values the panel sets
    current_cell: Callable[[], CellModel | None]  # the controller's cell, to name what is in the way
    ghosts: GhostStage  # one ghost at a time in this browser's view

    def allowed(self, client: viser.ClientHandle | None, label: str) -> bool: ...

    def edit(self, label: str, client: viser.ClientHandle | None, action: Callable[[], object]) -> None:
        """A change to the shared program or files: refused for viewers; errors go to that browser."""
        ...

    def with_controller(
        self, label: str, client: viser.ClientHandle | None, action: Callable[[Controller], object]
    ) -> Future[object]:
        """An edit that reads the arm (Record, Re-teach): off the UI thread."""
        ...

    def selected_line(self) -> Line | None: ...

    def redraw_program(self) -> None:
        """Redraw the step list (the Check's marks changed)."""
        ...

    def start_run(self, label: str, client: viser.ClientHandle | None) -> None:
        """Run, Run from or Step, as the run section's buttons do."""
        ...

    def run_allowed(self, label: str, client: viser.ClientHandle | None) -> bool:
        """The Run gate on a real arm: a passing pre-flight of the program as it is now, or an override."""
        ...

    @property
    def ghost(self) -> SharedUrdf | None:
        """The tab's translucent ghost arm (the Check's playback moves it)."""
        ...

    def select_line(self, index: int | None) -> None: ...

    def need_selection(self) -> int: ...
