"""The Cell tab: obstacles (listed, edited, dragged by their gizmo) and cell files."""
