"""The Program tab's "Check" folder: the pre-flight on the page, and the Run gate it opens on a real arm.

**Check** runs the program as it is now on a twin of the arm (pendant.planning): each line of the step list
gets a mark (✔ and the closest clearance, ✘ and why), the first failure is said in words, the TCP's swept
path is drawn in 3D with the failure point in red, and the Program tab's ghost plays the run back along a
time slider, the step list following it. On a real arm **Run** (and Run from, Step) waits for a passing check
of the program as it is now; **Run without check** lets the operator override it after a confirmation, and
the event log says who did.
"""

from __future__ import annotations

import bisect
import threading
import weakref

import numpy as np
import viser

from pendant.controller import Controller, ControllerError
from pendant.kinematics import ArmModel
from pendant.kinematics.transforms import position_to_matrix
from pendant.planning.budget import Budget
from pendant.planning.gate import RunGate, current_fingerprint
from pendant.planning.preflight import PreflightRefused, preflight
from pendant.planning.report import PreflightReport
from pendant.planning.twin import read_seed
from pendant.program import Program, ProgramWorkspace
from pendant.remote import RemoteController
from pendant.ui.kit.commands import notify_refusal
from pendant.ui.program.host import ProgramHost

ROOT = "/program_check"
PATH_RGB = (20, 170, 170)
FAILURE_RGB = (230, 30, 30)
FAILURE_RADIUS_M = 0.02
PATH_THICKNESS_PX = 3.0
GATED = ("Run", "Run from", "Step")  # what starts the arm on a program (Resume and Retry continue one)
MSG_OVERRIDE = "Run without a passing pre-flight"
MSG_RUNNING = "a check is already running (up to 30 s): its result comes first"


class SharedCheck:
    """One per workspace (every browser sees the same program): the gate and the last check."""

    def __init__(self, required: bool) -> None:
        self.gate = RunGate(required)
        self.lock = threading.Lock()
        self.program: Program | None = None  # the program the last report is of
        self.report: PreflightReport | None = None
        # One check at a time (issue #32): another click would queue one more pre-flight of up to 30 s on
        # the command worker, ahead of the operator's next commands.
        self.running = False


_SHARED: weakref.WeakKeyDictionary[ProgramWorkspace, SharedCheck] = weakref.WeakKeyDictionary()


def shared_check(workspace: ProgramWorkspace, required: bool) -> SharedCheck:
    found = _SHARED.get(workspace)
    if found is None:
        found = _SHARED[workspace] = SharedCheck(required)
    return found


