"""Issue 35: pressing and releasing a jog button makes the page compile no shader. In software WebGL a shader
program's compile waits for the frame being drawn (a 50-90 ms long task on the main thread, at the moment
of a press or a release); three.js compiles again whatever the page unmounts and shows once more. The
drag-to-target gizmo used to be hidden (unmounted) at each press and shown at each release, and the TCP
trail made at the first motion: four programs a press and release. Counted in the page: the WebGL
programs created (three.js makes one per compile) during two holds, after a first one and once the page
has settled."""

from __future__ import annotations

import time
from collections.abc import Iterator
from typing import Any

import pytest

from tests.support.jog_measure import mouse_hold, open_as_operator
from tests.support.launchers import Pendant
from tests.support.shared_pendants import NOT_REAL_TIME

# Not about real time: the shared pendant's simulator runs faster (tests/browser/conftest.py).
pytestmark = pytest.mark.time_scale(NOT_REAL_TIME)

COUNT_PROGRAMS = """
window.__programs = 0;
const createProgram = WebGL2RenderingContext.prototype.createProgram;
WebGL2RenderingContext.prototype.createProgram = function () {
  window.__programs += 1;
  return createProgram.call(this);
};
"""
HOLD_S = 1.5
SETTLED_S = 3.0  # no program made for this long: the page's start-up compiles are done
SETTLE_WITHIN_S = 90.0
AFTER_RELEASE_S = 2.0  # the gizmo back at the TCP, drawn
MIN_MOVED_DEG = 1.0


def programs(page: Any) -> int:
    return int(page.evaluate("window.__programs"))


def settled_programs(page: Any) -> int:
    """The count once no program has been made for SETTLED_S (the page drew its view, with the arm)."""
    deadline = time.monotonic() + SETTLE_WITHIN_S
    count, since = programs(page), time.monotonic()
    while time.monotonic() - since < SETTLED_S:
        assert time.monotonic() < deadline, "the page kept compiling shaders after it loaded"
        time.sleep(0.25)
        now = programs(page)
        if now != count:
            count, since = now, time.monotonic()
    assert count > 0, "the page drew no 3D view"
    return count


@pytest.fixture
def operator(browser: Any, pendant: Pendant) -> Iterator[Any]:
    context = browser.new_context(viewport={"width": 1400, "height": 900})
    page = context.new_page()
    page.add_init_script(COUNT_PROGRAMS)
    open_as_operator(page, pendant.ui_url)
    yield page
    context.close()


def hold(page: Any, pendant: Pendant, label: str) -> None:
    held = mouse_hold(page, pendant.api, label, HOLD_S)
    assert held.moved_deg > MIN_MOVED_DEG, f"the {label} hold did not jog the arm"


def test_a_jog_press_and_release_compile_no_shader(operator: Any, pendant: Pendant) -> None:
    # One hold first, and the page left to settle: on a loaded machine its start-up compiles (the arm's
    # meshes, what the first motion shows) can come seconds apart, and none of them is a press's.
    hold(operator, pendant, "J1+")
    before = settled_programs(operator)
    for label in ("J1-", "J1+"):
        hold(operator, pendant, label)
    time.sleep(AFTER_RELEASE_S)
    made = programs(operator) - before
    assert made == 0, f"{made} shader programs compiled during two jog holds"
