"""The Target tab: a goal set by sliders or by the gizmo, checked before it is sent, and hand guiding.

Plan around (a collision-free route to the target) goes here as its own module.
"""
