"""The Dashboard's Replay: a kept recording played back in this browser only. The recorded arm is drawn as a
ghost in the 3D view; a time slider, Play and Pause at a chosen speed, the program step and the event log at
the slider's time, and a jump to each stop or error of the recording.

Replay moves nothing: it holds no controller and sends no command; anybody watching may replay."""

from __future__ import annotations

import html
import math
import threading
import time
from collections.abc import Callable
from pathlib import Path

import viser

from pendant.telemetry.replay import Replay, ReplayError, ReplayEvent, load_replay
from pendant.ui.kit.gui_target import GuiTarget
from pendant.ui.kit.jobs import PageJobs
from pendant.ui.scene.ghost import GhostArm
from pendant.ui.scene.ghost_stage import GhostStage

GHOST_RGBA = (0.55, 0.35, 0.85, 0.35)  # violet: neither the target's blue nor the waypoints' green
PLAY_PERIOD_S = 0.1  # the ghost moves 10 times a second while playing
SPEEDS = {"0.5×": 0.5, "1×": 1.0, "2×": 2.0, "5×": 5.0, "10×": 10.0}
EVENTS_SHOWN = 8
JUMPS_LISTED = 200  # the stops and errors offered to jump to (the first ones)
JUMP_PROMPT = "(choose a stop or an error)"
NO_JUMPS = "(no stops or errors)"
MESSAGE_CHARS = 80
PLAYED_TEXT = "Played to the end: the ghost is cleared (move the slider to see it again)."
IDLE_TEXT = "Choose a recording above and press **Replay**: its arm is drawn as a violet ghost."
LEVEL_COLOURS = {"ERROR": "#e03131", "FATAL": "#e03131", "WARNING": "#e8590c"}

ChosenRecording = Callable[[], Path | None]


def render_replay_events(events: list[ReplayEvent]) -> str:
    """Newest first: seconds into the recording, who, what."""
    if not events:
        return '<div id="replay-log" style="color:#868e96;font-size:0.85em">No events yet</div>'
    lines = [
        f'<div><span style="color:#868e96">{event.t_s:.1f} s</span> '
        f'<b style="color:{LEVEL_COLOURS.get(event.level, "#495057")}">{html.escape(event.who)}</b>: '
        f"{html.escape(event.message)}</div>"
        for event in events
    ]
    return f'<div id="replay-log" style="font-size:0.78em;line-height:1.35">{"".join(lines)}</div>'


def jump_label(event: ReplayEvent) -> str:
    message = event.message if len(event.message) <= MESSAGE_CHARS else event.message[:MESSAGE_CHARS] + "…"
    return f"{event.t_s:.1f} s · {message}"


