"""The Program tab: the file, the steps and their form, the waypoints, the run controls and the program's
path drawn in the scene.

Check (pre-flight), History (the program's saved versions) and Replay go here, one module each.
"""
