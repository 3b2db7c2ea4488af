"""The wheel carries the arm models, and the installed package finds them wherever it was installed to."""

from __future__ import annotations

import importlib.util
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

import pytest

from pendant.paths import MODEL_NAMES, data_root

pytestmark = pytest.mark.slow

REPO = Path(__file__).resolve().parents[1]
SHIPPED = ("pyproject.toml", "README.md", "pendant", "urdf", "assets")


def pip(*args: str) -> None:
    # Offline: --no-deps, and the build backend is the venv's own (no build isolation, no download).
    subprocess.run([sys.executable, "-m", "pip", "-q", *args], check=True, capture_output=True)


def test_a_wheel_installed_to_another_prefix_finds_its_model_files(tmp_path: Path) -> None:
    source = tmp_path / "source"  # a copy: building in the checkout would leave build/ and egg-info there
    source.mkdir()
    for name in SHIPPED:
        copy = shutil.copytree if (REPO / name).is_dir() else shutil.copy
        copy(REPO / name, source / name)
    pip("wheel", "--no-deps", "--no-build-isolation", "--wheel-dir", str(tmp_path / "dist"), str(source))
    (wheel,) = (tmp_path / "dist").glob("pulse_pendant-*.whl")
    prefix = tmp_path / "prefix"
    # --ignore-installed: otherwise pip first uninstalls the pendant this test suite runs from.
    pip("install", "--no-deps", "--ignore-installed", "--prefix", str(prefix), str(wheel))

    # The installed pendant/paths.py, loaded on its own: `import pendant` here would find the checkout.
    site_packages = Path(sysconfig.get_path("purelib", vars={"base": str(prefix)}))
    spec = importlib.util.spec_from_file_location("installed_paths", site_packages / "pendant" / "paths.py")
    assert spec is not None and spec.loader is not None
    installed = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(installed)

    root = installed.data_root()
    assert root == prefix / "share" / "pulse-pendant"
    for model in MODEL_NAMES:
        assert (
            installed.urdf_path(model).read_bytes() == (data_root() / "urdf" / f"{model}.urdf").read_bytes()
        )
    shipped_meshes = sorted(p.name for p in (data_root() / "assets").iterdir())
    assert sorted(p.name for p in installed.assets_dir().iterdir()) == shipped_meshes
    # ... and the environment the suite runs in still has its own pendant (pip left it installed).
    subprocess.run([sys.executable, "-c", "import pendant"], cwd=tmp_path, check=True)
