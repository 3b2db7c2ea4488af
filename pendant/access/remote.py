"""One operator for the arm: the page's Remote control switch, and API motions kept apart from jogs.

As PolyScope's Local/Remote mode: the operator in the page decides whether API clients may command the arm.
While the switch is off, every API command (anything but a read or a stop) is refused with 403 naming who has
control. While it is on, API commands and the page's hold-to-run jogs take turns, so that a jog's freeze never
drops a command an API client was told was accepted:

- while a jog is held (from the press until the freeze of its release has gone out), API commands are refused;
- a jog press is refused while an API command is being answered, or while the arm is still running the
  motions the API sent (until the arm is seen stopped).

Stops (Freeze) are never refused here. Thread-safe: the API's event loop and the page's threads share it.
"""

from __future__ import annotations

import threading
from collections.abc import Callable

FORBIDDEN = 403
CONFLICT = 409

RemoteListener = Callable[[bool], None]


def msg_remote_off(holder: str) -> str:
    return (
        f"Remote control is off: the arm is commanded from the pendant's page, where {holder} has control "
        "(the operator can turn Remote control on there)"
    )


def msg_jog_held(holder: str) -> str:
    return f"{holder} is jogging the arm in the pendant: send the command again when the jog is released"


MSG_API_MOVING = "An API client's motion is under way: wait for it to finish, or press Freeze"


class RemoteControl:
    """The switch (`enabled`) and the turn-taking between API commands and jogs.

    `holder()` names who has control in the page ("browser #3 (10.0.0.7)", or "nobody").
    """

    def __init__(self, enabled: bool, holder: Callable[[], str] = lambda: "the pendant's operator") -> None:
        self._enabled = enabled
        self.holder = holder
        self._lock = threading.Lock()
        self._in_flight = 0  # API commands sent on and not answered yet
        self._api_answered = False  # an API command was answered since the arm was last seen stopped
        self._jog_held = False
        self._listeners: list[RemoteListener] = []

    @property
    def enabled(self) -> bool:
        return self._enabled

    def on_change(self, listener: RemoteListener) -> None:
        self._listeners.append(listener)

    def set_enabled(self, enabled: bool) -> bool:
        """Turn the switch; True when it changed (listeners are told, outside the lock)."""
        with self._lock:
            changed = self._enabled != enabled
            self._enabled = enabled
        if changed:
            for listener in list(self._listeners):
                listener(enabled)
        return changed

    # --- the API side -------------------------------------------------------------------------------
    def begin_api_command(self) -> tuple[int, str] | None:
        """(status, message) when an API command must be refused; else it counts until `end_api_command`."""
        with self._lock:
            if not self._enabled:
                return FORBIDDEN, msg_remote_off(self.holder())
            if self._jog_held:
                return CONFLICT, msg_jog_held(self.holder())
            self._in_flight += 1
            return None

    def end_api_command(self) -> None:
        with self._lock:
            self._in_flight = max(0, self._in_flight - 1)
            self._api_answered = True

    # --- the page's jogs ----------------------------------------------------------------------------
    def begin_jog(self, arm_running: Callable[[], bool]) -> str | None:
        """Claim the arm for a jog, or the reason why not. `arm_running()` reads the controller (called with
        the claim held, so no API command slips in between the read and the jog)."""
        with self._lock:
            if self._in_flight:
                return MSG_API_MOVING
            self._jog_held = True
            api_answered = self._api_answered
        if not api_answered:
            return None
        try:
            running = arm_running()
        except Exception:
            self.end_jog()
            raise
        if running:
            self.end_jog()
            return MSG_API_MOVING
        with self._lock:
            self._api_answered = False  # seen stopped after every API command answered so far
        return None

    def end_jog(self) -> None:
        with self._lock:
            self._jog_held = False

    @property
    def jog_held(self) -> bool:
        return self._jog_held
