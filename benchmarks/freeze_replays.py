"""Freeze while viewers load replays (issue #32): PUT /freeze latency while viewers keep pressing Replay on a
two-hour recording. The stop buttons no longer wait for viser's pool; what is left is the interpreter itself:
loading a replay makes many objects that stay, and a full garbage collection then walks the whole heap of the
page's process, holding every thread (the API's Freeze included) meanwhile.

Starts `pendant` (page and API) on a data folder holding one two-hour recording; idle first, then `--viewers`
bare websocket viewers each press Replay every `--click-s` (one job per browser, viewers share two: the rest
are refused) while PUT /freeze is sent every `--period-ms` over one bare-socket keep-alive connection.
Run: .venv/bin/python benchmarks/freeze_replays.py [--seconds 20] [--viewers 4]
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import threading
import time
from pathlib import Path

import viser
import zstandard
from websockets.sync.client import connect

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from benchmarks.preflight_bodies import freeze_latencies_ms, summary
from tests.support.big_recordings import write_long_recording
from tests.support.headless_viewer import CAMERA_HELLO, click_message, decode_window
from tests.support.launchers import running_pendant_ui
from tests.support.ports import LOOPBACK

RECORDING = "pendant-20260101-000000.mcap"


def viewer(ui_port: int, click_s: float, stop: threading.Event, clicks: list[int]) -> None:
    """A browser without control pressing Replay every `click_s`, reading everything the page sends."""
    ws = connect(
        f"ws://{LOOPBACK}:{ui_port}/",
        subprotocols=[f"viser-v{viser.__version__}"],  # type: ignore[list-item]  # a str is a Subprotocol
        max_size=None,
        max_queue=None,
    )
    ws.send(CAMERA_HELLO)
    zstd = zstandard.ZstdDecompressor()
    replay, next_click = None, 0.0
    try:
        while not stop.is_set():
            try:
                frame = ws.recv(timeout=0.05)
            except TimeoutError:
                frame = None
            if isinstance(frame, bytes) and replay is None:
                for message in decode_window(frame, zstd):
                    if (
                        message.get("type") == "GuiButtonMessage"
                        and message["props"].get("label") == "Replay"
                    ):
                        replay = str(message["uuid"])
            if replay is not None and time.monotonic() >= next_click:
                ws.send(click_message(replay))
                clicks.append(1)
                next_click = time.monotonic() + click_s
    finally:
        ws.close()


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seconds", type=float, default=20.0)
    parser.add_argument("--period-ms", type=float, default=20.0)
    parser.add_argument("--viewers", type=int, default=4)
    parser.add_argument("--click-s", type=float, default=0.5)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as data:
        (Path(data) / "recordings").mkdir()
        write_long_recording(Path(data) / "recordings" / RECORDING)
        with running_pendant_ui(env={"PENDANT_DATA_DIR": data}) as pendant:
            port = int(str(pendant.api.base_url).rsplit(":", 1)[1].rstrip("/"))
            print(f"{'idle':<10}{summary(freeze_latencies_ms(port, 5.0, args.period_ms / 1e3))}")
            stop, clicks = threading.Event(), []
            threads = [
                threading.Thread(target=viewer, args=(pendant.ui_port, args.click_s, stop, clicks))
                for _ in range(args.viewers)
            ]
            for thread in threads:
                thread.start()
            time.sleep(3.0)  # the viewers' pages have come
            times = freeze_latencies_ms(port, args.seconds, args.period_ms / 1e3)
            stop.set()
            for thread in threads:
                thread.join()
            print(f"{'replays':<10}{summary(times)}  ({len(clicks)} Replay clicks)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
