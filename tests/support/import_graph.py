"""The pendant's packages and which imports which (grimp, as import-linter builds it), and the arrows of a
mermaid flowchart, so docs/architecture.md's diagram can be checked against the code.

`python -m tests.support.import_graph` prints the arrows the diagram should have, one line per package.
"""

from __future__ import annotations

import itertools
import re
from collections import defaultdict

import grimp

ROOT = "pendant"
# Left out of the diagram: the root package holds only __version__, and __main__ only runs the CLI.
NOT_DRAWN = {ROOT, f"{ROOT}.__main__"}

Edges = set[tuple[str, str]]


def _top(module: str) -> str:
    parts = module.split(".")
    return ".".join(parts[:2])


def package_edges() -> tuple[set[str], Edges]:
    """The top-level packages and modules of `pendant` (short names) and the (importer, imported) pairs
    between two of them, type-checking imports included (as the import contracts count them)."""
    graph = grimp.build_graph(ROOT, exclude_type_checking_imports=False)
    nodes = {_top(m) for m in graph.modules} - NOT_DRAWN
    edges: Edges = set()
    for module in graph.modules:
        for imported in graph.find_modules_directly_imported_by(module):
            a, b = _top(module), _top(imported)
            if a != b and a in nodes and b in nodes:
                edges.add((a, b))
    short = len(ROOT) + 1
    return {n[short:] for n in nodes}, {(a[short:], b[short:]) for a, b in edges}


_NODE = r"[A-Za-z_][A-Za-z0-9_]*"
_LABELLED = re.compile(rf"({_NODE})\s*\[")


def mermaid_block(markdown: str) -> str:
    """The first ```mermaid block of `markdown`."""
    match = re.search(r"```mermaid\n(.*?)```", markdown, re.S)
    assert match is not None, "no ```mermaid block"
    return match.group(1)


def diagram_edges(block: str) -> tuple[set[str], Edges]:
    """The nodes and arrows of a mermaid flowchart written as `a["label"] --> b & c`, `a --> b`."""
    nodes: set[str] = set()
    edges: Edges = set()
    for raw in block.splitlines():
        line = re.sub(r'\["[^"]*"\]', "", raw).strip()  # labels out: what is left is names and arrows
        if not line or line.startswith(("flowchart", "graph", "%%")):
            continue
        sides = [side.strip() for side in line.split("-->")]
        groups = [{name.strip() for name in side.split("&")} for side in sides]
        for group in groups:
            nodes |= group
        for sources, targets in itertools.pairwise(groups):
            edges |= {(a, b) for a in sources for b in targets}
    return nodes, edges


def arrows(edges: Edges) -> list[str]:
    """One mermaid line per importer: `a --> b & c`, sorted."""
    by_source: dict[str, list[str]] = defaultdict(list)
    for a, b in sorted(edges):
        by_source[a].append(b)
    return [f"    {a} --> {' & '.join(targets)}" for a, targets in sorted(by_source.items())]


if __name__ == "__main__":
    _, found = package_edges()
    print("\n".join(arrows(found)))
