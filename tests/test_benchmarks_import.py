"""The benchmarks run (README and docs quote their numbers): every name a benchmark imports from the pendant
or the test kit exists. Tests moved into tests/support/ had left four of them importing modules that were
gone (benchmarks/screens.py, cell_check.py, environment.py, history.py), found only when one was run."""

from __future__ import annotations

import ast
import importlib
from pathlib import Path

BENCHMARKS = Path(__file__).resolve().parents[1] / "benchmarks"
OURS = ("pendant", "tests", "benchmarks")


def our_imports(path: Path) -> list[tuple[int, str, str | None]]:
    """(line, module, name or None) of every import of ours in `path`, at any depth (functions too)."""
    found: list[tuple[int, str, str | None]] = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.ImportFrom) and node.level == 0 and node.module is not None:
            if node.module.split(".")[0] in OURS:
                found += [(node.lineno, node.module, alias.name) for alias in node.names]
        elif isinstance(node, ast.Import):
            found += [(node.lineno, a.name, None) for a in node.names if a.name.split(".")[0] in OURS]
    return found


def test_every_name_a_benchmark_imports_from_the_project_exists() -> None:
    missing = []
    for path in sorted(BENCHMARKS.glob("*.py")):
        for line, module, name in our_imports(path):
            try:
                imported = importlib.import_module(module)
            except ImportError as error:
                missing.append(f"{path.name}:{line}: {module}: {error}")
                continue
            if name is not None and not hasattr(imported, name):
                try:
                    importlib.import_module(f"{module}.{name}")  # a submodule
                except ImportError:
                    missing.append(f"{path.name}:{line}: {module} has no {name}")
    assert missing == []
