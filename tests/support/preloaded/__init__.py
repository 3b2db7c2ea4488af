"""Pendants forked from a preloaded interpreter (`client.py`: popen and run; `__main__.py`: the forker)."""

from .client import popen, run

__all__ = ["popen", "run"]
