"""The Program tab's "History" folder: the versions of the open program (time, who, summary), the diff of
any two of them (or of the unsaved program) in words, the waypoints that moved drawn old and new in 3D,
and Restore (itself a new version; Undo brings back what was on screen).
"""

from __future__ import annotations

import logging

import numpy as np
import viser

from pendant.controller.types import Position
from pendant.program import Change, ProgramFileError
from pendant.program.diff import ProgramDiff, WaypointMove, diff_programs
from pendant.program.history import HistoryError, Version
from pendant.ui.program.host import ProgramHost

log = logging.getLogger(__name__)

SHOWN_VERSIONS = 50  # in the page's lists; `pendant history` lists up to a thousand
TABLE_ROWS = 8
UNSAVED = "the program on screen"
NO_VERSION = "(no versions yet: save the program)"
ROOT = "/program_history"
MARK_RADIUS_M = 0.01
BEFORE_RGB = (150, 150, 150)
AFTER_RGB = (250, 110, 20)
MOVE_THICKNESS_PX = 3.0


class HistorySection:
    def __init__(self, host: ProgramHost) -> None:
        self._host = host
        self._versions: list[Version] = []
        self._nodes: list[viser.SceneNodeHandle] = []
        self.shown: ProgramDiff | None = None  # the diff on screen (tests read it)
        gui = host.target.gui
        with gui.add_folder("History", expand_by_default=False):
            self.status = gui.add_markdown("")
            self.table = gui.add_markdown("")
            self.older = gui.add_dropdown("From", options=[NO_VERSION], initial_value=NO_VERSION)
            self.newer = gui.add_dropdown("To", options=[UNSAVED], initial_value=UNSAVED)
            self.diff_view = gui.add_markdown("")
            self.restore = gui.add_button(
                "Restore the From version",
                icon=viser.Icon.HISTORY,
                hint="Saved as a new version; Undo goes back",
            )
        self.older.on_update(lambda e: self._picked(e))
        self.newer.on_update(lambda e: self._picked(e))
        self.restore.on_click(
            lambda e: host.edit("Restore version", e.client, lambda: self._restore_selected())
        )
        self._listener = self._on_change
        host.shared.on_change(self._listener)
        self.redraw()

    @property
    def nodes(self) -> tuple[viser.SceneNodeHandle, ...]:
        """The scene nodes it draws now."""
        return tuple(self._nodes)

    def close(self) -> None:
        self._host.shared.remove_listener(self._listener)
        self._clear_scene()

    # --- following the workspace ------------------------------------------------------------------
    def _on_change(self, change: Change) -> None:
        if change is Change.FILES:
            self.redraw()
        elif change is Change.PROGRAM and self.newer.value == UNSAVED:
            self.show_diff()

    def _picked(self, event: viser.GuiEvent) -> None:
        if not self._host.syncing and event.client is not None:
            self.show_diff()

    def redraw(self) -> None:
        """Re-read the versions of the open file; From is the last saved version, To the program on screen."""
        shared = self._host.shared
        problem = None
        try:
            history = shared.versions
            name = shared.file_name
            self._versions = history.versions(name, SHOWN_VERSIONS) if name else []
            problem = history.history_note
        except (HistoryError, ProgramFileError) as error:
            self._versions, problem = [], str(error)
        where = f"`{shared.file_name}.json`" if shared.file_name else "this program (not saved yet)"
        self.status.content = f"Versions of {where}: {len(self._versions)}" + (
            f"  \n**{problem}**" if problem else ""
        )
        rows = [f"`{v.short}` {_when(v)} · {v.who}  \n{v.summary}" for v in self._versions[:TABLE_ROWS]]
        self.table.content = "  \n".join(rows) if rows else "_No versions yet: Save makes one._"
        labels = [_label(v) for v in self._versions] or [NO_VERSION]
        self._host.syncing = True
        try:
            self.older.options = labels
            # The unsaved changes against the last version, else what the last save changed.
            self.older.value = labels[0 if shared.dirty or len(labels) < 2 else 1]
            self.newer.options = [UNSAVED, *labels[: len(self._versions)]]
            self.newer.value = UNSAVED
        finally:
            self._host.syncing = False
        self.show_diff()

    # --- the diff -----------------------------------------------------------------------------------
    def _commit_of(self, label: str) -> str | None:
        return next((v.commit for v in self._versions if _label(v) == label), None)

    def show_diff(self) -> None:
        shared = self._host.shared
        older = self._commit_of(str(self.older.value))
        if older is None or shared.file_name is None:
            self._show(None, "")
            return
        try:
            before = shared.versions.version_program(shared.file_name, older)
            newer = self._commit_of(str(self.newer.value))
            after = (
                shared.program if newer is None else shared.versions.version_program(shared.file_name, newer)
            )
        except (HistoryError, ProgramFileError) as error:
            self._show(None, f"**{error}**")
            return
        change = diff_programs(before, after)
        lines = [f"- {line}" for line in change.lines] or ["_No changes._"]
        self._show(change, "\n".join(lines))

    def _show(self, change: ProgramDiff | None, text: str) -> None:
        self.shown = change
        self.diff_view.content = text
        self._clear_scene()
        for k, moved in enumerate(change.moved if change is not None else ()):
            self._draw_move(k, moved)

    def _draw_move(self, k: int, moved: WaypointMove) -> None:
        scene = self._host.target.scene
        before = _xyz(moved.before)
        after = _xyz(moved.after)
        for tag, point, color in (("before", before, BEFORE_RGB), ("after", after, AFTER_RGB)):
            self._nodes.append(
                scene.add_icosphere(
                    f"{ROOT}/{k}_{tag}", radius=MARK_RADIUS_M, color=color, position=point, cast_shadow=False
                )
            )
        self._nodes.append(
            scene.add_line_segments(
                f"{ROOT}/{k}_move",
                np.array([[before, after]]),
                AFTER_RGB,
                thickness=MOVE_THICKNESS_PX,
                thickness_units="screen",
            )
        )
        self._nodes.append(
            scene.add_label(
                f"{ROOT}/{k}_label",
                f"{moved.name}: {moved.distance_mm:.1f} mm",
                position=after,
                anchor="bottom-center",
            )
        )

    def _clear_scene(self) -> None:
        for node in self._nodes:
            node.remove()
        self._nodes.clear()

    def _restore_selected(self) -> None:
        commit = self._commit_of(str(self.older.value))
        if commit is None:
            raise ProgramFileError("Pick the version to restore in From")
        self._host.shared.restore_version(commit)


def _when(version: Version) -> str:
    return f"{version.time:%Y-%m-%d %H:%M:%S} UTC"


def _label(version: Version) -> str:
    return f"{version.short} · {version.time:%m-%d %H:%M:%S} · {version.who}"


def _xyz(position: Position) -> tuple[float, float, float]:
    return (position.point.x, position.point.y, position.point.z)
