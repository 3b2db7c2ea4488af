"""Where the pendant's files live: the model files (next to the package in a checkout, or under
<prefix>/share in a wheel) and the programs folder."""

from __future__ import annotations

import os
import site
import sys
from pathlib import Path

_HERE = Path(__file__).resolve()
DEFAULT_PROGRAMS_DIR = Path("programs")  # relative to the pendant's working directory
PROGRAMS_DIR_ENV = "PENDANT_PROGRAMS_DIR"
_CHECKOUT_ROOT = _HERE.parent.parent


def _installed_roots() -> tuple[Path, ...]:
    """Where a wheel's data files land: under the prefix it was installed into. That is the one holding
    this package (<prefix>/lib/pythonX.Y/site-packages/pendant), whatever it is (a venv, --user, --prefix),
    then, in case of an unusual layout, the running environment's and the user's."""
    prefixes = [Path(sys.prefix), Path(site.getuserbase())]
    if len(_HERE.parents) > 4:
        prefixes.insert(0, _HERE.parents[4])
    return tuple(dict.fromkeys(prefix / "share" / "pulse-pendant" for prefix in prefixes))


def data_root() -> Path:
    """The folder holding `urdf/` and `assets/` (checkout first, so an editable install sees edits)."""
    candidates = (_CHECKOUT_ROOT, *_installed_roots())
    for root in candidates:
        if (root / "urdf").is_dir():
            return root
    raise FileNotFoundError(f"PULSE model files not found under any of {[str(c) for c in candidates]}")


def urdf_dir() -> Path:
    return data_root() / "urdf"


def assets_dir() -> Path:
    return data_root() / "assets"


def deploy_dir() -> Path:
    """The site's monitoring files: Prometheus, Alertmanager and Grafana configuration."""
    return data_root() / "deploy"


MODEL_NAMES = ("pulse75", "pulse90")


def urdf_path(model: str) -> Path:
    """The URDF of a named model ("pulse75", "pulse90") or a path given as is."""
    if model in MODEL_NAMES:
        return urdf_dir() / f"{model}.urdf"
    path = Path(model)
    if not path.is_file():
        raise FileNotFoundError(f"unknown arm model {model!r}: expected one of {MODEL_NAMES} or a URDF path")
    return path


def programs_dir() -> Path:
    """Where programs are kept: $PENDANT_PROGRAMS_DIR, else ./programs."""
    return Path(os.environ.get(PROGRAMS_DIR_ENV) or DEFAULT_PROGRAMS_DIR)
