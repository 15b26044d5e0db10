#!/usr/bin/env python3
"""How `dynapath plot`'s figures are laid out, checked on the figures
themselves (tools/plot/dynapath_plot.py imported, its `save` replaced by one
that keeps the figure): exact percent tick labels, the last bar of the
obstacle changes inside its axis, one x range per map in a --maps study,
whole-number ticks for a whole-number sweep parameter, legends outside
every panel, a log panel beside the cumulative adaptation when its totals
span decades, and the --format list.

Usage: figure_layout_test.py PLOT_SCRIPT
"""

import os
import sys

try:
    import matplotlib  # noqa: F401
    import pandas as pd
except ImportError:
    # Debian's interpreter has them when the python3 on PATH does not.
    if os.environ.get("FIGURE_LAYOUT_REEXEC") != "1" and os.path.exists("/usr/bin/python3"):
        os.environ["FIGURE_LAYOUT_REEXEC"] = "1"
        os.execv("/usr/bin/python3", ["/usr/bin/python3"] + sys.argv)
    raise

import importlib.util
from pathlib import Path

os.environ.setdefault("MPLBACKEND", "Agg")
failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print(f"FAIL: {message}")


def load(script):
    from importlib.machinery import SourceFileLoader
    loader = SourceFileLoader("dynapath_plot", str(script))
    spec = importlib.util.spec_from_loader("dynapath_plot", loader)
    module = importlib.util.module_from_spec(spec)
    loader.exec_module(module)
    return module


def drawn(module, draw, *args):
    """The figures `draw(*args, out_dir, written)` makes, drawn, not saved."""
    figures = []
    original = module.save
    module.save = lambda figure, path, written: (figures.append(figure), written.append(path))
    try:
        draw(*args)
    finally:
        module.save = original
    for figure in figures:
        figure.canvas.draw()
    return figures


def tick_labels(axis):
    return [(tick.get_loc(), tick.label1.get_text()) for tick in axis.get_major_ticks()
            if tick.label1.get_text()]


def percent_labels_exact(axis, what):
    for location, text in tick_labels(axis):
        value = float(text.rstrip("%"))
        check(abs(value - location * 100) < 1e-6, f"{what}: tick {location} labelled {text}")


def legends_outside(figure, what):
    """No legend box overlaps a panel holding data."""
    renderer = figure.canvas.get_renderer()
    boxes = [axis.get_window_extent(renderer) for axis in figure.axes if axis.has_data()]
    legends = list(figure.legends) + [axis.get_legend() for axis in figure.axes
                                      if axis.get_legend() is not None and axis.has_data()]
    for legend in legends:
        box = legend.get_window_extent(renderer)
        for panel in boxes:
            check(not box.overlaps(panel), f"{what}: a legend lies over a panel")


def summary_rows(rows):
    return pd.DataFrame(rows, columns=["Approach", "Size", "Difficulty", "InitialTime",
                                       "AdaptTimePerStep", "AvgSuccessRate", "AvgPathLength"])


def detailed_rows(approaches, steps, adapt):
    rows = []
    for approach in approaches:
        for step in range(steps + 1):
            rows.append([approach, "20", "Easy", step, 1 if step else 0,
                         adapt[approach] if step else 0.0, 0.92 + 0.06 * step / steps, 4.0])
    frame = pd.DataFrame(rows, columns=["Approach", "Size", "Difficulty", "TimeStep", "NumChanges",
                                        "AdaptTime", "SuccessRate", "AvgPathLength"])
    return frame


