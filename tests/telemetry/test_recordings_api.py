"""Recordings from scripts, over real HTTP on a real `pendant`: start (named or not), refusals with their
reason, stop; the files are the Dashboard's (the recordings folder of the data folder), readable by mcap."""

from __future__ import annotations

import json
import time
from pathlib import Path

import httpx
from mcap.reader import make_reader

from tests.support.launchers import running_pendant, running_pendant_ui
from tests.support.waiting import SAFETY_NET_S

REACHABLE_POSE = {"angles": [10.0, -90.0, 90.0, -90.0, -90.0, 0.0]}
RECORD_S = 1.5  # long enough for a dozen samples at 10 Hz


def joint_messages(mcap: Path) -> list[dict[str, object]]:
    with mcap.open("rb") as stream:
        return [
            json.loads(message.data)
            for _, channel, message in make_reader(stream).iter_messages()
            if channel.topic == "/joints"
        ]


def test_a_script_records_a_move_and_gets_each_refusal_with_its_reason(tmp_path: Path) -> None:
    with running_pendant("--data", str(tmp_path)) as base:
        api = httpx.Client(base_url=base, timeout=SAFETY_NET_S)
        started = api.post("/pendant/recordings", json={"name": "pick-test"})
        assert started.status_code == 201, started.text
        assert started.json()["name"] == "pick-test" and started.json()["running"] is True

        again = api.post("/pendant/recordings", json={"name": "other"})
        assert again.status_code == 409 and "'pick-test' is running" in again.json(), again.text
        for name in ("../escape", ".hidden", "a/b", "x" * 65, "clip.mcap", ""):
            refused = api.post("/pendant/recordings", json={"name": name})
            assert refused.status_code in (400, 409), (name, refused.text)
        assert api.post("/pendant/recordings", json={"name": "../escape"}).status_code == 409, (
            "one recording at a time comes first"
        )
        assert api.post("/pendant/recordings", content=b"{not json").status_code == 400
        assert api.put("/pose?speed=50", json=REACHABLE_POSE).status_code == 200
        time.sleep(RECORD_S)
        wrong = api.post("/pendant/recordings/other/stop")
        assert wrong.status_code == 409 and "'other' is not running" in wrong.json(), wrong.text
        stopped = api.post("/pendant/recordings/pick-test/stop")
        assert stopped.status_code == 200, stopped.text
        assert stopped.json()["files"] == ["pendant-pick-test.mcap", "pendant-pick-test.csv"]
        assert stopped.json()["samples"] >= 5
        none_running = api.post("/pendant/recordings/pick-test/stop")
        assert none_running.status_code == 409 and "No recording is running" in none_running.json()

        # Nothing runs now: the name checks answer for themselves.
        bad = api.post("/pendant/recordings", json={"name": "../escape"})
        assert bad.status_code == 400 and "Bad recording name" in bad.json(), bad.text
        taken = api.post("/pendant/recordings", json={"name": "pick-test"})
        assert taken.status_code == 409 and "already exists" in taken.json(), taken.text
        unknown = api.post("/pendant/recordings", json={"name": "x", "speed": 3})
        assert unknown.status_code == 400 and "Bad body" in unknown.json(), unknown.text
        unnamed = api.post("/pendant/recordings")
        assert unnamed.status_code == 201, unnamed.text
        listed = api.get("/pendant/recordings").json()
        assert [r["running"] for r in listed if r["name"] == "pick-test"] == [False]
        assert [r["name"] for r in listed if r["running"]] == [unnamed.json()["name"]]
    folder = tmp_path / "recordings"
    angles = [message["position_deg"] for message in joint_messages(folder / "pendant-pick-test.mcap")]
    assert len(angles) >= 5
    assert abs(angles[-1][0] - 10.0) < 0.5, "the move is in the file: J1 ends at 10°"  # type: ignore[index]
    assert (folder / "pendant-pick-test.csv").read_text().count("\n") >= 6
    assert (folder / f"pendant-{unnamed.json()['name']}.mcap").exists(), (
        "a running one is finished on SIGTERM"
    )
    assert joint_messages(folder / f"pendant-{unnamed.json()['name']}.mcap")


def test_the_routes_are_in_the_openapi_document(tmp_path: Path) -> None:
    with running_pendant("--data", str(tmp_path)) as base:
        paths = httpx.get(f"{base}/openapi.json", timeout=SAFETY_NET_S).json()["paths"]
    assert "post" in paths["/pendant/recordings"] and "get" in paths["/pendant/recordings"]
    start = paths["/pendant/recordings"]["post"]
    assert start["requestBody"]["content"]["application/json"]["schema"]["properties"]["name"]
    assert set(start["responses"]) >= {"201", "400", "409"}
    assert "post" in paths["/pendant/recordings/{name}/stop"]


def test_with_the_page_the_api_records_with_the_dashboards_recorder(tmp_path: Path) -> None:
    with running_pendant_ui(env={"PENDANT_DATA_DIR": str(tmp_path)}) as pendant:
        assert pendant.api.post("/pendant/recordings", json={"name": "from-api"}).status_code == 201
        time.sleep(RECORD_S)
        stopped = pendant.api.post("/pendant/recordings/from-api/stop")
        assert stopped.status_code == 200 and stopped.json()["samples"] >= 5, stopped.text
        assert stopped.json()["folder"] == str(tmp_path / "recordings")
    assert joint_messages(tmp_path / "recordings" / "pendant-from-api.mcap")
