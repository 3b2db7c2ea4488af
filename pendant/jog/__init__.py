"""Jogging: hold-to-run motion with a server-side deadman."""

from pendant.jog.deadman import DEADMAN_TIMEOUT_S, Deadman
from pendant.jog.jogger import Jogger
from pendant.jog.targets import JOG_TCP_MAX_VELOCITY_M_S, JogFrame, JogRefused, JogRequest

__all__ = [
    "DEADMAN_TIMEOUT_S",
    "JOG_TCP_MAX_VELOCITY_M_S",
    "Deadman",
    "JogFrame",
    "JogRefused",
    "JogRequest",
    "Jogger",
]
