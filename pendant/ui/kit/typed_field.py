"""Numbers the operator types, used exactly as typed.

Every numeric field of the panel is a text box (viser's number and slider boxes parse, clamp and round each
keystroke, and the server's echo of one keystroke overwrote the next). The page's script (typed_fields.js)
sends a box's text only when the operator commits it (Enter, or leaving the box) and keeps the server's
updates out of a box that has focus or an edit not yet committed. Here the committed text is read as it
is: an empty box, text that is not a number or a value out of range is marked with the reason under the
box, and reading it raises FieldInvalid with that reason, so the action that needs it is refused (never an
old value used silently).
"""

from __future__ import annotations

import html
import math
from collections.abc import Callable, Sequence

import viser

from pendant.controller import BadRequest
from pendant.ui.kit.html import inset

MAX_TEXT_CHARS = 40  # a number is short: a longer entry is refused, not parsed
MARK_STYLE = "font-size:0.8em;color:#c92a2a;margin:-0.35em 0 0.4em 0"


class FieldInvalid(BadRequest, ValueError):
    """A field the action needs holds no usable number; the message names the field and says why."""


def format_number(value: float, decimals: int) -> str:
    """How the server shows a value in a field: no trailing zeros ("20", "-69.3")."""
    text = f"{value:.{decimals}f}"
    if "." in text:
        text = text.rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def parse_number(text: str, low: float | None, high: float | None, *, integer: bool = False) -> float:
    """The number `text` says, or ValueError with the reason the operator is shown."""
    text = text.strip()
    if not text:
        raise ValueError("empty: type a number")
    if len(text) > MAX_TEXT_CHARS:
        raise ValueError("too long for a number")
    try:
        value = float(text)
    except ValueError:
        raise ValueError(f"'{text}' is not a number") from None
    if not math.isfinite(value):
        raise ValueError(f"'{text}' is not a number")
    if integer and value != int(value):
        raise ValueError("must be a whole number")
    if (low is not None and value < low) or (high is not None and value > high):
        raise ValueError(f"out of range: {_range(low, high)}")
    return value


def _range(low: float | None, high: float | None) -> str:
    if low is not None and high is not None:
        return f"from {format_number(low, 3)} to {format_number(high, 3)}"
    if low is not None:
        return f"at least {format_number(low, 3)}"
    return f"at most {format_number(high, 3) if high is not None else ''}"


class TypedField:
    """A text box whose committed text is parsed by `parse` (ValueError: the reason shown under it)."""

    def __init__(
        self, gui: viser.GuiApi, label: str, text: str, *, hint: str | None, name: str | None
    ) -> None:
        self.label = label
        self.name = name if name is not None else label  # how a refusal names it ("J1", "Speed %")
        self.handle = gui.add_text(label, initial_value=text, hint=hint)
        self._mark = gui.add_html("", visible=False)
        self._visible = True
        self.handle.on_update(lambda _: self._show_mark())

    def parse(self) -> object:
        raise NotImplementedError

    @property
    def reason(self) -> str | None:
        """Why the committed text is not usable, or None."""
        try:
            self.parse()
        except ValueError as error:
            return str(error)
        return None

    def _checked(self) -> object:
        try:
            return self.parse()
        except ValueError as error:
            raise FieldInvalid(f"{self.name}: {error}") from None

    @property
    def text(self) -> str:
        return str(self.handle.value)

    def _write(self, text: str, *, resend: bool = False) -> None:
        """A value from the server (a selected step's speed, the arm's angle); `resend`: even when the
        server believes the browser shows it already (viser sends only changes)."""
        if resend and self.handle.value == text:
            self.handle.value = text + " "
        if self.handle.value != text:
            self.handle.value = text
        self._show_mark()

    def on_commit(self, callback: Callable[[viser.GuiEvent], None]) -> None:
        """`callback` when the operator commits the box (not when the server writes it)."""
        self.handle.on_update(lambda event: None if event.client is None else callback(event))

    @property
    def visible(self) -> bool:
        return self._visible

    @visible.setter
    def visible(self, visible: bool) -> None:
        self._visible = visible
        self.handle.visible = visible
        self._show_mark()

    @property
    def disabled(self) -> bool:
        return bool(self.handle.disabled)

    @disabled.setter
    def disabled(self, disabled: bool) -> None:
        self.handle.disabled = disabled

    def _show_mark(self) -> None:
        reason = self.reason if self._visible else None
        content = (
            ""
            if reason is None
            else inset(
                f'<div role="alert" data-field-invalid="{html.escape(self.label)}" style="{MARK_STYLE}">'
                f"⚠ {html.escape(reason, quote=False)}</div>"
            )
        )
        if self._mark.content != content:
            self._mark.content = content
        if self._mark.visible != (reason is not None):
            self._mark.visible = reason is not None


