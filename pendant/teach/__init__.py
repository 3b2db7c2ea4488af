"""Teaching by demonstration: record the arm's path while free-driven or jogged, and simplify it."""
