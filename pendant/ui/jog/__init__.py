"""The Jog tab: the hold-to-run pad and the path recording."""
