"""Jog tab: "Record path" samples the arm at the refresh rate (30 Hz) while the operator free-drives or jogs;
"Stop and add to program" simplifies it (tolerance in mm and degrees, at most 100 waypoints) and adds it to
the program as a group of linear moves; the raw recording is downloadable."""

from __future__ import annotations

import viser

from pendant.controller import MotionType
from pendant.program import ProgramWorkspace
from pendant.teach.recording import PathRecorder
from pendant.teach.simplify import DEFAULT_TOL_DEG, DEFAULT_TOL_MM, MAX_WAYPOINTS
from pendant.ui.commands import CommandRunner, notify_refusal
from pendant.ui.gui_target import GuiTarget

RECORD_LABEL = "Record path"


class RecordPanel:
    def __init__(
        self, target: GuiTarget, recorder: PathRecorder, programs: ProgramWorkspace, runner: CommandRunner
    ) -> None:
        self._recorder = recorder
        self._programs = programs
        self._runner = runner
        self._paths = 0
        with target.gui.add_folder("Path recording", expand_by_default=True):
            self.note = target.gui.add_markdown("Free-drive or jog the arm while recording.")
            self.tol_mm = target.gui.add_number(
                "Tolerance mm", initial_value=DEFAULT_TOL_MM, min=0.01, step=0.1
            )
            self.tol_deg = target.gui.add_number(
                "Tolerance °", initial_value=DEFAULT_TOL_DEG, min=0.01, step=0.1
            )
            self.start = target.gui.add_button(RECORD_LABEL, icon=viser.Icon.PLAYER_RECORD, color="red")
            self.finish = target.gui.add_button("Stop and add to program", icon=viser.Icon.PLAYER_STOP)
            self.download = target.gui.add_button("Download recording", icon=viser.Icon.DOWNLOAD)
        self.start.on_click(lambda e: self.begin(e.client))
        self.finish.on_click(lambda e: self.end(e.client))
        self.download.on_click(lambda e: self.send(e.client))

    @property
    def controls(self) -> tuple[viser.GuiInputHandle, ...]:
        return (self.tol_mm, self.tol_deg, self.start, self.finish)

    def begin(self, client: viser.ClientHandle | None = None) -> bool:
        if self._runner.refusal(client, RECORD_LABEL) is not None:
            return False
        self._recorder.start()
        self._runner.record(RECORD_LABEL, client)
        self._say("**Recording…** move the arm, then Stop.")
        return True

    def end(self, client: viser.ClientHandle | None = None) -> list[int]:
        """Stop; add the simplified path to the program. Returns the indices of the steps added."""
        if self._runner.refusal(client, "Stop recording") is not None:
            return []
        recording = self._recorder.stop()
        if recording is None:
            notify_refusal(client, "Nothing recorded", "press Record path first")
            return []
        asked_mm = float(self.tol_mm.value)
        try:
            waypoints, tol_mm, tol_deg = recording.waypoints(asked_mm, float(self.tol_deg.value))
        except ValueError as error:
            notify_refusal(client, "Path not added", str(error))
            return []
        self._paths += 1
        added = [
            self._programs.record(pose, position, name=f"path{self._paths}_{i + 1}", motion=MotionType.LINEAR)
            for i, (pose, position) in enumerate(waypoints)
        ]
        self._runner.record(f"Recorded path: {len(added)} waypoints", client)
        relaxed = "" if tol_mm == asked_mm else f" (relaxed to fit {MAX_WAYPOINTS} waypoints)"
        rate = f"{recording.rate_hz:.0f} Hz"
        self._say(
            f"{len(recording.samples)} samples in {recording.duration_s:.1f} s ({rate}) → "
            f"**{len(added)} waypoints** within {tol_mm:g} mm / {tol_deg:g}°{relaxed}, added to the program."
        )
        return added

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