class CheckSection:
    def __init__(self, host: ProgramHost, arm: ArmModel | None) -> None:
        self._host = host
        self._arm = arm
        self._controller = host.commands.controller
        self.shared = shared_check(host.shared, isinstance(self._controller, RemoteController))
        self._nodes: list[viser.SceneNodeHandle] = []
        self._drawn: PreflightReport | None = None
        gui = host.target.gui
        with gui.add_folder("Check (pre-flight)"):
            self.check = gui.add_button(
                "Check", icon=viser.Icon.SHIELD_CHECK, hint="Run the program on the twin: nothing moves"
            )
            self.summary = gui.add_markdown(self._gate_line())
            self.playback = gui.add_slider(
                "Playback (s)", min=0.0, max=1.0, step=0.05, initial_value=0.0, disabled=True
            )
            self.override = gui.add_button(
                "Run without check",
                color="orange",
                icon=viser.Icon.ALERT_TRIANGLE,
                hint="Run without a passing pre-flight (logged)",
                visible=self.shared.gate.required,
            )
        self.check.on_click(lambda e: self._start_check(e.client))
        self.override.on_click(lambda e: self._confirm_override(e.client))
        self.playback.on_update(self._on_playback)
        host.ghosts.register("check", self._hide_ghost)

    def _hide_ghost(self) -> None:
        """Another ghost took the view (the stage calls this): the playback's ghost goes."""
        ghost = self._host.ghost
        if ghost is not None:
            ghost.show_visual = False

    # --- the check -------------------------------------------------------------------------------------
    @property
    def nodes(self) -> tuple[viser.SceneNodeHandle, ...]:
        """The scene nodes it draws now."""
        return tuple(self._nodes)

    def _start_check(self, client: viser.ClientHandle | None) -> None:
        may_command = client is None or self._host.commands.gate(client) is None  # else refused as ever
        with self.shared.lock:
            busy = may_command and self.shared.running
            self.shared.running = self.shared.running or may_command
        if busy:
            notify_refusal(client, "Check refused", MSG_RUNNING)
            return
        try:  # off the UI thread; `pending` to wait on
            started = self._host.with_controller("Check", client, self._check)
        except BaseException:  # the page is closing: nothing runs
            self._check_ended()
            raise
        if may_command:
            started.add_done_callback(lambda _: self._check_ended())

    def _check_ended(self) -> None:
        with self.shared.lock:
            self.shared.running = False

    def _check(self, controller: Controller) -> PreflightReport | None:
        workspace = self._host.shared
        program = workspace.program
        model = self._arm.name if self._arm is not None else "pulse75"
        print_ = current_fingerprint(program, controller, workspace.store.load)
        try:
            # Quitting ends it at once (the API's pre-flights: their process is ended; this one: its budget).
            budget = Budget(cancel=self._host.commands.quitting)
            report = preflight(
                program, read_seed(controller), model=model, load=workspace.store.load, budget=budget
            )
        except PreflightRefused as error:
            raise ValueError(str(error)) from error  # told to the browser that asked (USER_ERRORS)
        with self.shared.lock:
            self.shared.program, self.shared.report = program, report
        self.shared.gate.record_check(print_, report)
        self.redraw()
        self._host.redraw_program()  # the marks on the step list
        return report

    def current(self) -> PreflightReport | None:
        """The last check's report if it is of the program as it is now."""
        with self.shared.lock:
            same = self.shared.program == self._host.shared.program
            return self.shared.report if same else None

    def mark(self, index: int) -> str:
        """The step list's mark for line `index` (0-based): "✔ 152 mm", "✘ why", "○ not checked" or ""."""
        report = self.current()
        if report is None or index >= len(report.steps):
            return ""
        step = report.steps[index]
        if not step.checked:
            return " · ○ not checked" if not step.ok else ""  # not reached: not the failing ✘
        if not step.ok:
            return f" · ✘ {step.reason}"
        clearance = "" if step.min_clearance_mm is None else f" {step.min_clearance_mm:.0f} mm"
        return f" · ✔{clearance}"

    def redraw(self) -> None:
        report = self.current()
        lines = [self._gate_line()]
        if report is not None:
            lines.insert(0, f"**{'✘ ' if not report.ok else '✔ '}{report.summary}**")
        self.summary.content = "\n\n".join(lines)
        self.playback.disabled = report is None or not report.timeline
        if report is not None and report.timeline:
            self.playback.max = max(round(report.cycle_time_s, 2), self.playback.step)
        self._draw(report)

    def _gate_line(self) -> str:
        if not self.shared.gate.required:
            return "Simulator: Check is offered, not required."
        return "Real arm: **Run** needs a passing check of the program as it is now."

    # --- the gate --------------------------------------------------------------------------------------
    def allows(self, label: str, client: viser.ClientHandle | None) -> bool:
        """Whether `label` may start the program now; if not, that browser is told why."""
        if label not in GATED or not self.shared.gate.required:
            return True
        try:
            print_ = self._fingerprint()
        except ControllerError as error:
            notify_refusal(client, f"{label} refused", f"Cannot read the arm: {error.message}")
            return False
        decision = self.shared.gate.decide(print_)
        if not decision.allowed:
            notify_refusal(client, f"{label} refused", f"{decision.reason} (or: Run without check)")
        return decision.allowed

    def _fingerprint(self) -> str:
        workspace = self._host.shared
        return current_fingerprint(workspace.program, self._controller, workspace.store.load)

    def _confirm_override(self, client: viser.ClientHandle | None) -> None:
        if not self._host.allowed(client, "Run without check"):
            return
        where = client if client is not None else self._host.target
        with where.gui.add_modal(f"{MSG_OVERRIDE}?") as modal:
            where.gui.add_markdown(
                "The program has not passed a pre-flight as it is now. Run it on the arm anyway? "
                "The event log records who decided."
            )
            yes = where.gui.add_button("Yes, run without check", color="orange")
            where.gui.add_button("Cancel").on_click(lambda _: modal.close())

        def confirmed(_: viser.GuiEvent) -> None:
            modal.close()
            try:
                print_ = self._fingerprint()
            except ControllerError as error:
                notify_refusal(client, "Run without check refused", f"Cannot read the arm: {error.message}")
                return
            name = self._host.shared.program.name
            self.shared.gate.override(print_, "page", name)
            self._host.commands.record(f"Program: {MSG_OVERRIDE} of {name!r} (confirmed)", client)
            self._host.start_run("Run", client)

        yes.on_click(confirmed)

    # --- 3D: the swept path, the failure point, the playback --------------------------------------------
    def _draw(self, report: PreflightReport | None) -> None:
        if report is self._drawn:
            return
        self._drawn = report
        for node in self._nodes:
            node.remove()
        self._nodes.clear()
        if report is None or self._arm is None:
            return
        T_flange_tool = self._tool()
        points = np.array([(self._arm.fk(q) @ T_flange_tool)[:3, 3] for _, _, q in report.timeline])
        scene = self._host.target.scene
        if len(points) >= 2:
            segments = np.stack([points[:-1], points[1:]], axis=1)
            self._nodes.append(
                scene.add_line_segments(
                    f"{ROOT}/swept", segments, PATH_RGB, thickness=PATH_THICKNESS_PX, thickness_units="screen"
                )
            )
        if report.failure_q is not None:
            at = (self._arm.fk(report.failure_q) @ T_flange_tool)[:3, 3]
            self._nodes.append(
                scene.add_icosphere(
                    f"{ROOT}/failure", radius=FAILURE_RADIUS_M, color=FAILURE_RGB, position=at
                )
            )

    def _tool(self) -> np.ndarray:
        report = self.current()
        if report is None:
            return np.eye(4)
        try:
            return position_to_matrix(self._controller.get_tool().position)
        except ControllerError:
            return np.eye(4)

    def _on_playback(self, event: viser.GuiEvent) -> None:
        report = self.current()
        if report is None or not report.timeline or event.client is None:
            return
        times = [t for t, _, _ in report.timeline]
        k = max(0, bisect.bisect_right(times, float(self.playback.value)) - 1)
        _, line, q = report.timeline[k]
        host = self._host
        if host.selected != line:
            host.select_line(line)  # the step list follows the playback
        ghost = host.ghost
        if ghost is not None:
            host.ghosts.show("check")  # before it is drawn: the waypoint preview is this same ghost
            ghost.pose(q)  # posed first: a ghost drawn at its first show stands there
            ghost.show_visual = True

    def close(self) -> None:
        for node in self._nodes:
            node.remove()
        self._nodes.clear()
