"""What every browser gets around the tabs: its session (building the tabs), the operator and viewer roles,
the status line, the activity log, the page's own script and the websocket guard.

The recovery banner (one component reading the controller's and the runner's state and offering the next
action) belongs here, beside the status line.
"""
