"""The Dashboard's plots (uPlot): joint angles, RMS currents and stator temperatures, each with its unit on
the axis and every joint's current value in the legend; one joint or all, over the last 1 to 60 minutes,
paused to read or to zoom (drag across a plot; double-click to zoom back out).

The data are shared: the refresh loop builds them once per window length (`plot_data`) for every browser;
each browser's PlotView picks its window, its joints, and whether it follows.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import viser
import viser.uplot as uplot

from pendant.telemetry.history import HistoryWindow
from pendant.ui.kit.gui_target import GuiTarget

PLOT_HEIGHT_PX = 240
MAX_POINTS = 300  # per series and plot: about the panel's width in pixels (as many as the 60 s plots had)
# New legend values rebuild the chart in the browser (uplot-react recreates it when its series change):
# while the arm moves, the legend follows every 4th redraw (2 s), the lines every redraw.
LEGEND_EVERY_N_DRAWS = 4
JOINT_COLOURS = ("#e03131", "#2f9e44", "#1971c2", "#f08c00", "#9c36b5", "#0c8599")
ALL_JOINTS = "All joints"
JOINT_CHOICES = (ALL_JOINTS, "J1", "J2", "J3", "J4", "J5", "J6")
# label -> seconds
WINDOWS = {"Last minute": 60.0, "Last 5 minutes": 300.0, "Last 15 minutes": 900.0, "Last hour": 3600.0}
PLOTS = (("angle", "Joint angles"), ("current", "RMS currents"), ("stator", "Stator temperatures"))
UNITS = {"angle": ("°", 1), "current": ("A", 2), "stator": ("°C", 1)}  # unit, decimals in the legend

PlotData = dict[str, tuple[np.ndarray, ...]]
PlotSource = Callable[[float], PlotData]  # window length in seconds -> the plots' data


def x_unit(window_s: float) -> tuple[str, float]:
    """The time axis: seconds ago for a minute, minutes ago beyond."""
    return ("s ago", 1.0) if window_s <= 60.0 else ("min ago", 60.0)


def plot_data(window: HistoryWindow, window_s: float = 60.0, max_points: int = MAX_POINTS) -> PlotData:
    """uPlot data: x = time ago (x_unit), then a series per joint; thinned to at most `max_points`, the
    newest sample always kept."""
    every = max(1, int(np.ceil(len(window) / max_points)))
    _, per = x_unit(window_s)
    t = window.t[::-1][::every][::-1] / per

    def series(values: np.ndarray) -> tuple[np.ndarray, ...]:
        thinned = values[::-1][::every][::-1]
        return (t, *(thinned[:, j] for j in range(thinned.shape[1])))

    return {
        "angle": series(window.angle_deg),
        "current": series(window.current_a),
        "stator": series(window.stator_c),
    }


def _empty() -> tuple[np.ndarray, ...]:
    return tuple(np.zeros(1) for _ in range(7))


def legend_label(joint: int, value: float | None, unit: str, decimals: int) -> str:
    """`J1 12.3 °`: the legend shows each joint's newest value (uPlot's own live legend shows "--" until
    the mouse is over the plot)."""
    return f"J{joint + 1}" if value is None else f"J{joint + 1} {value:.{decimals}f} {unit}"


class PlotView:
    """One browser's three plots and their controls."""

    def __init__(self, target: GuiTarget) -> None:
        self.joint = target.gui.add_dropdown("Plot", JOINT_CHOICES, initial_value=ALL_JOINTS)
        self.window = target.gui.add_dropdown("Window", tuple(WINDOWS), initial_value="Last minute")
        self.paused = target.gui.add_checkbox(
            "Pause", False, hint="Stop following, to read or zoom (drag across a plot)"
        )
        self.plots: dict[str, viser.GuiUplotHandle] = {}
        self._labels: dict[str, tuple[tuple[object, object], ...]] = {}
        for key, title in PLOTS:
            unit, _ = UNITS[key]
            self.plots[key] = target.gui.add_uplot(
                data=_empty(),
                series=self._series(key, [None] * 6),
                title=f"{title} ({unit})",
                scales={"x": uplot.Scale(time=False, range=(-60.0, 0.0))},
                axes=(uplot.Axis(label="s ago"), uplot.Axis(label=unit)),
                legend=uplot.Legend(show=True, live=False),
                height=PLOT_HEIGHT_PX,
            )
        self._source: PlotSource | None = None
        self._data: PlotData | None = None
        self._draws = 0
        self.joint.on_update(lambda _: self._draw())  # a new choice of joints shows at once
        self.window.on_update(lambda _: self._rescale())
        self.paused.on_update(lambda _: self._follow())

    @property
    def window_s(self) -> float:
        return WINDOWS[self.window.value]

    def show(self, source: PlotSource) -> None:
        """New data from the refresh loop (kept, not drawn, while paused)."""
        self._source = source
        if not self.paused.value:
            self._follow()

    def _follow(self) -> None:
        if self._source is not None and not self.paused.value:
            self._data = self._source(self.window_s)
            self._draw()

    def _draw(self) -> None:
        data = self._data
        if data is None:
            return
        self._draws += 1
        legend_due = self._draws % LEGEND_EVERY_N_DRAWS == 1 or not self._labels
        for key, handle in self.plots.items():
            if len(data[key][0]) < 2:
                continue
            handle.data = data[key]
            series = self._series(key, [float(values[-1]) for values in data[key][1:]])
            labels = tuple((s["label"], s.get("show", True)) for s in series)
            previous = self._labels.get(key)
            shown_changed = previous is None or [v for _, v in previous] != [v for _, v in labels]
            if labels != previous and (legend_due or shown_changed):  # only what changed goes to the browser
                handle.series = series
                self._labels[key] = labels

    def _series(self, key: str, newest: list[float | None]) -> tuple[uplot.Series, ...]:
        unit, decimals = UNITS[key]
        chosen = self.joint.value
        return (
            uplot.Series(label=x_unit(self.window_s)[0]),
            *(
                uplot.Series(
                    label=legend_label(j, newest[j], unit, decimals),
                    stroke=JOINT_COLOURS[j],
                    width=1.5,
                    show=chosen in (ALL_JOINTS, f"J{j + 1}"),
                )
                for j in range(6)
            ),
        )

    def _rescale(self) -> None:
        """A new window: its time axis, and its data even while paused (that is the zoom)."""
        label, per = x_unit(self.window_s)
        for key, handle in self.plots.items():
            unit, _ = UNITS[key]
            handle.scales = {"x": uplot.Scale(time=False, range=(-self.window_s / per, 0.0))}
            handle.axes = (uplot.Axis(label=label), uplot.Axis(label=unit))
        if self._source is not None:
            self._data = self._source(self.window_s)
        self._labels.clear()
        self._draw()
