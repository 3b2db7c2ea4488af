"""The shared 3D scene: the arm, its TCP trail, the cell's obstacles and the tool shape.

A tab's own scene parts (the program's path, the cell's gizmo) live in the tab's package; what several
tabs draw (a ghost of the arm for Plan around or Replay) belongs here.
"""
