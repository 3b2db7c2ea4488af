"""Widgets and page plumbing shared by the tabs: the command runner (and how a refusal is shown), the
controller snapshot, the cell state, HTML helpers, upload limits. Nothing here knows a tab."""
