"""docs/architecture.md's diagram is the import graph: every package, every import between two of them."""

from __future__ import annotations

from pathlib import Path

from tests.support.import_graph import arrows, diagram_edges, mermaid_block, package_edges

ARCHITECTURE = Path(__file__).parents[2] / "docs" / "architecture.md"


def test_the_diagram_has_every_package_and_every_import_between_them() -> None:
    packages, imports = package_edges()
    drawn_nodes, drawn = diagram_edges(mermaid_block(ARCHITECTURE.read_text()))
    differences = [
        *(f"package not drawn: {name}" for name in sorted(packages - drawn_nodes)),
        *(f"drawn, not a package: {name}" for name in sorted(drawn_nodes - packages)),
        *(f"import not drawn: {a} --> {b}" for a, b in sorted(imports - drawn)),
        *(f"drawn, not imported: {a} --> {b}" for a, b in sorted(drawn - imports)),
    ]
    assert differences == [], (
        "docs/architecture.md's diagram and the code differ:\n"
        + "\n".join(differences)
        + "\nthe arrows as the code has them:\n"
        + "\n".join(arrows(imports))
    )


def test_a_drawn_arrow_is_read_as_mermaid_draws_it() -> None:
    """`a --> b & c` is two arrows; labels are not names; a chain draws each step."""
    nodes, edges = diagram_edges('    a["a: the top --> no arrow"] --> b & c\n    b --> c --> d\n')
    assert nodes == {"a", "b", "c", "d"}
    assert edges == {("a", "b"), ("a", "c"), ("b", "c"), ("c", "d")}
