"""One operator, many viewers: who may command the arm from a browser, and the panel to take control.

The `ControlDesk` is the server's record (one per pendant); the `CommandRunner`'s gate and the jog panel ask
it before anything reaches the controller, so a viewer is refused by the server, not only greyed out.
On loopback with no token the first browser gets control as it connects (a single user at the machine drives
at once); a pendant with an access token (exposed on a network) gives control only to a browser that
presents the token, from its page URL or typed into the "Access token" field.

Hand-over never leaves nobody in control when somebody may have it: when the operator's browser leaves,
control passes to the browser that has waited longest among those that may take it without asking (any, on
loopback without a token; with a token, those that presented it before).

The control line also carries the Remote control switch (pendant.access.remote): the operator decides whether
API clients may move the arm.
"""

from __future__ import annotations

import html
import threading
from collections.abc import Callable

import viser

from pendant.access import tokens_match
from pendant.access.remote import RemoteControl
from pendant.access.throttle import FailedAttempts
from pendant.eventlog import EventKind, EventLog
from pendant.ui.kit.gui_target import GuiTarget
from pendant.ui.kit.html import inset

MSG_VIEWER = "This browser is a viewer: press Take control first"
MSG_NO_TOKEN = "This pendant needs its access token to take control"
MSG_WRONG_TOKEN = "Wrong access token"
MSG_TOO_MANY = "Too many wrong access tokens from this address: wait a few seconds and try again"

ControlListener = Callable[[int | None], None]
AskListener = Callable[[int, int], None]  # (the browser asking for control, the operator asked)


def browser_name(client_id: int, address: str | None = None) -> str:
    """`browser #3 (10.0.0.7)`: how the event log and the page name a browser."""
    return f"browser #{client_id}" + (f" ({address})" if address else "")


