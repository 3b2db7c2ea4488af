"""An operator running a program from the page, without a browser: over viser's websocket, as the page's
Program tab does it (pick the file in "Saved programs", File > Load, type the loop count, press Run), then
reading the run's line under Run ("Running step 3/8, loop 1/3", ..., "Finished").

`classroom_program` is the program it runs: two Move J steps, each followed by a wait, an output and a wait,
so that every step's start can be timed from the controller's side (tests/support/sim_step_log.py)."""

from __future__ import annotations

import asyncio
import contextlib
from dataclasses import dataclass, field
from pathlib import Path

import websockets
import zstandard

from pendant.controller import SignalLevel
from pendant.program import MoveStep, OutputStep, Program, ProgramStore, WaitStep
from pendant.sim import FakeClock, SimController
from tests.support.headless_viewer import decode_window, gui_update
from tests.support.programs import POSE_A_DEG, POSE_B_DEG, teach

PROGRAM_NAME = "classroom"
WAIT_MS = 500
MOVE_SPEED_PERCENT = 30.0
FINISHED = "Finished"


def classroom_program() -> Program:
    """Move J A, Wait, DO1 high, Wait, Move J B, Wait, DO1 low, Wait (run in a loop by the Run's count)."""
    clock = FakeClock()
    sim = SimController("pulse75", clock)
    a, b = teach(sim, clock, POSE_A_DEG, "A"), teach(sim, clock, POSE_B_DEG, "B")
    wait = WaitStep(ms=WAIT_MS)
    steps = (
        MoveStep(waypoint="A", speed=MOVE_SPEED_PERCENT),
        wait,
        OutputStep(port=1, level=SignalLevel.HIGH),
        wait,
        MoveStep(waypoint="B", speed=MOVE_SPEED_PERCENT),
        wait,
        OutputStep(port=1, level=SignalLevel.LOW),
        wait,
    )
    return Program(name=PROGRAM_NAME, waypoints=(a, b), steps=steps)


def save_classroom_program(folder: Path) -> None:
    """The program as a file in the pendant's programs folder (PENDANT_PROGRAMS_DIR)."""
    ProgramStore(folder).save(classroom_program(), PROGRAM_NAME)


@dataclass
class ProgramOperator:
    """The operator's page: reads every frame (as a browser does), keeps the Program tab's controls and
    the run's line under Run."""

    ws: websockets.ClientConnection
    uuids: dict[str, str] = field(default_factory=dict)  # saved, file, loops, run, status, stop
    status: list[str] = field(default_factory=list)  # the run's line, each time it changed
    loaded: asyncio.Event = field(default_factory=asyncio.Event)
    controls: asyncio.Event = field(default_factory=asyncio.Event)  # the six, and the whole panel after them
    whole_panel: bool = field(
        default=False, init=False
    )  # its last tab (the Dashboard's plots) came: every control has its handler
    _reader: asyncio.Task[None] | None = None

    def start(self) -> None:
        self._reader = asyncio.create_task(self._read())

    async def _read(self) -> None:
        zstd = zstandard.ZstdDecompressor()
        with contextlib.suppress(websockets.ConnectionClosed):
            async for frame in self.ws:
                assert isinstance(frame, bytes)
                for message in decode_window(frame, zstd):
                    self._take(message)

    def _take(self, message: dict[str, object]) -> None:
        kind, uuid = message.get("type"), str(message.get("uuid"))
        props = message.get("props")
        label = props.get("label") if isinstance(props, dict) else None
        found = self.uuids
        self.whole_panel = self.whole_panel or kind == "GuiUplotMessage"
        if kind == "GuiDropdownMessage" and label == "Saved programs":
            found["saved"] = uuid
        elif kind == "GuiButtonGroupMessage" and label == "File":
            found["file"] = uuid
        elif kind == "GuiTextMessage" and label == "Loops":
            found["loops"] = uuid
        elif kind == "GuiButtonMessage" and label == "Run" and isinstance(props, dict):
            if props.get("color") == "green":  # the Run folder's (the teach bar has a Run of its own)
                found["run"] = uuid
        elif kind == "GuiButtonMessage" and label == "Stop" and "run" in found and "stop" not in found:
            found["stop"] = uuid
        elif kind == "GuiMarkdownMessage" and "run" in found and "status" not in found:
            found["status"] = uuid  # the first markdown after Run: its line under the progress bar
        elif kind == "GuiUpdateMessage":
            updates = message.get("updates")
            assert isinstance(updates, dict)
            if uuid == found.get("status") and "_markdown" in updates:
                self.status.append(str(updates["_markdown"]))
            elif updates.get("value") == PROGRAM_NAME and uuid != found.get("saved"):
                self.loaded.set()  # the file's name written in "Save as name": the program is open
        if len(found) == 6 and self.whole_panel:  # viser drops a click on a control with no handler yet
            self.controls.set()

    async def run(self, loops: int, timeout_s: float) -> None:
        """Open the program's file and press Run for `loops` loops (0: until Stop)."""
        async with asyncio.timeout(timeout_s):
            await self.controls.wait()
            await self.ws.send(gui_update(self.uuids["saved"], PROGRAM_NAME))
            await self.ws.send(gui_update(self.uuids["file"], "Load"))
            await self.loaded.wait()
            await self.ws.send(gui_update(self.uuids["loops"], str(loops)))
            await self.ws.send(gui_update(self.uuids["run"], True))

    async def stop(self) -> None:
        """Press the Run folder's Stop."""
        await self.ws.send(gui_update(self.uuids["stop"], True))

    async def ended(self, timeout_s: float) -> str:
        """Wait for the run's line to leave "Running ..."; that line ("Finished", "Stopped at ...")."""
        running = ("Running", "Starting")
        async with asyncio.timeout(timeout_s):
            while True:
                began = [k for k, line in enumerate(self.status) if line.startswith(running)]
                if began and not self.status[-1].startswith(running):
                    return self.status[-1]
                await asyncio.sleep(0.1)

    async def close(self) -> None:
        if self._reader is not None:
            self._reader.cancel()
        await self.ws.close()
