"""The pulse_sim plugin used as a user would: a test project in a temp folder, run by pytest in a subprocess
(plain, and with pytest-xdist), talking to the fixture's simulator over real HTTP."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

import pytest

from tests.support.launchers import REPO_ROOT
from tests.support.user_project import port_is_closed, run_project

pytestmark = pytest.mark.slow

USER_TESTS = Path(__file__).with_name("user_tests.py").read_text(encoding="utf-8")
INI = "[pytest]\n"
# Every test in user_tests.py but the one that must fail (the one erring at teardown passes its call).
EXPECTED_PASSED = 19


def outcome(output: str, word: str) -> int:
    found = re.search(rf"(\d+) {word}", output)
    return int(found.group(1)) if found else 0


def urls_used(folder: Path) -> dict[str, set[str]]:
    """worker -> the simulator URLs its tests were given."""
    used: dict[str, set[str]] = {}
    for path in (folder / "urls").glob("*.txt"):
        used.setdefault(path.name.split("-")[0], set()).add(path.read_text())
    return used


def test_a_user_project_with_every_fault_and_scripted_event(tmp_path: Path) -> None:
    run = run_project(tmp_path, {"pytest.ini": INI, "test_robot.py": USER_TESTS})
    output = run.stdout + run.stderr
    assert outcome(output, "passed") == EXPECTED_PASSED, output
    # The test whose robot code meets the scripted ERROR fails, with the controller's own message.
    assert outcome(output, "failed") == 1, output
    assert "FAILED test_robot.py::test_user_code_meets_the_scripted_error" in output
    assert "500 Internal Server Error" in output
    # A waypoint the run does not have is an error at teardown, saying why.
    assert outcome(output, "error") == 1, output
    assert "at waypoint 5: error: the run has only 1 waypoint" in output
    urls = urls_used(tmp_path)
    assert len(urls["main"]) == 2  # one simulator per model (pulse75, pulse90) for the whole session
    assert all(port_is_closed(url) for url in urls["main"])


def test_with_xdist_each_worker_has_its_own_simulator(tmp_path: Path) -> None:
    many = "\n".join(
        f"def test_{i}(pulse_sim, api):\n    assert motion_status(api) == 'IDLE'\n" for i in range(8)
    )
    files = {"pytest.ini": INI, "test_robot.py": USER_TESTS + "\n\n" + many}
    run = run_project(tmp_path, files, "-n", "2", "-k", "test_ and not meets and not does_not_have")
    output = run.stdout + run.stderr
    assert run.returncode == 0, output
    assert outcome(output, "passed") == EXPECTED_PASSED - 1 + 8, output
    urls = urls_used(tmp_path)
    assert sorted(urls) == ["gw0", "gw1"]
    assert not urls["gw0"] & urls["gw1"]  # each worker its own simulators
    assert all(port_is_closed(url) for worker in urls.values() for url in worker)


def test_cell_option_puts_the_cell_in_place_before_each_test(tmp_path: Path) -> None:
    cell = '{"obstacles": [{"obstacleType": "BOX", "name": "table", "sides": {"x": 1, "y": 1, "z": 0.1}, '
    cell += '"centerPosition": {"point": {"x": 0.6, "y": 0, "z": 0.05}, "rotation": '
    cell += '{"roll": 0, "pitch": 0, "yaw": 0}}}]}'
    test = (
        "def test_cell(pulse_sim):\n"
        "    import httpx\n"
        "    names = [o['name'] for o in httpx.get(pulse_sim.url + '/environment').json()]\n"
        "    assert names == ['table']\n"
    )
    files = {"pytest.ini": INI, "cell.json": cell, "test_cell.py": test}
    run = run_project(tmp_path, files, "--pulse-sim-cell", "cell.json")
    output = run.stdout + run.stderr
    assert outcome(output, "passed") == 1, output


def test_the_entry_point_makes_the_fixture_available_once_installed(tmp_path: Path) -> None:
    project = tomllib.loads((REPO_ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    entry_points = project["project"]["entry-points"]["pytest11"]
    assert entry_points == {"pendant.testing": "pendant.testing"}
    # What installing the package writes (the entry points of its metadata), without touching the venv.
    site = tmp_path / "site"
    metadata = site / "pulse_pendant_installed-0.1.dist-info"
    metadata.mkdir(parents=True)
    (metadata / "METADATA").write_text("Metadata-Version: 2.1\nName: pulse-pendant-installed\nVersion: 0.1\n")
    lines = [f"{name} = {target}" for name, target in entry_points.items()]
    (metadata / "entry_points.txt").write_text("[pytest11]\n" + "\n".join(lines) + "\n")
    test = "def test_url(pulse_sim):\n    assert pulse_sim.url.startswith('http://127.0.0.1:')\n"
    files = {"pytest.ini": INI, "test_url.py": test}
    project_dir = tmp_path / "project"
    project_dir.mkdir()
    for by_name in (False, True):  # installed alone, and installed plus -p (registered once, not twice)
        run = run_project(project_dir, files, by_name=by_name, site=site)
        assert run.returncode == 0, run.stdout + run.stderr
        assert "1 passed" in run.stdout
