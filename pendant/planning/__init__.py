"""Planning ahead of the arm: the digital twin, pre-flight checks of programs, the Run gate, the planner."""
