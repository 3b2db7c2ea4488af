"""The pendant's web page, one sub-package per tab.

Layers, top to bottom (import-linter checks them, see pyproject.toml):
- `app`: PendantUI, the wiring: one viser server, the refresh loop, the sessions.
- `page/`: what every browser gets around the tabs: its session, roles (operator or viewer), the status line,
  the activity log, the page's script and the websocket guard.
- one package per tab: `jog/`, `target/`, `program/`, `cell/`, `robot/` (Robot, IO, Simulator),
  `dashboard/`. A tab owns its panel, its scene parts and its refusal wording; tabs never import each
  other, they meet through the session, the controller and the command runner.
- `scene/`: the shared 3D scene (the arm, its TCP trail, the cell's obstacles and tool shape).
- `kit/`: widgets and plumbing any tab may use (the command runner, the snapshot, HTML helpers).

A new tab is a new package beside these; a page-wide component (the recovery banner) goes in `page/`.
"""
