"""Finding 2 of the audit in a real browser: a web page from another origin (a tiny http.server on another
loopback port) that the operator happens to open cannot change or drive the arm, and a DNS-rebound host name
(Chromium told that evil.example is 127.0.0.1) is refused on both ports. The pendant runs as `make run` does
it: the simulator on loopback, no token."""

from __future__ import annotations

import contextlib
import http.server
import json
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest
import viser
from playwright.sync_api import Browser, Playwright

from tests.support.browser_pages import ARTIFACTS
from tests.support.chromium import CHROMIUM, CHROMIUM_ARGS
from tests.support.launchers import Pendant
from tests.support.shared_pendants import NOT_REAL_TIME

# Not about real time: the shared pendant's simulator runs faster (tests/browser/conftest.py).
pytestmark = pytest.mark.time_scale(NOT_REAL_TIME)

RESULT_TIMEOUT_MS = 15_000
REBOUND = "evil.example"
TOOL = {"name": "evil", "radius": 0.0, "position": {"point": {"x": 0, "y": 0, "z": 0.5}}}
BASE = {"point": {"x": 0.3, "y": 0, "z": 0}, "rotation": {"roll": 0, "pitch": 0, "yaw": 0}}
POSE = {"angles": [40.0, -90.0, 90.0, -90.0, -90.0, 0.0]}

ATTACK_PAGE = """<!doctype html><html><body><h1>Cute cats</h1>
<iframe id="pendant" width="800" height="600"></iframe><script>
window.done = (async () => {{
  const frame = document.getElementById("pendant");
  const framed = new Promise((resolve) => {{ frame.onload = resolve; }});
  frame.src = "http://127.0.0.1:{ui_port}/";  // clickjacking: the pendant under a page of ours
  await framed;
  const api = "http://127.0.0.1:{api_port}";
  const sent = [];
  const post = async (method, path, body) => {{
    try {{
      await fetch(api + path, {{method, mode: "no-cors", headers: {{"Content-Type": "text/plain"}}, body}});
      sent.push(path);
    }} catch (error) {{ sent.push(path + " failed"); }}
  }};
  await post("POST", "/tool", {tool});
  await post("POST", "/base", {base});
  await post("POST", "/poses/run?speed=100", {pose});  // a motion, by the one method no-cors allows
  const socket = await new Promise((resolve) => {{
    const ws = new WebSocket("ws://127.0.0.1:{ui_port}/", ["viser-v{viser_version}"]);
    ws.onopen = () => {{ ws.close(); resolve("open"); }};
    ws.onerror = () => resolve("refused");
  }});
  return {{sent, socket}};
}})();
</script></body></html>"""


@contextlib.contextmanager
def attack_site(root: Path, api_port: int, ui_port: int) -> Iterator[str]:
    """A page of another origin (another loopback port), as any site the operator might open."""
    page = ATTACK_PAGE.format(
        api_port=api_port,
        ui_port=ui_port,
        viser_version=viser.__version__,
        tool=json.dumps(json.dumps(TOOL)),
        base=json.dumps(json.dumps(BASE)),
        pose=json.dumps(json.dumps([POSE])),
    )
    (root / "index.html").write_text(page)

    class Quiet(http.server.SimpleHTTPRequestHandler):
        def __init__(self, *args: Any, **kwargs: Any) -> None:
            super().__init__(*args, directory=str(root), **kwargs)

        def log_message(self, format: str, *args: Any) -> None:
            pass

    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), Quiet)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}/"
    finally:
        server.shutdown()
        server.server_close()


@pytest.fixture(scope="module")
def browser(playwright: Playwright) -> Iterator[Browser]:
    """Chromium that resolves evil.example to 127.0.0.1, as a rebinding attacker's DNS would make it."""
    chromium = playwright.chromium.launch(
        executable_path=CHROMIUM, args=[*CHROMIUM_ARGS, f"--host-resolver-rules=MAP {REBOUND} 127.0.0.1"]
    )
    yield chromium
    chromium.close()


def state(pendant: Pendant) -> tuple[object, ...]:
    api = pendant.api
    return (api.get("/tool").json(), api.get("/base").json(), pendant.pose(), pendant.status())


def test_a_page_from_another_origin_cannot_change_or_drive_the_arm(
    browser: Browser, pendant: Pendant, tmp_path: Path
) -> None:
    before = state(pendant)
    api_port = int(str(pendant.api.base_url).rsplit(":", 1)[1].rstrip("/"))
    with attack_site(tmp_path, api_port, pendant.ui_port) as url:
        page = browser.new_page()
        try:
            page.goto(url)
            page.wait_for_function("() => window.done !== undefined", timeout=RESULT_TIMEOUT_MS)
            outcome = page.evaluate("() => window.done")  # awaits the attack's promise
            framed_url = page.frames[1].url  # a refused frame shows the browser's error page instead
            page.screenshot(path=str(ARTIFACTS / "cross-origin-attack.png"))
        finally:
            page.close()
    assert outcome["sent"] == ["/tool", "/base", "/poses/run?speed=100"]  # the browser did send them
    assert not framed_url.startswith(f"http://127.0.0.1:{pendant.ui_port}"), (
        "the pendant let itself be framed"
    )
    assert outcome["socket"] == "refused", "a foreign page's websocket was accepted (it would be a browser)"
    assert state(pendant) == before, "a foreign page changed the tool, the base or the arm"


def test_a_dns_rebound_host_name_is_refused_on_both_ports(browser: Browser, pendant: Pendant) -> None:
    api_port = int(str(pendant.api.base_url).rsplit(":", 1)[1].rstrip("/"))
    page = browser.new_page()
    try:
        for port, path in ((pendant.ui_port, "/"), (api_port, "/pose")):
            response = page.goto(f"http://{REBOUND}:{port}{path}")
            assert response is not None and response.status == 403, (port, path)
            assert "not allowed" in page.content()
        page.screenshot(path=str(ARTIFACTS / "dns-rebinding-refused.png"))
        # The pendant's own page, by a loopback name, still loads and connects.
        page.goto(f"http://localhost:{pendant.ui_port}/")
        page.get_by_role("button", name="Freeze").wait_for(timeout=30_000)
    finally:
        page.close()
    assert httpx.get(f"http://127.0.0.1:{api_port}/pose").status_code == 200
