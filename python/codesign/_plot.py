"""Plots with matplotlib, an optional dependency: a solution's charts as ``codesign solve --plot``
draws them (the same curves, limits, colours and titles, from the native module's charts), and a
co-design run's cost per evaluation."""

from __future__ import annotations

import math
from typing import Any, Dict, List, Sequence

_MISSING = (
    "{what} draws with matplotlib, which is not installed: pip install matplotlib "
    "(the command line's `solve --plot` draws the same charts as SVG without it)"
)


def pyplot(what: str) -> Any:
    """``matplotlib.pyplot``, or an ImportError naming ``what`` and how to install it."""
    try:
        import matplotlib.pyplot as plt
    except ImportError as error:
        raise ImportError(_MISSING.format(what=what)) from error
    return plt


def _draw_guide(ax: Any, guide: Dict[str, Any]) -> None:
    """A dashed reference line in its (first) owner's colour, labelled once."""
    line, colour = guide["line"], guide["colours"][0]
    style = dict(color=colour, linestyle="--", linewidth=1.5, label=guide["label"])
    if line.get("horizontal") is not None:
        ax.axhline(line["horizontal"], **style)
    elif line.get("vertical") is not None:
        ax.axvline(line["vertical"], **style)
    elif line.get("segment") is not None:
        (x0, y0), (x1, y1) = line["segment"]
        ax.plot([x0, x1], [y0, y1], **style)


def _draw_series(ax: Any, series: Dict[str, Any]) -> None:
    """A line (dashed where the SVG dashes it) or dots, and a path's start and goal."""
    points = [(x, y) for x, y in series["points"] if x is not None and y is not None]
    if not points:
        return
    xs, ys = zip(*points)
    colour = series["colour"]
    if series["mark"] == "dots":
        ax.plot(xs, ys, ".", color=colour, label=series["name"])
    else:
        style = "--" if series["dashed"] else "-"
        ax.plot(xs, ys, style, color=colour, linewidth=2, label=series["name"])
    if series["ends"]:
        ax.plot(xs[0], ys[0], "o", color=colour, markeredgecolor="black", markersize=8)
        ax.plot(xs[-1], ys[-1], "s", color=colour, markeredgecolor="black", markersize=8)


def draw_chart(plt: Any, chart: Dict[str, Any]) -> Any:
    """One chart (``Chart::to_json``) as a matplotlib Figure, its legend beside the axes."""
    figure, ax = plt.subplots(figsize=(11, 5.4), layout="constrained")
    for guide in chart["guides"]:
        _draw_guide(ax, guide)
    for series in chart["series"]:
        _draw_series(ax, series)
    if chart["log_y"]:
        ax.set_yscale("log")
    ax.set_title(chart["title"], fontsize="medium", wrap=True)
    ax.set_xlabel(chart["x_label"])
    ax.set_ylabel(chart["y_label"])
    ax.grid(True, alpha=0.3)
    handles, labels = ax.get_legend_handles_labels()
    unique = dict(zip(labels, handles))
    if unique:
        ax.legend(unique.values(), unique.keys(), loc="upper left", bbox_to_anchor=(1.01, 1.0))
    return figure


def cost_history(plt: Any, costs: Sequence[float], penalty: float, title: str) -> Any:
    """A run's cost per evaluation: the feasible ones as dots and the best so far as a line on
    a log axis; the penalised ones (cost ``penalty`` or more, or not finite) counted in the
    legend, as the command line's ``cost_evolution`` plots show them."""
    feasible: List[tuple] = []
    best: List[tuple] = []
    least = math.inf
    penalised = 0
    for i, cost in enumerate(costs):
        if not (math.isfinite(cost) and cost < penalty):
            penalised += 1
        elif cost > 0:
            feasible.append((i, cost))
            least = min(least, cost)
        if math.isfinite(least):
            best.append((i, least))
    figure, ax = plt.subplots(figsize=(11, 5.4), layout="constrained")
    if feasible:
        ax.plot(*zip(*feasible), ".", color="#0072b2", alpha=0.45, label="feasible evaluation")
        ax.plot(*zip(*best), "-", color="#0072b2", linewidth=2, label="best so far")
        ax.set_yscale("log")
    ax.plot([], [], " ", label=f"{penalised} of {len(costs)} penalised (infeasible or invalid)")
    ax.set_title(title, fontsize="medium")
    ax.set_xlabel("evaluation")
    ax.set_ylabel("J")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))
    return figure