class ControlDesk:
    """Who the operator is (a browser's client id, or None), and the rules to change it. Thread-safe."""

    def __init__(
        self,
        events: EventLog,
        *,
        token: str | None = None,
        auto_grant: bool | None = None,
        attempts: FailedAttempts | None = None,
    ) -> None:
        self._events = events
        self._token = token
        # Wrong tokens typed into pages, per address: shared with the API's guard, so a guesser gains
        # nothing by switching from one to the other. A page is never made to wait: it is told to.
        self._attempts = attempts if attempts is not None else FailedAttempts()
        self._addresses: dict[int, str] = {}
        self._auto_grant = token is None if auto_grant is None else auto_grant
        self._operator: int | None = None
        self._names: dict[int, str] = {}  # in the order they joined
        self._trusted: set[int] = set()  # browsers that presented the token
        self._listeners: list[ControlListener] = []
        self._ask_listeners: list[AskListener] = []
        self._lock = threading.RLock()

    @property
    def needs_token(self) -> bool:
        return self._token is not None

    @property
    def operator(self) -> int | None:
        return self._operator

    def name(self, client_id: int | None) -> str:
        if client_id is None:
            return "nobody"
        return self._names.get(client_id, browser_name(client_id))

    def on_change(self, listener: ControlListener) -> None:
        """`listener(operator)` after every change of operator (called outside the desk's lock)."""
        self._listeners.append(listener)

    def on_ask(self, listener: AskListener) -> None:
        """`listener(asker, operator)` when a browser asks for control that the operator holds."""
        self._ask_listeners.append(listener)

    def is_operator(self, client_id: int | None) -> bool:
        return client_id is not None and client_id == self._operator

    # --- browsers coming and going ------------------------------------------------------------------
    def join(self, client_id: int, address: str | None = None) -> None:
        with self._lock:
            self._names[client_id] = browser_name(client_id, address)
            self._addresses[client_id] = address or "unknown"
            grant = self._auto_grant and self._operator is None
            if grant:
                self._operator = client_id
        if grant:
            self._changed(f"{self.name(client_id)} has control (first browser on this machine)")

    def leave(self, client_id: int) -> bool:
        """Forget a browser; True when it was the operator (control is released, or handed on)."""
        with self._lock:
            name = self.name(client_id)
            was_operator = self._operator == client_id
            self._names.pop(client_id, None)
            self._addresses.pop(client_id, None)
            self._trusted.discard(client_id)
            if was_operator:
                self._operator = self._successor()
            successor = self._operator
        if was_operator and successor is None:
            self._changed(f"{name} left: control released")
        elif was_operator:
            self._changed(f"{name} left: {self.name(successor)} has control")
        return was_operator

    def _successor(self) -> int | None:
        """The browser waiting longest that may have control without asking (called with the lock held)."""
        for client_id in self._names:
            if self._auto_grant or client_id in self._trusted:
                return client_id
        return None

    # --- control ------------------------------------------------------------------------------------
    def take(self, client_id: int, offered_token: str | None = None) -> str | None:
        """Make `client_id` the operator; the reason when refused (refusals are logged)."""
        with self._lock:
            name = self.name(client_id)
            if self._operator == client_id:
                return None
            reason: str | None = None
            asked: int | None = None
            address = self._addresses.get(client_id, "unknown")
            if self._token is not None and not offered_token:
                reason = MSG_NO_TOKEN
            elif self._token is not None and self._attempts.wait_before_check(address) != 0.0:
                reason = MSG_TOO_MANY
            elif self._token is not None and not tokens_match(offered_token, self._token):
                reason = MSG_WRONG_TOKEN
                self._attempts.failed(address)
            elif self._operator is not None:
                reason = f"{self.name(self._operator)} has control: ask them to release it"
                asked = self._operator
            if reason is None:
                self._operator = client_id
                if self._token is not None:
                    self._trusted.add(client_id)
                    self._attempts.succeeded(address)
        if reason is not None:
            self._events.record(EventKind.REFUSED, name, f"Take control refused: {reason}")
            for listener in self._ask_listeners if asked is not None else ():
                listener(client_id, asked)  # the operator is told: they may release it
            return reason
        self._changed(f"{name} took control")
        return None

    def release(self, client_id: int) -> bool:
        """Give up control; False when `client_id` did not have it."""
        with self._lock:
            if self._operator != client_id:
                return False
            self._operator = None
        self._changed(f"{self.name(client_id)} released control")
        return True

    def gate(self, client: viser.ClientHandle | None) -> str | None:
        """The CommandRunner's gate: None for the operator (and for the server itself), else the reason."""
        if client is None or self.is_operator(client.client_id):
            return None
        return self.gate_reason()

    def set_remote(self, client_id: int | None, remote: RemoteControl, enabled: bool) -> str | None:
        """Turn the Remote control switch for the operator `client_id` (None: the server itself); the reason
        when refused (logged)."""
        name = self.name(client_id) if client_id is not None else "pendant"
        if client_id is not None and not self.is_operator(client_id):
            reason = self.gate_reason()
            self._events.record(EventKind.REFUSED, name, f"Remote control refused: {reason}")
            return reason
        if remote.set_enabled(enabled):
            state = (
                "on: API clients may move the arm"
                if enabled
                else "off: only the pendant's page moves the arm"
            )
            self._events.record(EventKind.CONTROL, name, f"Remote control {state}")
        return None

    def gate_reason(self) -> str:
        operator = self._operator
        if operator is None:
            return MSG_VIEWER
        return f"{MSG_VIEWER} ({self.name(operator)} has control)"

    def _changed(self, message: str) -> None:
        self._events.record(EventKind.CONTROL, "pendant", message)
        operator = self._operator
        for listener in list(self._listeners):
            listener(operator)


