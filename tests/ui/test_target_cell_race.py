"""The target and a cell that changes under it: a script adds an obstacle while the page is still checking
the operator's new target against the old cell. The two checks take turns, so the target ends up checked
against the new cell (before: the late check against the old one overwrote the recheck, and the ghost said
"Target ready" for a path through the new obstacle until the next drag)."""

from __future__ import annotations

import threading

import numpy as np

from pendant.cell.geometry import CellModel
from pendant.controller.cell_types import ToolShape
from pendant.sim import SimController
from pendant.ui.app import PendantUI
from pendant.ui.target.panel import TargetPanel
from tests.support.obstacles import box
from tests.support.sim_sampling import home_q

SCRIPT_WAIT_S = 0.5  # how long the script's refresh gets to run while the operator's check is under way


def test_a_target_set_while_an_obstacle_arrives_is_checked_against_it(
    pendant_ui: PendantUI, sim: SimController
) -> None:
    q = home_q(sim)
    around, halfway = q.copy(), q.copy()
    around[0] += np.radians(90.0)
    halfway[0] += np.radians(45.0)
    wall = box("wall", tuple(sim.arm.fk(halfway)[:3, 3]))
    cells = {"now": CellModel(sim.arm, [], ToolShape(shape=[]))}
    operator = threading.Thread(target=lambda: panel.set_joint_target(around), name="operator")

    def obstacle_arrives() -> None:
        cells.update(now=with_wall)
        panel.recheck()

    script = threading.Thread(target=obstacle_arrives, name="script")
    with_wall = CellModel(sim.arm, [wall], ToolShape(shape=[]))

    def current_cell() -> CellModel:
        cell = cells["now"]
        if threading.current_thread() is operator and not script.is_alive() and script.ident is None:
            script.start()  # the obstacle arrives (the refresh's recheck) while this check runs
            script.join(timeout=SCRIPT_WAIT_S)
        return cell

    panel = TargetPanel(
        pendant_ui.server, sim.arm, pendant_ui.runner, lambda: q, lambda: np.eye(4), current_cell
    )
    operator.start()
    operator.join()
    script.join()
    assert panel.check.reason == "Collision detected: the path to the target passes through 'wall'"
    assert panel.check.q is not None
    np.testing.assert_allclose(panel.check.q, around)  # the operator's target, not the arm's pose
    assert panel.move_j.disabled