class ReplayPanel:
    """One browser's replay; `chosen()` is the recording picked in the Recordings list, `recording_now()`
    the one being written (it cannot be replayed until it stops)."""

    def __init__(
        self,
        target: GuiTarget,
        urdf_path: Path | None,
        chosen: ChosenRecording,
        recording_now: ChosenRecording,
        jobs: PageJobs | None = None,
        ghosts: GhostStage | None = None,
    ) -> None:
        self._target = target
        self.ghosts = ghosts if ghosts is not None else GhostStage()
        self.ghosts.register("replay", self._hide_ghost)
        self._jobs = jobs if jobs is not None else PageJobs()
        self._chosen = chosen
        self._recording_now = recording_now
        self._urdf_path = urdf_path
        self.ghost: GhostArm | None = (
            None  # made at the first Replay: a page that never replays loads no more
        )
        gui = target.gui
        self.start = gui.add_button(
            "Replay", icon=viser.Icon.PLAYER_PLAY, hint="Play the chosen recording back here; moves nothing"
        )
        self.status = gui.add_markdown(IDLE_TEXT)
        self.time = gui.add_slider("Time s", min=0.0, max=1.0, step=0.1, initial_value=0.0, disabled=True)
        self.play = gui.add_button("Play", icon=viser.Icon.PLAYER_PLAY, disabled=True)
        self.pause = gui.add_button("Pause", icon=viser.Icon.PLAYER_PAUSE, disabled=True)
        self.speed = gui.add_dropdown("Speed", tuple(SPEEDS), initial_value="1×", disabled=True)
        self.step = gui.add_markdown("")
        self.jump = gui.add_dropdown("Jump to", (NO_JUMPS,), disabled=True)
        self.close_replay = gui.add_button("Close replay", icon=viser.Icon.X, disabled=True)
        self.log = gui.add_html("")
        self.replay: Replay | None = None
        self._jumps: dict[str, ReplayEvent] = {}
        self._lock = threading.RLock()  # the play thread and the browser's edits take turns
        self._playing = threading.Event()
        self._closed = threading.Event()
        self._player: threading.Thread | None = None
        # Loading is this browser's one job at a time (kit/jobs.py), never on viser's callback pool.
        self.start.on_click(
            lambda event: self._jobs.start("Replay", event.client, lambda: self.open(event.client))
        )
        self.time.on_update(lambda _: self.show_at(float(self.time.value)))
        self.play.on_click(lambda _: self.resume())
        self.pause.on_click(lambda _: self.hold())
        self.jump.on_update(lambda event: self._jump(event.client))
        self.close_replay.on_click(lambda _: self.close_view())

    # --- opening and closing ------------------------------------------------------------------------
    def open(self, client: viser.ClientHandle | None) -> Replay | None:
        """Load the chosen recording and show its start (a clear notification when it cannot be)."""
        path = self._chosen()
        if path is None:
            self._notify(client, "No recording is kept yet: record one first.")
            return None
        if path == self._recording_now():
            self._notify(client, f"{path.stem} is still being recorded: stop the recording first.")
            return None
        shown = self.status.content
        self.status.content = f"Loading **{path.stem}**…"
        try:
            replay = load_replay(path)
        except ReplayError as error:
            self.status.content = shown
            self._notify(client, str(error))
            return None
        self.hold()
        with self._lock:
            if self.ghost is None and self._urdf_path is not None:
                self.ghost = GhostArm(self._target, self._urdf_path, "/replay_ghost", GHOST_RGBA)
            self.replay = replay
            notable = [event for event in replay.events if event.notable][:JUMPS_LISTED]
            self._jumps = {jump_label(event): event for event in notable}
            self.jump.options = (JUMP_PROMPT, *self._jumps) if self._jumps else (NO_JUMPS,)
            self.jump.value = self.jump.options[0]
            self.time.max = max(math.ceil(replay.duration_s * 10) / 10, self.time.step)  # tenths, as its box
            for handle in (self.time, self.play, self.pause, self.speed, self.jump, self.close_replay):
                handle.disabled = False
            if float(self.time.value) == 0.0:
                self.show_at(0.0)
            else:
                self.time.value = 0.0  # shows it (the slider's callback)
        return replay

    def close_view(self) -> None:
        """Hide the ghost and go back to the live view."""
        self.hold()
        with self._lock:
            self.replay = None
            if self.ghost is not None:
                self.ghost.hide()
            self.ghosts.hidden("replay")
            for handle in (self.time, self.play, self.pause, self.speed, self.jump, self.close_replay):
                handle.disabled = True
            self.status.content = IDLE_TEXT
            self.step.content = ""
            self.log.content = ""

    def close(self) -> None:
        """The browser left: the play thread ends."""
        self._closed.set()
        self.hold()

    # --- the time --------------------------------------------------------------------------------------
    def show_at(self, t_s: float) -> None:
        """The ghost, the step and the events at `t_s` seconds into the recording."""
        with self._lock:
            replay = self.replay
            if replay is None:
                return
            q = replay.q_at(t_s)
            if self.ghost is not None:
                self.ghosts.show("replay")
                self.ghost.show(q)
            angles = " ".join(f"J{i + 1} {a:.1f}°" for i, a in enumerate(replay.q_deg[replay.index_at(t_s)]))
            self.status.content = (
                f"**{replay.name}** · {t_s:.1f} s of {replay.duration_s:.1f} s  \nGhost: {angles}"
            )
            step = replay.step_at(t_s)
            if step is None:
                self.step.content = "Program: none ran yet"
            elif step.line == 0:
                self.step.content = f"Program: {step.state}"
            else:
                self.step.content = f"Program step **{step.line}**: {step.step} ({step.state})"
            self.log.content = render_replay_events(replay.events_until(t_s, EVENTS_SHOWN))

    def _jump(self, client: viser.ClientHandle | None) -> None:
        event = self._jumps.get(str(self.jump.value))
        if event is None or client is None:  # the prompt, or the options being replaced
            return
        self.hold()
        self.time.value = event.t_s

    # --- playing ----------------------------------------------------------------------------------------
    def resume(self) -> None:
        if self.replay is None or self._closed.is_set():
            return
        if float(self.time.value) >= self.replay.duration_s:
            self.time.value = 0.0  # Play at the end starts again
        self._playing.set()
        if self._player is None or not self._player.is_alive():
            self._player = threading.Thread(target=self._play, name="replay-player", daemon=True)
            self._player.start()

    def hold(self) -> None:
        self._playing.clear()

    def _play(self) -> None:
        last = time.monotonic()
        while self._playing.is_set() and not self._closed.is_set():
            time.sleep(PLAY_PERIOD_S)
            now = time.monotonic()
            with self._lock:
                replay = self.replay
                if replay is None or not self._playing.is_set():
                    return
                t = min(
                    float(self.time.value) + (now - last) * SPEEDS.get(str(self.speed.value), 1.0),
                    replay.duration_s,
                )
                self.time.value = t
                if t >= replay.duration_s:
                    self._playing.clear()
                    self._played_to_the_end()
            last = now

    def _hide_ghost(self) -> None:
        """Another ghost took the view (the stage calls this): the replay pauses and its ghost goes."""
        self.hold()
        if self.ghost is not None:
            self.ghost.hide()

    def _played_to_the_end(self) -> None:
        """A replay played to its end clears itself: the ghost goes (the slider shows it again)."""
        if self.ghost is not None:
            self.ghost.hide()
        self.ghosts.hidden("replay")
        self.status.content += f"  \n{PLAYED_TEXT}"

    def _notify(self, client: viser.ClientHandle | None, body: str) -> None:
        if client is not None:
            client.add_notification(title="Replay", body=body, color="red", auto_close_seconds=8.0)
