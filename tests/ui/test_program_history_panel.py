"""The Program tab's History on a real PendantUI: saves listed with who made them, the diff of two versions
in words with the moved waypoint drawn old and new in 3D, Restore for the operator only, and Undo after it."""

from __future__ import annotations

import numpy as np
import pytest
import viser

from pendant.program import MoveStep
from pendant.ui.app import PendantUI
from pendant.ui.page.session import ClientSession
from pendant.ui.program.history_section import AFTER_RGB, BEFORE_RGB, UNSAVED
from tests.support.doubles import OPERATOR, VIEWER, FakeBrowser, fire
from tests.support.program_history import cut_head_commit, git, pick_program, waypoint

POSITION_TOL_M = 1e-9


def save(ui: ClientSession, browser: FakeBrowser, option: str, name: str = "") -> None:
    files = ui.program.file_section
    if name:
        fire(files.file_name, browser, name)
    fire(files.files, browser, option)


@pytest.fixture
def two_saves(pendant_ui: PendantUI, ui: ClientSession) -> bytes:
    """pick saved, then saved again with step 1 faster and P3 re-taught 12 mm further in X (by OPERATOR)."""
    operator = FakeBrowser(OPERATOR)
    workspace = pendant_ui.programs
    workspace.open_uploaded(pick_program())
    save(ui, operator, "Save as", "pick")
    first = (workspace.store.folder / "pick.json").read_bytes()
    workspace.replace_step(0, MoveStep(waypoint="P1", speed=40.0))
    moved = waypoint("P3", 512.0)
    workspace.reteach_waypoint("P3", moved.pose, moved.position)
    save(ui, operator, "Save")
    return first


def test_history_lists_who_saved_and_the_diff_of_the_last_save(
    pendant_ui: PendantUI, ui: ClientSession, two_saves: bytes
) -> None:
    history = ui.program.history_section
    assert "Versions of `pick.json`: 2" in history.status.content
    assert history.table.content.count("browser #1") == 2
    assert "Save pick: P3 moved +12.0 mm in X; step 1 (Move J to P1 @ 40%): speed 20 -> 40 %" in (
        history.table.content
    )
    # From: the version before; To: the program on screen (the newest save).
    assert history.newer.value == UNSAVED
    assert history.diff_view.content.splitlines() == [
        "- P3 moved +12.0 mm in X",
        "- step 1 (Move J to P1 @ 40%): speed 20 -> 40 %",
    ]
    assert history.shown is not None
    [moved] = history.shown.moved
    spheres = {node.name: node for node in history.nodes if node.name.endswith(("_before", "_after"))}
    before, after = spheres["/program_history/0_before"], spheres["/program_history/0_after"]
    assert isinstance(before, viser.IcosphereHandle) and isinstance(after, viser.IcosphereHandle)
    np.testing.assert_allclose(before.position, (0.5, 0.0, 0.3), atol=POSITION_TOL_M)
    np.testing.assert_allclose(after.position, (0.512, 0.0, 0.3), atol=POSITION_TOL_M)
    assert (tuple(before.color), tuple(after.color)) == (BEFORE_RGB, AFTER_RGB)
    assert moved.name == "P3"


def test_picking_two_versions_and_the_unsaved_program(
    pendant_ui: PendantUI, ui: ClientSession, two_saves: bytes
) -> None:
    operator = FakeBrowser(OPERATOR)
    history = ui.program.history_section
    newest, oldest = history.older.options
    fire(history.older, operator, newest)
    assert history.diff_view.content == "_No changes._" and not history.nodes
    pendant_ui.programs.delete_step(1)  # an unsaved change shows at once against the picked version
    assert history.diff_view.content == "- step 2 (Move J to P2 @ 20%) removed"
    fire(history.newer, operator, newest)
    fire(history.older, operator, oldest)
    assert "- step 1 (Move J to P1 @ 40%): speed 20 -> 40 %" in history.diff_view.content


def test_restore_is_for_the_operator_and_undo_brings_back_the_program(
    pendant_ui: PendantUI, ui: ClientSession, two_saves: bytes
) -> None:
    workspace = pendant_ui.programs
    history = ui.program.history_section
    folder = workspace.store.folder
    edited = workspace.program
    oldest = history.older.options[-1]

    viewer = FakeBrowser(VIEWER)
    fire(history.older, viewer, oldest)
    fire(history.restore, viewer)
    assert viewer.notifications and viewer.notifications[-1].startswith("Restore version refused")
    assert (
        workspace.program == edited and len(git(folder, "log", "--format=%H", "--", "pick.json").split()) == 2
    )

    operator = FakeBrowser(OPERATOR)
    fire(history.older, operator, oldest)
    fire(history.restore, operator)
    assert (folder / "pick.json").read_bytes() == two_saves
    log = git(folder, "log", "--format=%an|%s", "--", "pick.json").splitlines()
    assert len(log) == 3 and log[0].startswith("browser #1|Restore pick to version ")
    assert "Versions of `pick.json`: 3" in history.status.content

    fire(ui.program.history, operator, "Undo")
    assert workspace.program == edited and workspace.dirty


def test_a_save_the_history_cannot_record_is_kept_and_said_in_the_page(
    pendant_ui: PendantUI, ui: ClientSession, two_saves: bytes
) -> None:
    operator = FakeBrowser(OPERATOR)
    workspace = pendant_ui.programs
    folder = workspace.store.folder
    head = git(folder, "rev-parse", "HEAD").strip()
    (folder / ".git" / "MERGE_HEAD").write_text(head + "\n")  # someone left a merge half done

    workspace.replace_step(0, MoveStep(waypoint="P1", speed=80.0))
    save(ui, operator, "Save")
    said = operator.notifications[-1]  # the save itself went through, and its notification says the rest
    assert (
        said.startswith("Saved: pick.json was saved, but not recorded in the history: ") and "merge" in said
    )
    assert b'"speed": 80.0' in (folder / "pick.json").read_bytes()
    status = ui.program.history_section.status.content
    assert "pick.json was saved, but not recorded in the history" in status and "middle of a merge" in status
    assert git(folder, "rev-parse", "HEAD").strip() == head


def test_save_as_a_new_name_into_a_damaged_history_writes_the_file_and_says_so(
    pendant_ui: PendantUI, ui: ClientSession, two_saves: bytes
) -> None:
    operator = FakeBrowser(OPERATOR)
    folder = pendant_ui.programs.store.folder
    cut_head_commit(folder)
    save(ui, operator, "Save as", "pick copy")
    assert pendant_ui.programs.store.load("pick copy").steps == pendant_ui.programs.program.steps
    said = operator.notifications[-1]
    assert (
        said.startswith("Saved: pick copy.json was saved, but not recorded in the history: ")
        and "fsck" in said
    )
