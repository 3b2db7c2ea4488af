"""The Dashboard's recording controls: start and stop (the operator), download the last recording as CSV or
MCAP, and any earlier one kept in the recordings folder (anybody: downloads change nothing)."""

from __future__ import annotations

import datetime as dt
from collections.abc import Callable
from pathlib import Path

import viser

from pendant.telemetry import Telemetry
from pendant.telemetry.recordings import RecordingError
from pendant.ui.kit.commands import notify_refusal
from pendant.ui.kit.download import send_bytes, send_file
from pendant.ui.kit.gui_target import GuiTarget
from pendant.ui.kit.jobs import PageJobs

NO_RECORDINGS = "(none yet)"
Client = viser.ClientHandle | None
RecordingListener = Callable[[viser.ClientHandle | None, str], None]


class RecordingControls:
    def __init__(
        self,
        target: GuiTarget,
        telemetry: Telemetry,
        *,
        may_record: Callable[[viser.ClientHandle | None], str | None],
        on_recording: RecordingListener,
        jobs: PageJobs | None = None,
    ) -> None:
        self._target = target
        self._jobs = jobs if jobs is not None else PageJobs()
        self._telemetry = telemetry
        self._may_record = may_record
        self._on_recording = on_recording
        self.recording_status = target.gui.add_markdown("Not recording.")
        self.record_start = target.gui.add_button("Start recording", icon=viser.Icon.PLAYER_RECORD)
        self.record_stop = target.gui.add_button("Stop recording", icon=viser.Icon.PLAYER_STOP, disabled=True)
        self.download = target.gui.add_button("Download CSV", icon=viser.Icon.DOWNLOAD, disabled=True)
        self.saved = target.gui.add_dropdown(
            "Recordings",
            self._choices(),
            hint="Kept in the data folder; MCAP opens in Foxglove or Lichtblick",
        )
        self.download_mcap = target.gui.add_button("Download MCAP", icon=viser.Icon.DOWNLOAD)
        self.download_saved_csv = target.gui.add_button("Download its CSV", icon=viser.Icon.DOWNLOAD)
        self.record_start.on_click(lambda event: self.start_recording(event.client))
        self.record_stop.on_click(lambda event: self.stop_recording(event.client))
        # Downloads run as the browser's one job at a time (kit/jobs.py), never on viser's callback pool.
        self.download.on_click(lambda event: self._job("Download CSV", event.client, self.send_csv))
        self.download_mcap.on_click(
            lambda event: self._job("Download MCAP", event.client, lambda c: self.send_saved(c, ".mcap"))
        )
        self.download_saved_csv.on_click(
            lambda event: self._job("Download its CSV", event.client, lambda c: self.send_saved(c, ".csv"))
        )
        self._text = ""
        self._was_recording = False

    def _job(self, label: str, client: viser.ClientHandle | None, send: Callable[[Client], object]) -> None:
        self._jobs.start(label, client, lambda: send(client))

    def _choices(self) -> tuple[str, ...]:
        labels = tuple(recording.label for recording in self._telemetry.recordings())
        return labels or (NO_RECORDINGS,)

    def show(self, *, locked: bool) -> None:
        """The refresh loop: status and which buttons work."""
        recorder = self._telemetry.recorder
        if recorder.recording:
            text = f"**Recording** · {recorder.row_count} samples"
        elif recorder.row_count:
            text = f"Stopped · {recorder.row_count} samples ready to download"
        else:
            text = "Not recording."
        if text != self._text:
            self.recording_status.content = text
            self._text = text
        if recorder.recording != self._was_recording:  # started or stopped (here or in another browser)
            self._was_recording = recorder.recording
            self.saved.options = self._choices()
        for handle, disabled in (
            (self.record_start, locked or recorder.recording),
            (self.record_stop, locked or not recorder.recording),
            (self.download, recorder.row_count == 0),
        ):
            if handle.disabled != disabled:  # each assignment is a message to the browser
                handle.disabled = disabled

    def start_recording(self, client: viser.ClientHandle | None) -> bool:
        if self._refused(client, "Start recording"):
            return False
        try:
            self._telemetry.start_recording()
        except RecordingError as error:
            notify_refusal(client, "Start recording", str(error))
            return False
        self._on_recording(client, "Recording started")
        return True

    def stop_recording(self, client: viser.ClientHandle | None) -> bool:
        if self._refused(client, "Stop recording"):
            return False
        rows = self._telemetry.stop_recording()
        self._on_recording(client, f"Recording stopped: {rows} samples")
        self.saved.options = self._choices()
        return True

    def send_csv(self, client: viser.ClientHandle | None) -> bytes:
        content = self._telemetry.recorder.to_csv()
        name = f"pendant-telemetry-{dt.datetime.now():%Y%m%d-%H%M%S}.csv"
        self._send(client, name, content)
        return content

    def chosen_file(self, suffix: str = ".mcap") -> Path | None:
        """The chosen saved recording's file (the newest when none is chosen yet)."""
        recordings = self._telemetry.recordings()
        chosen = next(
            (r for r in recordings if r.label == self.saved.value), recordings[0] if recordings else None
        )
        return next((f for f in chosen.files if f.suffix == suffix), None) if chosen is not None else None

    def send_saved(self, client: viser.ClientHandle | None, suffix: str) -> Path | None:
        """The chosen saved recording's file (the newest when none is chosen yet)."""
        path = self.chosen_file(suffix)
        if path is None:
            if client is not None:
                client.add_notification(
                    title="Nothing to download", body="No recording is kept yet.", auto_close_seconds=5.0
                )
            return None
        if client is None:  # the server's own page (headless tests): viser's whole-file download
            self._target.send_file_download(path.name, path.read_bytes(), save_immediately=True)
        else:
            send_file(client, path)  # read a part at a time as the browser takes them
        return path

    def _send(self, client: viser.ClientHandle | None, name: str, content: bytes) -> None:
        if client is None:
            self._target.send_file_download(name, content, save_immediately=True)
        else:
            send_bytes(client, name, content)

    def _refused(self, client: viser.ClientHandle | None, label: str) -> bool:
        reason = self._may_record(client)
        if reason is not None and client is not None:
            client.add_notification(
                title=f"{label} refused", body=reason, color="red", auto_close_seconds=8.0
            )
        return reason is not None
