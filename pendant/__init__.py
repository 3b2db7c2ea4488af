"""PULSE teach pendant: a browser-based 3D pendant and a PULSE controller simulator."""

__version__ = "0.1.0"