def main():
    module = load(Path(sys.argv[1]))
    styles = module.Styles({"A* Oracle", "BFS Oracle", "singleAgent"})
    out = Path("/nonexistent")

    # Success over time with rates 92%..98%: exact labels, last bar inside.
    detailed = detailed_rows(["A* Oracle", "BFS Oracle"], 12, {"A* Oracle": 2.0,
                                                               "BFS Oracle": 0.001})
    (figure,) = drawn(module, module.plot_success_over_time, detailed, "20", "Easy", styles,
                      out / "s.png", [], "")
    rate_axis, changes_axis = figure.axes[0], figure.axes[1]
    percent_labels_exact(rate_axis.yaxis, "success over time")
    check(len(tick_labels(rate_axis.yaxis)) >= 3, "success over time: fewer than 3 ticks")
    low, high = changes_axis.get_xlim()
    for patch in changes_axis.patches:
        check(patch.get_x() >= low and patch.get_x() + patch.get_width() <= high,
              f"obstacle changes: the bar at {patch.get_x()} is cut by the axis {low}..{high}")
    legends_outside(figure, "success over time")

    # Cumulative adaptation: 2000x apart, so a log panel beside the linear one.
    (figure,) = drawn(module, module.plot_cumulative_adapt, detailed, "20", "Easy", styles,
                      out / "c.png", [], "")
    scales = [axis.get_yscale() for axis in figure.axes]
    check(scales == ["linear", "log"], f"cumulative adaptation: axes {scales}, expected linear, log")
    legends_outside(figure, "cumulative adaptation")
    close = detailed_rows(["A* Oracle", "BFS Oracle"], 12, {"A* Oracle": 2.0, "BFS Oracle": 1.0})
    (figure,) = drawn(module, module.plot_cumulative_adapt, close, "20", "Easy", styles,
                      out / "c.png", [], "")
    check(len(figure.axes) == 1, "cumulative adaptation: a log panel for totals 2x apart")

    # A --maps study: each map its own size; each panel shows only its own.
    maps = summary_rows([
        [approach, size, name, 0.1, 0.01, success, 5.0]
        for name, size in (("arena", "49x49"), ("den312d", "65x81"), ("warehouse", "123x321"))
        for approach, success in (("A* Oracle", 0.975), ("BFS Oracle", 0.95))])
    figures = drawn(module, module.plot_by_size, maps, None, styles, out, [])
    for figure in figures:
        panels = [axis for axis in figure.axes if axis.has_data()]
        check(len(panels) == 3, f"maps: {len(panels)} panels, expected 3")
        for axis in panels:
            labels = [text for _, text in tick_labels(axis.xaxis)]
            check(len(labels) == 1, f"maps: panel {axis.get_title()} has x ticks {labels}")
    percent_labels_exact(figures[0].axes[0].yaxis, "success by size")
    legends_outside(figures[0], "success by size")

    # A sweep of a whole-number parameter 2, 3, 4: ticks 2, 3, 4 only.
    sweep_rows = []
    for value in (2, 3, 4):
        for approach in ("BFS Oracle", "singleAgent"):
            for metric, mean in (("AvgSuccessRate", 0.9 + value / 100), ("AvgPathLength", 5.0),
                                 ("AdaptTimePerStep", 0.01)):
                sweep_rows.append([value, approach, "all", "all", metric, 3, mean, mean * 0.99,
                                   mean * 1.01])
    sweep = pd.DataFrame(sweep_rows, columns=["episodes", "Approach", "Size", "Difficulty",
                                              "Metric", "Repeats", "Mean", "MeanCILow",
                                              "MeanCIHigh"])
    (figure,) = drawn(module, module.plot_sweeps, (["episodes"], sweep), styles, out, [])
    for axis in figure.axes:
        if axis.has_data():
            labels = [text for _, text in tick_labels(axis.xaxis)]
            check(labels == ["2", "3", "4"], f"sweep: x ticks {labels}, expected 2, 3, 4")
    legends_outside(figure, "sweep")

    # --format: a list of known formats; anything else is a usage error.
    check(module.image_formats("png,svg,pdf") == ["png", "svg", "pdf"], "--format png,svg,pdf")
    try:
        module.image_formats("png,gif")
        check(False, "--format png,gif accepted")
    except Exception as error:  # noqa: BLE001 - argparse's ArgumentTypeError
        check("gif" in str(error), f"--format png,gif: {error}")

    if failures:
        print(f"{len(failures)} check(s) failed")
        return 1
    print("figure_layout_test: all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
