"""The test kit's rule (docs/development.md): what tests share lives in tests/support/; a test module never
imports another test module, a conftest or a helper kept beside the tests."""

from __future__ import annotations

import ast
from pathlib import Path

TESTS = Path(__file__).parent
KIT = "tests.support"


def module_name(path: Path) -> str:
    parts = path.relative_to(TESTS.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def imported(path: Path) -> list[tuple[int, str]]:
    """(line, module) of every import of a tests module in `path`, relative imports resolved."""
    package = module_name(path) if path.name == "__init__.py" else module_name(path).rpartition(".")[0]
    found = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                up = package.split(".")[: len(package.split(".")) - (node.level - 1)]
                base = ".".join([*up, base] if base else up)
            names = [base]
        else:
            continue
        found += [(node.lineno, name) for name in names if name == "tests" or name.startswith("tests.")]
    return found


def test_tests_import_only_the_kit_from_tests() -> None:
    outside_kit = [
        f"{path.relative_to(TESTS.parent)}:{line}: imports {name}"
        for path in sorted(TESTS.rglob("*.py"))
        if not path.is_relative_to(TESTS / "support")
        for line, name in imported(path)
        if name != KIT and not name.startswith(f"{KIT}.")
    ]
    assert outside_kit == [], "move what they share to tests/support/:\n" + "\n".join(outside_kit)


def test_the_kit_imports_no_test() -> None:
    kit = TESTS / "support"
    outside = [
        f"{path.relative_to(TESTS.parent)}:{line}: imports {name}"
        for path in sorted(kit.rglob("*.py"))
        for line, name in imported(path)
        if name != KIT and not name.startswith(f"{KIT}.")
    ]
    assert outside == []
