"""Jog tab: "Record path" samples the arm at the refresh rate (30 Hz) while the operator free-drives or jogs;
"Stop and add to program" simplifies it (tolerance in mm and degrees, at most 100 waypoints) and adds it to
the program as one Path step, played back as one blended run; the raw recording is downloadable."""

from __future__ import annotations

import viser

from pendant.program import EditError, PathStep, ProgramWorkspace
from pendant.program.models import DEFAULT_PATH_NAME, walk
from pendant.teach.path_step import path_step
from pendant.teach.recording import PathRecorder
from pendant.teach.simplify import DEFAULT_TOL_DEG, DEFAULT_TOL_MM, MAX_WAYPOINTS
from pendant.ui.kit.commands import CommandRunner, notify_refusal
from pendant.ui.kit.gui_target import GuiTarget
from pendant.ui.kit.typed_field import FieldInvalid, NumberField, read_all

RECORD_LABEL = "Record path"


class RecordPanel:
    def __init__(
        self, target: GuiTarget, recorder: PathRecorder, programs: ProgramWorkspace, runner: CommandRunner
    ) -> None:
        self._recorder = recorder
        self._programs = programs
        self._runner = runner
        with target.gui.add_folder("Path recording", expand_by_default=True):
            self.note = target.gui.add_markdown("Free-drive or jog the arm while recording.")
            self.tol_mm = NumberField(target.gui, "Tolerance mm", DEFAULT_TOL_MM, low=0.01, decimals=2)
            self.tol_deg = NumberField(target.gui, "Tolerance °", DEFAULT_TOL_DEG, low=0.01, decimals=2)
            self.start = target.gui.add_button(RECORD_LABEL, icon=viser.Icon.PLAYER_RECORD, color="red")
            self.finish = target.gui.add_button("Stop and add to program", icon=viser.Icon.PLAYER_STOP)
            self.download = target.gui.add_button("Download recording", icon=viser.Icon.DOWNLOAD)
        self.start.on_click(lambda e: self.begin(e.client))
        self.finish.on_click(lambda e: self.end(e.client))
        self.download.on_click(lambda e: self.send(e.client))

    @property
    def controls(self) -> tuple[viser.GuiInputHandle, ...]:
        return (self.tol_mm.handle, self.tol_deg.handle, self.start, self.finish)

    def begin(self, client: viser.ClientHandle | None = None) -> bool:
        if self._runner.refusal(client, RECORD_LABEL) is not None:
            return False
        self._recorder.start()
        self._runner.record(RECORD_LABEL, client)
        self._say("**Recording…** move the arm, then Stop.")
        return True

    def end(self, client: viser.ClientHandle | None = None) -> int | None:
        """Stop; add the path to the program as one Path step. Returns its line (None: nothing added)."""
        if self._runner.refusal(client, "Stop recording") is not None:
            return None
        try:
            asked_mm, asked_deg = read_all((self.tol_mm, self.tol_deg))
        except FieldInvalid as error:  # the recording is kept: fix the tolerance and Stop again
            notify_refusal(client, "Path not added", error.message)
            return None
        recording = self._recorder.stop()
        if recording is None:
            notify_refusal(client, "Nothing recorded", "press Record path first")
            return None
        try:
            step = path_step(recording, asked_mm, asked_deg, self._next_name())
            line = self._programs.insert_step(step)
        except (ValueError, EditError) as error:
            notify_refusal(client, "Path not added", str(error))
            return None
        count = len(step.points)
        self._runner.record(f"Recorded path {step.name}: {count} waypoints", client)
        relaxed = "" if step.tol_mm == asked_mm else f" (relaxed to fit {MAX_WAYPOINTS} waypoints)"
        took = (
            f"{len(recording.samples)} samples in {recording.duration_s:.1f} s ({recording.rate_hz:.0f} Hz)"
        )
        self._say(
            f"{took} → **{count} waypoints** "
            f"within {step.tol_mm:g} mm / {step.tol_deg:g}°{relaxed}, added to the program as step "
            f"{line + 1} (path {step.name})."
            + (f" The recording is kept as `{recording.file}`." if recording.file else "")
        )
        return line

    def _next_name(self) -> str:
        names = {s.name for s in walk(self._programs.program.steps) if isinstance(s, PathStep)}
        return next(
            f"{DEFAULT_PATH_NAME}{k}"
            for k in range(1, len(names) + 2)
            if f"{DEFAULT_PATH_NAME}{k}" not in names
        )

    def send(self, client: viser.ClientHandle | None = None) -> bytes | None:
        recording = self._recorder.last
        if recording is None:
            notify_refusal(client, "No recording", "record a path first")
            return None
        data = recording.to_json()
        if client is not None:
            client.send_file_download(f"path-{recording.started_at[:19].replace(':', '')}.json", data)
        return data

    def show(self) -> None:
        if self._recorder.active:
            self._say(f"**Recording…** {self._recorder.samples} samples")

    def _say(self, text: str) -> None:
        if self.note.content != text:
            self.note.content = text
