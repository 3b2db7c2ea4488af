"""Stand-ins for a browser: what the pendant uses of a viser ClientHandle, and viser's way of calling back."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import viser

from pendant.ui.kit.typed_field import TypedField

OPERATOR, VIEWER = 1, 2  # client ids: on loopback the first browser to join is the operator


@dataclass
class FakeBrowser:
    """Its id, and the notifications and downloads the pendant sends it (kept for the test)."""

    client_id: int
    notifications: list[str] = field(default_factory=list)
    downloads: list[tuple[str, bytes]] = field(default_factory=list)

    def add_notification(self, *, title: str, body: str, **_: object) -> None:
        self.notifications.append(f"{title}: {body}")

    def send_file_download(self, filename: str, content: bytes, **_: object) -> None:
        self.downloads.append((filename, content))


def event(handle: Any, browser: FakeBrowser) -> viser.GuiEvent:
    return viser.GuiEvent(client=browser, client_id=browser.client_id, target=handle)  # type: ignore[arg-type]  # a fake client for viser's


def committed(handle: Any, value: Any) -> tuple[Any, Any]:
    """A typed field (pendant/ui/kit/typed_field.py) gets the text the page commits: its text box, and a
    number as typed ("80.0"), a vector as "x, y, z", a string as it is."""
    if not isinstance(handle, TypedField):
        return handle, value
    if isinstance(value, tuple | list):
        value = ", ".join(repr(float(v)) for v in value)
    elif value is not None and not isinstance(value, str):
        value = repr(float(value))
    return handle.handle, value


def fire(handle: Any, browser: FakeBrowser, value: Any = None) -> None:
    """What viser does when a browser clicks or edits `handle`: set the value, call the callbacks once."""
    handle, value = committed(handle, value)
    if value is not None:
        handle._impl.value = value  # not `handle.value = ...`: that calls back as from Python (client None)
    for callback in list(handle._impl.update_cb):
        callback(event(handle, browser))