class NumberField(TypedField):
    """One number: `value` is the committed number (FieldInvalid when there is none), `show(v)` writes one
    from the server (the page keeps it out of the box while the operator edits it)."""

    def __init__(
        self,
        gui: viser.GuiApi,
        label: str,
        initial: float,
        *,
        low: float | None = None,
        high: float | None = None,
        decimals: int = 1,
        integer: bool = False,
        hint: str | None = None,
        name: str | None = None,
    ) -> None:
        self.low, self.high, self.decimals, self.integer = low, high, decimals, integer
        super().__init__(gui, label, format_number(initial, decimals), hint=hint, name=name)

    def parse(self) -> float:
        return parse_number(self.text, self.low, self.high, integer=self.integer)

    @property
    def value(self) -> float:
        """The committed number; FieldInvalid (the field's name and the reason) when there is none."""
        return float(self._checked())  # type: ignore[arg-type]  # parse() gives a float

    def show(self, value: float, *, resend: bool = False) -> None:
        self._write(format_number(value, self.decimals), resend=resend)


class VectorField(TypedField):
    """Several numbers in one box, "400, 0, 100" (commas or spaces between them)."""

    def __init__(
        self,
        gui: viser.GuiApi,
        label: str,
        initial: Sequence[float],
        *,
        low: float | None = None,
        high: float | None = None,
        decimals: int = 1,
        hint: str | None = None,
        name: str | None = None,
    ) -> None:
        self.count, self.low, self.high, self.decimals = len(initial), low, high, decimals
        super().__init__(gui, label, self._format(initial), hint=hint, name=name)

    def _format(self, values: Sequence[float]) -> str:
        return ", ".join(format_number(float(v), self.decimals) for v in values)

    def parse(self) -> tuple[float, ...]:
        parts = [p for p in self.text.replace(",", " ").split() if p]
        if not parts:
            raise ValueError(f"empty: type {self.count} numbers, e.g. {self._format([0.0] * self.count)}")
        if len(parts) != self.count:
            raise ValueError(f"type {self.count} numbers, e.g. {self._format([0.0] * self.count)}")
        values = []
        for k, part in enumerate(parts):
            try:
                values.append(parse_number(part, self.low, self.high))
            except ValueError as error:
                raise ValueError(f"number {k + 1}: {error}") from None
        return tuple(values)

    @property
    def value(self) -> tuple[float, ...]:
        return tuple(self._checked())  # type: ignore[call-overload]  # parse() gives a tuple

    def show(self, values: Sequence[float], *, resend: bool = False) -> None:
        self._write(self._format(values), resend=resend)


def read_all(fields: Sequence[NumberField]) -> list[float]:
    """Every field's number; FieldInvalid naming each field that has none."""
    reasons = [f.reason for f in fields]
    bad = [f"{f.name}: {r}" for f, r in zip(fields, reasons, strict=True) if r is not None]
    if bad:
        raise FieldInvalid("; ".join(bad))
    return [f.value for f in fields]