class ControlPanel:
    """A browser's role line with "Take control" and "Release control" (and "Access token" when needed)."""

    def __init__(
        self,
        target: GuiTarget,
        desk: ControlDesk,
        client_id: int | None,
        url_token: str | None = None,
        remote: RemoteControl | None = None,
    ) -> None:
        self._desk = desk
        self._remote = remote
        self._target = target
        self.client_id = client_id
        self.asked_by: str | None = None  # a browser that asked this operator for control, said on the line
        self.url_token = url_token  # the token the page's URL carried, if any
        self.role = target.gui.add_html("")
        self.token: viser.GuiTextHandle | None = None
        if desk.needs_token:
            hint = "from the page URL" if url_token else "printed when the pendant started"
            self.token = target.gui.add_text("Access token", initial_value="", hint=f"The token {hint}")
        # Both hidden until show() picks the one this browser can use: no flash of the other at load.
        gui = target.gui
        self.take_button = gui.add_button("Take control", icon=viser.Icon.STEERING_WHEEL, visible=False)
        self.release_button = gui.add_button("Release control", icon=viser.Icon.HAND_OFF, visible=False)
        self.take_button.on_click(lambda event: self.take(event.client))
        self.release_button.on_click(lambda event: self.release())
        self.remote: viser.GuiCheckboxHandle | None = None
        if remote is not None:
            self.remote = target.gui.add_checkbox(
                "Remote control",
                initial_value=remote.enabled,
                hint="On: API clients (scripts, the SDK) may move the arm. Off: only this page may.",
            )
            self.remote.on_update(lambda event: self.switch_remote(event.client))
        self.show(desk.operator)

    def offered_token(self) -> str | None:
        typed = self.token.value.strip() if self.token is not None else ""
        return typed or self.url_token

    def take(self, client: viser.ClientHandle | None = None) -> str | None:
        """Ask for control with the typed token (or the URL's); the reason when refused."""
        if self.client_id is None:
            return "Not a browser"
        reason = self._desk.take(self.client_id, self.offered_token())
        if reason is not None and client is not None:
            client.add_notification(
                title="Take control refused", body=reason, color="red", auto_close_seconds=8.0
            )
        return reason

    def release(self) -> bool:
        return self.client_id is not None and self._desk.release(self.client_id)

    def switch_remote(self, client: viser.ClientHandle | None = None) -> str | None:
        """The operator turned the Remote control switch; a viewer's change is refused and undone."""
        if self.remote is None or self._remote is None:
            return None
        wanted = bool(self.remote.value)
        if wanted == self._remote.enabled:
            return None
        reason = self._desk.set_remote(self.client_id, self._remote, wanted)
        if reason is not None:
            self.remote.value = self._remote.enabled
            if client is not None:
                client.add_notification(
                    title="Remote control refused", body=reason, color="red", auto_close_seconds=8.0
                )
        return reason

    def show_remote(self, enabled: bool) -> None:
        if self.remote is not None and self.remote.value != enabled:
            self.remote.value = enabled

    def asked(self, name: str) -> None:
        """`name` asked for the control this browser holds: said on its line, and in a notification."""
        self.asked_by = name
        self.show(self._desk.operator)
        if isinstance(self._target, viser.ClientHandle):
            self._target.add_notification(
                title=f"{name} asks for control",
                body="Release control to hand it over.",
                color="yellow",
                auto_close_seconds=15.0,
            )

    def show(self, operator: int | None) -> None:
        """One line and one button (the one this browser can use): the room above the tabs is the pad's."""
        mine = operator is not None and operator == self.client_id
        if not mine:
            self.asked_by = None  # control changed hands: the question is answered
        if mine and self.asked_by is not None:
            text = (
                '<b style="color:#237032">You have control</b> · '
                f"<b>{html.escape(self.asked_by)} asks for control</b>"
            )
        elif mine:
            text = '<b style="color:#237032">You have control</b> (operator)'
        elif operator is None:
            text = "<b>Viewing</b> · nobody has control"
        else:
            text = f"<b>Viewing</b> · {html.escape(self._desk.name(operator))} has control"
        you = html.escape(self._desk.name(self.client_id)) if self.client_id is not None else ""
        title = f' title="You are {you}"' if you else ""
        one_line = "font-size:0.85em;white-space:nowrap;overflow:hidden;text-overflow:ellipsis"
        # On a phone, "You have control (operator)" folds away (Release control under it says as much).
        fold = ' class="phone-fold"' if mine and self.asked_by is None else ""
        line = f'<div style="{one_line}"{title}{fold}>'
        content = inset(f"{line}{text}</div>")
        if self.role.content != content:
            self.role.content = content
        for button, usable in ((self.take_button, not mine), (self.release_button, mine)):
            if button.disabled == usable:
                button.disabled = not usable
            if button.visible != usable:
                button.visible = usable
