#!/usr/bin/env python3
"""dynapath plot: draw the report's figures from a study's result files.

Reads DIR/results.csv and DIR/results_detailed.csv (and, when present, the
edge case's DIR/edge_results.csv and DIR/edge_results_detailed.csv) and writes
one PNG per figure (--format svg,pdf for vector images too); docs/howto/PLOTTING.md explains every figure. Standard library,
pandas and matplotlib only (Debian's python3-pandas and python3-matplotlib).

Exit status: 0 figures written, 1 bad data (missing or malformed CSV), 2 bad
usage (unknown option, missing directory). Errors are one line on stderr.
"""

import argparse
import logging
import math
import os
import re
import sys
import warnings
from pathlib import Path

PROG = "dynapath plot"
EXIT_DATA = 1
EXIT_USAGE = 2

# CMake (tools/plot/CMakeLists.txt) substitutes the absolute path of the
# project's docs/reference when it configures this script into the build.
CONFIGURED_REFERENCE_DIR = "@DYNAPATH_REFERENCE_DIR@"
REFERENCE_SOURCE = "micss-lab/MARL4DynaPath"

SUMMARY_FILE = "results.csv"
DETAILED_FILE = "results_detailed.csv"
EDGE_PREFIX = "edge_"
SUMMARY_COLUMNS = ["Approach", "Size", "Difficulty", "InitialTime", "AdaptTimePerStep",
                   "AvgSuccessRate", "AvgPathLength"]
# NodesTrained and HighestLevel (ours) may follow; they are not plotted.
DETAILED_COLUMNS = ["Approach", "Size", "Difficulty", "TimeStep", "NumChanges", "AdaptTime",
                    "SuccessRate", "AvgPathLength"]
TEXT_COLUMNS = ["Approach", "Size", "Difficulty"]
# Repeats (dynapath experiment --repeats N): every repeat's results.csv row,
# and their statistics (mean and its 95% bootstrap interval, among others).
REPEATS_FILE = "repeats.csv"
REPEAT_SUMMARY_FILE = "summary.csv"
REPEAT_SUMMARY_COLUMNS = ["Approach", "Size", "Difficulty", "Metric", "Repeats", "Mean",
                          "MeanCILow", "MeanCIHigh"]

DIFFICULTIES = ["Easy", "Medium", "Hard"]
# One colour and marker per approach in every figure (Okabe-Ito colours, which
# stay distinct for colour-blind readers; filled markers so that the report's
# values can be drawn hollow).
# The registry's approaches in its order (core/include/dynapath/approach_list.h, substituted
# by CMake); the i-th gets the i-th style, so the colours stay where they
# were (A* Static grey, ..., fedAsynQ_ImAvg green, Incremental Oracle yellow)
# and a new approach takes the next one.
REGISTERED_APPROACHES = "@DYNAPATH_APPROACH_NAMES@".split("|")
STYLES = [("#8c8c8c", "s"), ("#000000", "D"), ("#cc79a7", "P"), ("#d55e00", "v"),
          ("#e69f00", "^"), ("#0072b2", "o"), ("#009e73", "X"), ("#f0e442", "d"),
          ("#56b4e9", "p"), ("#882255", "h"), ("#999933", "<"), ("#332288", ">"),
          ("#44aa99", "8"), ("#aa4499", "*")]
APPROACH_STYLES = {name: STYLES[i % len(STYLES)] for i, name in enumerate(REGISTERED_APPROACHES)}
# Names in a results file that are not registered (an older or newer tree's).
_FIRST_FREE = len(REGISTERED_APPROACHES) % len(STYLES)
EXTRA_STYLES = STYLES[_FIRST_FREE:] + STYLES[:_FIRST_FREE]

DPI = 150
# The image formats to write (--format): each figure in each of them.
FORMATS = ["png"]
KNOWN_FORMATS = ["png", "svg", "pdf"]


class PlotError(Exception):
    """A failure reported as one line on stderr with an exit status."""

    def __init__(self, message, status=EXIT_DATA):
        super().__init__(message)
        self.status = status


class ArgumentParser(argparse.ArgumentParser):
    """argparse that reports a usage error as one line (no usage dump)."""

    def error(self, message):
        raise PlotError(f"{message} (see --help)", EXIT_USAGE)


def parse_arguments(argv):
    parser = ArgumentParser(
        prog=PROG,
        description="Draw the report's figures (PNG, or SVG/PDF with --format) from a study directory holding results.csv "
                    "and results_detailed.csv, and optionally the edge case's edge_results.csv "
                    "and edge_results_detailed.csv. Prints the files written.",
        epilog="Figures: success_rate_by_size, adapt_time_by_size, path_length_by_size, "
               "initial_time_by_size (one panel per difficulty); per configuration "
               "adapt_box_<size>_<difficulty>, cumulative_adapt_<size>_<difficulty>, "
               "success_over_time_<size>_<difficulty>; for the edge case the same per-"
               "configuration figures prefixed edge_, and edge_summary_<size>_<difficulty>. "
               "A study with repeats (summary.csv, repeats.csv): the by-size and edge summary "
               "figures show means over the repeats with 95% bootstrap intervals, and "
               "performance_profile_success (and edge_performance_profile_success) is added. "
               "A study with a sweep (sweep_summary.csv): sweep_<parameter> per swept "
               "parameter. "
               "See docs/howto/PLOTTING.md. Exit status: 0 done, 1 bad data, 2 bad usage.")
    parser.add_argument("study", metavar="DIR", nargs="?",
                        help="the study directory (dynapath run --out DIR)")
    parser.add_argument("--compare", metavar="CSV",
                        help="instead of a study's figures, draw the paired differences of "
                             "`dynapath compare --csv` (CSV) into the file --out names; "
                             "`dynapath compare --plot FILE` does this")
    parser.add_argument("--out", metavar="DIR",
                        help="where to write the figures (default: DIR/figures)")
    parser.add_argument("--reference", metavar="DIR",
                        help="overlay the report's published values read from DIR/paper_results.csv "
                             "(and DIR/paper_edge_results.csv); 'default' is the project's "
                             "docs/reference")
    parser.add_argument("--overlay-reference", action="store_true",
                        help="the same as --reference default")
    parser.add_argument("--format", metavar="LIST", default="png", type=image_formats,
                        help="comma-separated image formats, each figure in each of them: "
                             f"{', '.join(KNOWN_FORMATS)} (default png; svg and pdf are vector "
                             "images for papers)")
    return parser.parse_args(argv)


def image_formats(text):
    formats = [item.strip().lower() for item in text.split(",")]
    unknown = [item for item in formats if item not in KNOWN_FORMATS]
    if unknown or not formats:
        raise argparse.ArgumentTypeError(
            f"unknown image format '{','.join(unknown) or text}' (expected a comma-separated "
            f"list of {', '.join(KNOWN_FORMATS)})")
    return list(dict.fromkeys(formats))


def default_reference_dir():
    if not CONFIGURED_REFERENCE_DIR.startswith("@"):
        return Path(CONFIGURED_REFERENCE_DIR)
    # Run from the source tree (tools/plot/dynapath_plot.py), not configured.
    return Path(__file__).resolve().parent.parent.parent / "docs" / "reference"


def reference_dir_from(args):
    choice = args.reference
    if choice is None and args.overlay_reference:
        choice = "default"
    if choice is None:
        return None
    directory = default_reference_dir() if choice == "default" else Path(choice)
    if not directory.is_dir():
        raise PlotError(f"--reference: {directory}: no such directory", EXIT_USAGE)
    return directory


def import_libraries():
    """Checks that pandas and matplotlib can be imported, or runs this script
    with Debian's python3 when the python3 on PATH (e.g. pyenv's) lacks them.
    matplotlib itself is imported only once the data have been read."""
    import importlib.util
    try:
        import pandas  # noqa: F401
        missing = None if importlib.util.find_spec("matplotlib") else "matplotlib"
    except ImportError as error:
        missing = error.name or "pandas"
    if missing is None:
        # Agg: no display needed. Quiet: its one-off notices (building the
        # font cache, a temporary config directory) are not our errors.
        os.environ.setdefault("MPLBACKEND", "Agg")
        logging.getLogger("matplotlib").setLevel(logging.ERROR)
        return
    system_python = "/usr/bin/python3"
    if (os.environ.get("DYNAPATH_PLOT_REEXEC") != "1" and os.path.exists(system_python)
            and os.path.realpath(sys.executable) != os.path.realpath(system_python)):
        os.environ["DYNAPATH_PLOT_REEXEC"] = "1"
        sys.stdout.flush()
        os.execv(system_python, [system_python, os.path.abspath(__file__)] + sys.argv[1:])
    raise PlotError(f"{sys.executable} cannot import {missing}: install Debian's "
                    "python3-pandas and python3-matplotlib")


# ----------------------------------------------------------------------------
# Reading and checking the CSV files.


def read_table(path, required, numeric, key):
    """Reads a result CSV; every check failure is a PlotError naming the file."""
    import pandas as pd
    if not path.is_file():
        raise PlotError(f"{path}: no such file")
    try:
        frame = pd.read_csv(path, dtype=str, keep_default_na=False, skipinitialspace=True)
    except pd.errors.EmptyDataError:
        raise PlotError(f"{path}: empty file (expected a header line: {','.join(required)})") \
            from None
    except (pd.errors.ParserError, UnicodeDecodeError, ValueError, OSError) as error:
        detail = str(error).strip().splitlines()[-1] if str(error).strip() else type(error).__name__
        raise PlotError(f"{path}: not a readable CSV table: {detail}") from None
    frame.columns = [str(column).strip() for column in frame.columns]
    missing = [column for column in required if column not in frame.columns]
    if missing:
        raise PlotError(f"{path}: missing column{'s' if len(missing) > 1 else ''} "
                        f"{', '.join(missing)} (expected {','.join(required)})")
    if frame.empty:
        raise PlotError(f"{path}: no data rows")
    frame = frame[required].copy()
    for column in TEXT_COLUMNS:
        frame[column] = frame[column].astype(str).str.strip()
        empty = frame.index[frame[column] == ""]
        if len(empty):
            raise PlotError(f"{path}: line {empty[0] + 2}: empty {column}")
    for column in numeric:
        text = frame[column].astype(str).str.strip()
        values = pd.to_numeric(text, errors="coerce")
        bad = values.isna() & ~text.str.lower().isin(["nan", "-nan", "+nan"])
        if bad.any():
            row = bad.idxmax()
            raise PlotError(f"{path}: line {row + 2}: {column} '{text[row]}' is not a number")
        frame[column] = values.astype(float)
    if "TimeStep" in frame.columns:
        steps = frame["TimeStep"]
        bad = ~(steps.notna() & (steps >= 0) & (steps == steps.round()))
        if bad.any():
            row = bad.idxmax()
            raise PlotError(f"{path}: line {row + 2}: TimeStep '{steps[row]}' is not a step number")
        frame["TimeStep"] = steps.astype(int)
    frame["Difficulty"] = frame["Difficulty"].map(normalise_difficulty)
    duplicated = frame.duplicated(subset=key, keep="first")
    if duplicated.any():
        row = duplicated.idxmax()
        what = ", ".join(f"{column} {frame.at[row, column]}" for column in key)
        raise PlotError(f"{path}: line {row + 2}: a second row for {what}")
    return frame


def read_summary(path):
    return read_table(path, SUMMARY_COLUMNS, SUMMARY_COLUMNS[3:], TEXT_COLUMNS)


def read_detailed(path):
    return read_table(path, DETAILED_COLUMNS, DETAILED_COLUMNS[3:], TEXT_COLUMNS + ["TimeStep"])


def read_intervals(path):
    """summary.csv of a study with repeats, without its rows over all
    configurations: {(approach, size, difficulty, metric): (repeats, mean,
    low, high)}; None when the file is absent."""
    if not path.exists():
        return None
    frame = read_table(path, REPEAT_SUMMARY_COLUMNS, REPEAT_SUMMARY_COLUMNS[4:],
                       TEXT_COLUMNS + ["Metric"])
    frame = frame[frame["Size"] != "all"]
    return {(row.Approach, row.Size, row.Difficulty, row.Metric):
            (int(row.Repeats), row.Mean, row.MeanCILow, row.MeanCIHigh)
            for row in frame.itertuples(index=False)}


def read_repeats(path):
    """repeats.csv (every repeat's result row), or None when absent."""
    if not path.exists():
        return None
    return read_table(path, ["Repeat"] + SUMMARY_COLUMNS, ["Repeat"] + SUMMARY_COLUMNS[3:],
                      ["Repeat"] + TEXT_COLUMNS)


def read_study(directory, prefix, optional):
    """The (summary, detailed) pair of one study; (None, None) when optional
    and neither file exists."""
    summary_path = directory / (prefix + SUMMARY_FILE)
    detailed_path = directory / (prefix + DETAILED_FILE)
    if optional and not summary_path.exists() and not detailed_path.exists():
        return None, None
    return read_summary(summary_path), read_detailed(detailed_path)


def normalise_difficulty(name):
    for known in DIFFICULTIES:
        if name.lower() == known.lower():
            return known
    return name


# ----------------------------------------------------------------------------
# Ordering and naming.


def size_key(label):
    """Sizes sort by their numbers ('40x60' by 40, then 60); others last."""
    numbers = [float(number) for number in re.findall(r"\d+(?:\.\d+)?", label)]
    if not numbers:
        return (1, 0.0, 0.0, label)
    return (0, numbers[0], numbers[1] if len(numbers) > 1 else numbers[0], label)


def size_display(label):
    if re.fullmatch(r"\d+", label):
        return f"{label}×{label}"
    match = re.fullmatch(r"(\d+)\s*[xX×*]\s*(\d+)", label)
    if match:
        return f"{match.group(1)}×{match.group(2)}"
    return label


def difficulty_key(name):
    return (DIFFICULTIES.index(name), "") if name in DIFFICULTIES else (len(DIFFICULTIES), name)


def sizes_of(frame):
    return sorted(frame["Size"].unique(), key=size_key)


def difficulties_of(frame):
    return sorted(frame["Difficulty"].unique(), key=difficulty_key)


def configurations_of(frame):
    pairs = frame[["Size", "Difficulty"]].drop_duplicates().itertuples(index=False)
    return sorted(pairs, key=lambda pair: (size_key(pair[0]), difficulty_key(pair[1])))


def file_token(text):
    return re.sub(r"[^A-Za-z0-9.+-]+", "_", text).strip("_") or "x"


class Styles:
    """Colour and marker of each approach, the same in every figure."""

    def __init__(self, approaches):
        known = [name for name in APPROACH_STYLES if name in approaches]
        others = [name for name in approaches if name not in APPROACH_STYLES]
        self.order = known + sorted(others)
        self.style = dict(APPROACH_STYLES)
        for index, name in enumerate(sorted(others)):
            self.style[name] = EXTRA_STYLES[index % len(EXTRA_STYLES)]

    def ordered(self, names):
        present = set(names)
        return [name for name in self.order if name in present]

    def colour(self, name):
        return self.style[name][0]

    def marker(self, name):
        return self.style[name][1]


# ----------------------------------------------------------------------------
# Drawing helpers.


def pyplot():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def line_handle(styles, name, label=None, hollow=False, dashed=False, colour=None, marker=None):
    from matplotlib.lines import Line2D
    colour = colour or styles.colour(name)
    return Line2D([], [], color=colour, marker=marker or styles.marker(name), markersize=7,
                  linestyle="--" if dashed else "-", linewidth=1.6,
                  markerfacecolor="none" if hollow else colour, markeredgewidth=1.4,
                  label=label or name)


def blank_handle():
    from matplotlib.lines import Line2D
    return Line2D([], [], linestyle="none", label=" ")


def figure_with_legend_row(panels, legend_rows, panel_width=4.6, panel_height=4.1,
                           width_ratios=None):
    """A row of panels (widths in `width_ratios`, default equal) above an
    axis-free strip holding the legend."""
    plt = pyplot()
    legend_height = 0.32 * legend_rows + 0.3
    width = panel_width * panels
    if width_ratios:
        # A panel of one size needs less room than one of five.
        width = sum(panel_width * (0.45 + 0.55 * ratio / max(width_ratios))
                    for ratio in width_ratios)
        width_ratios = [0.45 + 0.55 * ratio / max(width_ratios) for ratio in width_ratios]
    figure = plt.figure(figsize=(max(7.5, width), panel_height + legend_height))
    grid = figure.add_gridspec(2, panels, height_ratios=[panel_height, legend_height],
                               width_ratios=width_ratios)
    axes = []
    for index in range(panels):
        share = axes[0] if axes else None
        axes.append(figure.add_subplot(grid[0, index], sharey=share))
    legend_axis = figure.add_subplot(grid[1, :])
    legend_axis.axis("off")
    return figure, axes, legend_axis


def save(figure, path, written):
    """Writes `figure` as path.png (and .svg, .pdf when asked for)."""
    for extension in FORMATS:
        target = Path(path).with_suffix("." + extension)
        figure.savefig(target, dpi=DPI)
        written.append(target)
    pyplot().close(figure)


def configuration_title(size, difficulty):
    return f"{size_display(size)} {difficulty}"


def positive_or_nan(values):
    return [value if value > 0 else math.nan for value in values]


def percent_axis(axis):
    """Fractions as percentages on `axis` (an x or y axis), every tick label
    exact: tick steps of 1, 2 or 5 times a power of ten (never 2.5, whose
    half steps printed rounded: "98%, 95%, 92%" for 97.5, 95, 92.5), with as
    many decimals as the ticks need. No tick label above 100% (the axis may
    reach a little higher so that markers at 100% are not cut)."""
    from matplotlib.ticker import Formatter, MaxNLocator

    class ExactPercent(Formatter):
        def __call__(self, value, position=None):
            if value > 1.0 + 1e-9:
                return ""
            shown = [x for x in getattr(self, "locs", []) if x <= 1.0 + 1e-9] or [value]
            return f"{value * 100:.{percent_decimals(shown)}f}%"

    axis.set_major_locator(MaxNLocator(nbins=6, steps=[1, 2, 5, 10]))
    axis.set_major_formatter(ExactPercent())


def percent_decimals(locations):
    """The fewest decimals (0..4) that print every location (a fraction) as
    an exact percentage."""
    for decimals in range(5):
        if all(abs(round(value * 100, decimals) - value * 100) < 1e-6 for value in locations):
            return decimals
    return 4


def seconds_formatter():
    """Tick labels of a log axis in seconds (1e-4 s ... 100 s) as plain numbers."""
    from matplotlib.ticker import FuncFormatter

    def label(value, _position):
        if value <= 0:
            return ""
        exponent = math.floor(math.log10(value) + 1e-9)
        if abs(value / 10 ** exponent - 1) > 1e-6:
            return ""
        return f"{value:g}" if -3 <= exponent <= 3 else f"$10^{{{exponent}}}$"

    return FuncFormatter(label)


# ----------------------------------------------------------------------------
# Figures 1, 3, 5, 6: a summary column by maze size, one panel per difficulty.


BY_SIZE_FIGURES = [
    # file, column, title, y label, kind
    ("success_rate_by_size", "AvgSuccessRate", "Average success rate by maze size",
     "Average success rate (%, time steps 0–T)", "percent"),
    ("adapt_time_by_size", "AdaptTimePerStep", "Average adaptation time per time step by maze size",
     "Adaptation time per step (s, mean of steps 1–T)", "log"),
    ("path_length_by_size", "AvgPathLength", "Average path length by maze size",
     "Average path length (steps, time steps 0–T)", "linear"),
    ("initial_time_by_size", "InitialTime", "Initial training time by maze size",
     "Initial training time (s)", "log"),
]


def interval_series(intervals, approach, difficulty, sizes, column):
    """(sizes, means, lower errors, upper errors, fewest repeats) of one line
    of a by-size figure from the repeats' statistics."""
    found = [(size, intervals[(approach, size, difficulty, column)]) for size in sizes
             if (approach, size, difficulty, column) in intervals]
    means = [value[1] for _, value in found]
    low = [max(0.0, value[1] - value[2]) for _, value in found]
    high = [max(0.0, value[3] - value[1]) for _, value in found]
    fewest = min((value[0] for _, value in found), default=0)
    return [size for size, _ in found], means, low, high, fewest


def plot_by_size(summary, reference, styles, out_dir, written, intervals=None):
    """With `intervals` (a study with repeats), each point is the mean over
    the repeats with its 95% bootstrap interval as an error bar."""
    sizes = sizes_of(summary)
    difficulties = difficulties_of(summary)
    approaches = styles.ordered(summary["Approach"].unique())
    # Each panel's x axis holds its own sizes: the maps of a --maps study
    # (one panel each) have one size apiece, not every map's.
    panel_sizes = {difficulty: sizes_of(summary[summary["Difficulty"] == difficulty])
                   for difficulty in difficulties}
    # Approaches side by side around each size so that equal values (A* Oracle
    # and BFS Oracle) stay visible.
    spread = min(0.36, 0.07 * (len(approaches) - 1))
    offset = {name: (index / (len(approaches) - 1) - 0.5) * spread if len(approaches) > 1 else 0.0
              for index, name in enumerate(approaches)}
    if reference is not None:
        reference = reference[reference["Size"].isin(sizes)
                              & reference["Difficulty"].isin(difficulties)
                              & reference["Approach"].isin(approaches)]
    overlay = reference is not None and not reference.empty

    for name, column, title, ylabel, kind in BY_SIZE_FIGURES:
        notes = {}
        if kind == "log":
            # Never above 0 s (A* Static's adaptation): not drawable on a log axis.
            for approach in approaches:
                values = summary.loc[summary["Approach"] == approach, column]
                if len(values) and (values <= 0).all():
                    notes[approach] = "0 s, not on the log axis"
        rows_of_legend = math.ceil(len(approaches) / 4)
        if overlay:
            rows_of_legend = max(2, rows_of_legend)
        columns = math.ceil(len(approaches) / rows_of_legend)
        figure, axes, legend_axis = figure_with_legend_row(
            len(difficulties), rows_of_legend,
            width_ratios=[len(panel_sizes[difficulty]) for difficulty in difficulties])
        fewest_repeats = None
        for axis, difficulty in zip(axes, difficulties):
            rows = summary[summary["Difficulty"] == difficulty]
            here = panel_sizes[difficulty]
            position = {size: index for index, size in enumerate(here)}
            for approach in approaches:
                series = rows[rows["Approach"] == approach]
                if intervals is not None:
                    at, ys, low, high, fewest = interval_series(intervals, approach, difficulty,
                                                                here, column)
                    fewest_repeats = fewest if fewest_repeats is None else min(fewest_repeats,
                                                                               fewest)
                    xs = [position[size] + offset[approach] for size in at]
                    if kind == "log":  # bars that would reach 0 or below stop at the point
                        low = [min(d, y * 0.999) if y > 0 else 0 for d, y in zip(low, ys)]
                        ys = positive_or_nan(ys)
                    axis.errorbar(xs, ys, yerr=[low, high], color=styles.colour(approach),
                                  marker=styles.marker(approach), markersize=6.5, linewidth=1.6,
                                  elinewidth=1.3, capsize=3, zorder=3)
                else:
                    xs = [position[size] + offset[approach] for size in series["Size"]]
                    order = sorted(range(len(xs)), key=lambda i: xs[i])
                    xs = [xs[i] for i in order]
                    ys = [series[column].iloc[i] for i in order]
                    if kind == "log":
                        ys = positive_or_nan(ys)
                    axis.plot(xs, ys, color=styles.colour(approach),
                              marker=styles.marker(approach), markersize=6.5, linewidth=1.6,
                              zorder=3)
                if overlay:
                    published = reference[(reference["Difficulty"] == difficulty)
                                          & (reference["Approach"] == approach)
                                          & reference["Size"].isin(here)]
                    points = sorted((position[size] + offset[approach], value)
                                    for size, value in zip(published["Size"], published[column]))
                    ys_ref = [value for _, value in points]
                    if kind == "log":
                        ys_ref = positive_or_nan(ys_ref)
                    axis.plot([x for x, _ in points], ys_ref, color=styles.colour(approach),
                              marker=styles.marker(approach), markersize=7.5,
                              markerfacecolor="none", markeredgewidth=1.3, linestyle="--",
                              linewidth=1.1, alpha=0.85, zorder=2)
            axis.set_title(difficulty)
            axis.set_xticks(range(len(here)))
            axis.set_xticklabels([size_display(size) for size in here])
            axis.set_xlim(-0.5, len(here) - 0.5)
            axis.set_xlabel("Maze size (cells)")
            axis.grid(True, which="major", axis="y", alpha=0.3)
            if kind == "log":
                axis.set_yscale("log")
                axis.yaxis.set_major_formatter(seconds_formatter())
                axis.grid(True, which="minor", axis="y", alpha=0.1)
            elif kind == "percent":
                percent_axis(axis.yaxis)
        for axis in axes[1:]:
            axis.tick_params(labelleft=False)
        axes[0].set_ylabel(ylabel)
        if kind == "percent":
            low, high = axes[0].get_ylim()
            axes[0].set_ylim(low, min(high, 1.02))
        handles = [line_handle(styles, approach,
                               f"{approach} ({notes[approach]})" if approach in notes else None)
                   for approach in approaches]
        if overlay:
            # The approaches fill whole columns; "this study" and "report"
            # share the last one.
            handles += [blank_handle()] * (rows_of_legend * columns - len(handles))
            times = kind == "log"
            handles.append(line_handle(styles, "", "this study", colour="#555555", marker="o"))
            handles.append(line_handle(
                styles, "", f"report ({REFERENCE_SOURCE}" + ("; its times: i7-1165G7)" if times
                                                             else ")"),
                hollow=True, dashed=True, colour="#555555", marker="o"))
            handles += [blank_handle()] * (rows_of_legend - 2)
            columns += 1
        legend_axis.legend(handles=handles, loc="center", ncol=columns, frameon=False,
                           fontsize=9.5, handlelength=2.6, columnspacing=1.6)
        if fewest_repeats:
            title += (f" (mean of {fewest_repeats} repeats, "
                      "95% stratified-bootstrap interval)")
        figure.suptitle(title, fontsize=13)
        figure.tight_layout()
        save(figure, out_dir / f"{name}.png", written)


SWEEP_SUMMARY_FILE = "sweep_summary.csv"
SWEEP_PANELS = [
    ("AvgSuccessRate", "Average success rate (%)", "percent"),
    ("AvgPathLength", "Average path length (steps)", "linear"),
    ("AdaptTimePerStep", "Adaptation time per step (s)", "log"),
]


def read_sweep(path):
    """sweep_summary.csv: (the swept parameters' names, the frame); None
    when absent."""
    import pandas as pd
    if not path.exists():
        return None
    try:
        header = pd.read_csv(path, nrows=0).columns.tolist()
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError, ValueError) as error:
        raise PlotError(f"{path}: not a readable CSV table: {error}") from None
    if "Approach" not in header or header.index("Approach") == 0:
        raise PlotError(f"{path}: expected the swept parameters' columns, then Approach")
    names = header[:header.index("Approach")]
    frame = read_table(path, names + REPEAT_SUMMARY_COLUMNS, names + REPEAT_SUMMARY_COLUMNS[4:],
                       TEXT_COLUMNS + ["Metric"] + names)
    return names, frame


def plot_sweeps(sweep, styles, out_dir, written, prefix=""):
    """One figure per swept parameter: success rate, path length and
    adaptation time (means over all configurations and repeats, with their
    95% bootstrap intervals) against the parameter's values, one line per
    approach; the other swept parameters at their first value."""
    plt = pyplot()
    names, frame = sweep
    pooled = frame[frame["Size"] == "all"]
    if pooled.empty:  # one configuration: its own rows
        pooled = frame
    for name in names:
        rows = pooled
        fixed = []
        for other in names:
            if other != name:
                first = frame[other].iloc[0]
                rows = rows[rows[other] == first]
                fixed.append(f"{other} {first:g}")
        figure, axes = plt.subplots(1, len(SWEEP_PANELS), figsize=(15.0, 5.4))
        values = sorted(rows[name].dropna().unique())
        for axis, (metric, ylabel, kind) in zip(axes, SWEEP_PANELS):
            for approach in styles.ordered(rows["Approach"].unique()):
                series = rows[(rows["Approach"] == approach) & (rows["Metric"] == metric)]
                series = series.sort_values(name)
                xs = series[name].tolist()
                ys = series["Mean"].tolist()
                low = [max(0.0, m - l) for m, l in zip(ys, series["MeanCILow"])]
                high = [max(0.0, h - m) for m, h in zip(ys, series["MeanCIHigh"])]
                if kind == "log":
                    low = [min(d, y * 0.999) if y > 0 else 0 for d, y in zip(low, ys)]
                    ys = positive_or_nan(ys)
                axis.errorbar(xs, ys, yerr=[low, high], color=styles.colour(approach),
                              marker=styles.marker(approach), markersize=6, linewidth=1.5,
                              capsize=3, label=approach)
            axis.set_xlabel(name)
            axis.set_ylabel(ylabel)
            axis.grid(True, alpha=0.3)
            parameter_ticks(axis.xaxis, values)
            if kind == "log":
                axis.set_yscale("log")
                axis.yaxis.set_major_formatter(seconds_formatter())
            elif kind == "percent":
                percent_axis(axis.yaxis)
        # Below the panels, never over their data.
        handles, labels = axes[0].get_legend_handles_labels()
        figure.legend(handles, labels, loc="lower center", ncol=min(len(labels), 5) or 1,
                      frameon=False, fontsize=9)
        legend_rows = math.ceil(len(labels) / 5) if labels else 0
        where = "edge case" if prefix else "all configurations"
        title = f"Sweep of {name} ({where}; mean and 95% bootstrap interval over runs"
        title += (", " + ", ".join(fixed) if fixed else "") + ")"
        figure.suptitle(title, fontsize=12)
        figure.tight_layout(rect=(0, 0.06 * legend_rows, 1, 1))
        save(figure, out_dir / f"{prefix}sweep_{file_token(name)}.png", written)


def parameter_ticks(axis, values):
    """Ticks at a swept parameter's values when they are few; otherwise
    matplotlib's, whole numbers only for a parameter whose values all are
    (no 2.25 between the swept 2 and 3)."""
    from matplotlib.ticker import FixedLocator, FuncFormatter, MaxNLocator
    whole = all(float(value).is_integer() for value in values)
    if 0 < len(values) <= 12:
        axis.set_major_locator(FixedLocator(values))
    elif whole:
        axis.set_major_locator(MaxNLocator(integer=True))
    if whole:
        axis.set_major_formatter(FuncFormatter(lambda value, _position: f"{value:.0f}"))
    else:
        axis.set_major_formatter(FuncFormatter(lambda value, _position: f"{value:g}"))


def plot_performance_profile(repeats, styles, out_dir, written, prefix=""):
    """rliable's performance profile (score distribution) of the success
    rate: for each approach, the share of all its runs (configurations x
    repeats) whose AvgSuccessRate exceeds tau, against tau; a curve further
    up and right is better, and one that dominates another is better on
    every threshold."""
    import numpy as np
    plt = pyplot()
    approaches = styles.ordered(repeats["Approach"].unique())
    values = repeats["AvgSuccessRate"]
    low = max(0.0, float(values.min()) - 0.01)
    taus = np.linspace(low, 1.0, 400)
    figure, axis = plt.subplots(figsize=(10.0, 5.2))
    for approach in approaches:
        scores = np.sort(repeats.loc[repeats["Approach"] == approach, "AvgSuccessRate"].to_numpy())
        share = 1.0 - np.searchsorted(scores, taus, side="right") / len(scores)
        axis.step(taus, share, where="post", color=styles.colour(approach), linewidth=1.8,
                  label=approach)
    runs = repeats.groupby("Approach").size().min()
    configurations = len(repeats[["Size", "Difficulty"]].drop_duplicates())
    axis.set_xlabel("Average success rate τ")
    axis.set_ylabel("Share of runs with success rate > τ")
    percent_axis(axis.xaxis)
    axis.set_ylim(-0.02, 1.02)
    axis.grid(True, alpha=0.3)
    axis.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=9, frameon=False)
    what = "edge case" if prefix else f"{configurations} configurations"
    axis.set_title(f"Performance profile of the success rate ({what}, {runs} runs per approach)",
                   fontsize=11.5)
    figure.tight_layout()
    save(figure, out_dir / f"{prefix}performance_profile_success.png", written)


# ----------------------------------------------------------------------------
# Figures 2, 4, 7: one figure per configuration from the per-step rows.


def adaptation_steps(rows):
    return rows[rows["TimeStep"] >= 1].sort_values("TimeStep")


def plot_adapt_box(rows, size, difficulty, styles, path, written, label):
    plt = pyplot()
    approaches = styles.ordered(rows["Approach"].unique())
    steps = adaptation_steps(rows)
    boxes, names, not_shown = [], [], []
    for approach in approaches:
        times = steps.loc[steps["Approach"] == approach, "AdaptTime"].dropna()
        positive = times[times > 0]
        if times.empty:
            not_shown.append(f"{approach} (no step ≥ 1)")
        elif positive.empty:
            not_shown.append(f"{approach} (0 s at every step)")
        else:
            boxes.append(positive.to_numpy())
            zeros = len(times) - len(positive)
            names.append(approach if zeros == 0 else f"{approach}\n({zeros} steps at 0 s)")
    figure, axis = plt.subplots(figsize=(max(7.5, 1.35 * len(boxes) + 3.0), 5.2))
    if boxes:
        drawn = axis.boxplot(boxes, positions=range(len(boxes)), widths=0.55, patch_artist=True,
                             showmeans=True, whis=1.5,
                             medianprops=dict(color="black", linewidth=1.6),
                             meanprops=dict(marker="^", markerfacecolor="white",
                                            markeredgecolor="black", markersize=7),
                             flierprops=dict(marker=".", markersize=4, alpha=0.6))
        for index, approach in enumerate(name.split("\n")[0] for name in names):
            colour = styles.colour(approach)
            drawn["boxes"][index].set(facecolor=colour + "59", edgecolor=colour, linewidth=1.4)
            for part in ("whiskers", "caps"):
                for line in drawn[part][2 * index:2 * index + 2]:
                    line.set(color=colour, linewidth=1.3)
            drawn["fliers"][index].set(markerfacecolor=colour, markeredgecolor=colour)
        axis.set_xticks(range(len(boxes)))
        axis.set_xticklabels(names, rotation=20, ha="right", rotation_mode="anchor")
        axis.set_yscale("log")
        axis.yaxis.set_major_formatter(seconds_formatter())
        axis.grid(True, which="major", axis="y", alpha=0.3)
        axis.grid(True, which="minor", axis="y", alpha=0.1)
    else:
        axis.set_xticks([])
        axis.text(0.5, 0.5, "no adaptation time above 0 s", ha="center", va="center",
                  transform=axis.transAxes)
    steps_shown = (f" (time steps {int(steps['TimeStep'].min())}–{int(steps['TimeStep'].max())})"
                   if not steps.empty else " (no time step after step 0)")
    axis.set_ylabel("Adaptation time per step (s, log scale)")
    caption = "box: quartiles · whiskers: 1.5×IQR · △ mean · dots: outliers"
    if not_shown:
        caption += "\nnot shown: " + ", ".join(not_shown)
    axis.set_xlabel(caption, fontsize=9, color="#333333")
    axis.set_title(f"Adaptation time per step: {label}{configuration_title(size, difficulty)}"
                   f"{steps_shown}")
    figure.tight_layout()
    save(figure, path, written)


def staggered(rank, approaches, points, markers):
    """About `markers` markers per line, each approach's shifted so that the
    markers of overlapping lines do not hide one another."""
    every = max(1, points // markers)
    return (rank * every // max(1, approaches), every)


def time_series_axis_setup(axis, last_step):
    # Half a step beyond the first and last: the bars of the obstacle changes
    # (0.8 wide, centred on their step) are not cut at the edges.
    axis.set_xlim(-0.5, max(last_step, 1) + 0.5)
    axis.grid(True, alpha=0.3)


# Totals spanning this factor or more (A* Oracle's 66 s beside 0.01 s) get a
# second panel with a log axis: on the linear one the small ones lie flat.
CUMULATIVE_LOG_SPAN = 100.0


def plot_cumulative_adapt(rows, size, difficulty, styles, path, written, label):
    plt = pyplot()
    approaches = styles.ordered(rows["Approach"].unique())
    last_step = int(rows["TimeStep"].max())
    lines = []
    for approach in approaches:
        series = rows[rows["Approach"] == approach].sort_values("TimeStep")
        times = series["AdaptTime"].where(series["TimeStep"] >= 1, 0.0).fillna(0.0)
        lines.append((approach, series["TimeStep"], times.cumsum()))
    totals = [cumulative.iloc[-1] for _, _, cumulative in lines if cumulative.iloc[-1] > 0]
    log_panel = bool(totals) and max(totals) / min(totals) >= CUMULATIVE_LOG_SPAN
    if log_panel:
        figure, axes = plt.subplots(1, 2, figsize=(15, 5.2))
    else:
        figure, axis = plt.subplots(figsize=(10, 5.2))
        axes = [axis]
    for axis in axes:
        for rank, (approach, steps, cumulative) in enumerate(lines):
            ys = cumulative if axis is axes[0] else cumulative.where(cumulative > 0)
            axis.plot(steps, ys, color=styles.colour(approach), marker=styles.marker(approach),
                      markevery=staggered(rank, len(approaches), len(steps), 10),
                      markersize=6, linewidth=1.7,
                      label=f"{approach} (total {format_seconds(cumulative.iloc[-1])})")
        time_series_axis_setup(axis, last_step)
        axis.set_xlabel("Time step")
    axes[0].set_ylim(bottom=0)
    axes[0].set_ylabel("Cumulative adaptation time (s)")
    title = f"Cumulative adaptation time: {label}{configuration_title(size, difficulty)}"
    if log_panel:
        axes[0].set_title("linear axis")
        axes[1].set_yscale("log")
        axes[1].yaxis.set_major_formatter(seconds_formatter())
        axes[1].grid(True, which="minor", axis="y", alpha=0.1)
        axes[1].set_ylabel("Cumulative adaptation time (s, log scale)")
        axes[1].set_title("log axis (totals span "
                          f"{math.floor(math.log10(max(totals) / min(totals)))}+ decades)")
        figure.suptitle(title, fontsize=12)
    else:
        axes[0].set_title(title)
    axes[-1].legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False, fontsize=9.5)
    figure.tight_layout()
    save(figure, path, written)


def format_seconds(value):
    if value == 0:
        return "0 s"
    if value >= 100:
        return f"{value:.0f} s"
    if value >= 0.1:
        return f"{value:.3g} s"
    if value >= 1e-3:
        return f"{value * 1e3:.3g} ms"
    return f"{value * 1e6:.3g} µs"


def plot_success_over_time(rows, size, difficulty, styles, path, written, label):
    from matplotlib.ticker import MaxNLocator
    plt = pyplot()
    approaches = styles.ordered(rows["Approach"].unique())
    figure, (axis, changes_axis) = plt.subplots(
        2, 1, figsize=(10, 6.0), sharex=True, gridspec_kw=dict(height_ratios=[4, 1]))
    last_step = int(rows["TimeStep"].max())
    for rank, approach in enumerate(approaches):
        series = rows[rows["Approach"] == approach].sort_values("TimeStep")
        mean = series["SuccessRate"].mean()
        # Earlier approaches drawn wider underneath, so identical curves (the
        # two oracles) both stay visible.
        axis.plot(series["TimeStep"], series["SuccessRate"], color=styles.colour(approach),
                  marker=styles.marker(approach), markevery=staggered(rank, len(approaches), len(series), 12),
                  markersize=6, linewidth=max(1.2, 3.0 - 0.3 * rank), alpha=0.9, zorder=2 + rank,
                  label=f"{approach} (mean {mean:.1%})")
    time_series_axis_setup(axis, last_step)
    low, high = axis.get_ylim()
    axis.set_ylim(low, min(high, 1.01))
    percent_axis(axis.yaxis)
    axis.set_ylabel("Success rate (% of start cells)")
    axis.set_title(f"Success rate over time: {label}{configuration_title(size, difficulty)}")
    axis.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False, fontsize=9.5)
    first = rows[rows["Approach"] == approaches[0]].sort_values("TimeStep")
    changes_axis.bar(first["TimeStep"], first["NumChanges"], width=0.8, color="#777777")
    time_series_axis_setup(changes_axis, last_step)
    changes_axis.yaxis.set_major_locator(MaxNLocator(nbins=3, integer=True))
    changes_axis.set_ylabel("Obstacle\nchanges")
    changes_axis.set_xlabel("Time step")
    figure.tight_layout()
    save(figure, path, written)


PER_CONFIGURATION_FIGURES = [
    ("adapt_box", plot_adapt_box),
    ("cumulative_adapt", plot_cumulative_adapt),
    ("success_over_time", plot_success_over_time),
]


def plot_per_configuration(detailed, styles, out_dir, written, prefix=""):
    label = "edge case, " if prefix else ""
    for size, difficulty in configurations_of(detailed):
        rows = detailed[(detailed["Size"] == size) & (detailed["Difficulty"] == difficulty)]
        suffix = f"{file_token(size)}_{file_token(difficulty)}"
        for name, draw in PER_CONFIGURATION_FIGURES:
            draw(rows, size, difficulty, styles, out_dir / f"{prefix}{name}_{suffix}.png",
                 written, label)


# ----------------------------------------------------------------------------
# The edge case's summary: its four averages per approach as bars.


EDGE_SUMMARY_PANELS = [
    ("AvgSuccessRate", "Average success rate (%)", "percent"),
    ("AdaptTimePerStep", "Adaptation time per step (s)", "log"),
    ("AvgPathLength", "Average path length (steps)", "linear"),
    ("InitialTime", "Initial training time (s)", "log"),
]


def plot_edge_summary(summary, reference, styles, out_dir, written, intervals=None):
    """With `intervals`, the bars are the means over the repeats, with their
    95% bootstrap intervals."""
    plt = pyplot()
    for size, difficulty in configurations_of(summary):
        rows = summary[(summary["Size"] == size) & (summary["Difficulty"] == difficulty)]
        approaches = styles.ordered(rows["Approach"].unique())
        published = None
        if reference is not None:
            published = reference[(reference["Size"] == size)
                                  & (reference["Difficulty"] == difficulty)]
            if published.empty:
                published = None
        figure, axes = plt.subplots(2, 2, figsize=(max(9.0, 1.3 * len(approaches) + 3.5), 8.2))
        for axis, (column, ylabel, kind) in zip(axes.flat, EDGE_SUMMARY_PANELS):
            values = [rows.loc[rows["Approach"] == approach, column].iloc[0]
                      for approach in approaches]
            errors = None
            if intervals is not None and all((a, size, difficulty, column) in intervals
                                             for a in approaches):
                stats = [intervals[(a, size, difficulty, column)] for a in approaches]
                values = [value[1] for value in stats]
                errors = [[max(0.0, value[1] - value[2]) for value in stats],
                          [max(0.0, value[3] - value[1]) for value in stats]]
            heights = positive_or_nan(values) if kind == "log" else values
            axis.bar(range(len(approaches)), [0 if math.isnan(h) else h for h in heights],
                     color=[styles.colour(a) + "99" for a in approaches],
                     edgecolor=[styles.colour(a) for a in approaches], linewidth=1.3, width=0.65)
            if errors is not None:
                if kind == "log":
                    errors[0] = [min(d, h * 0.999) if h > 0 else 0
                                 for d, h in zip(errors[0], values)]
                axis.errorbar(range(len(approaches)), [0 if math.isnan(h) else h for h in heights],
                              yerr=errors, fmt="none", ecolor="black", elinewidth=1.2, capsize=4,
                              zorder=5)
            if kind == "log":
                axis.set_yscale("log")
                axis.yaxis.set_major_formatter(seconds_formatter())
                for index, value in enumerate(values):
                    if not value > 0:
                        axis.annotate("0 s", (index, 0), xycoords=("data", "axes fraction"),
                                      xytext=(0, 3), textcoords="offset points", ha="center",
                                      fontsize=9)
            if published is not None:
                for index, approach in enumerate(approaches):
                    match = published.loc[published["Approach"] == approach, column]
                    if not match.empty and (kind != "log" or match.iloc[0] > 0):
                        axis.plot(index, match.iloc[0], linestyle="none",
                                  marker=styles.marker(approach), markersize=9,
                                  markerfacecolor="none", markeredgecolor="black",
                                  markeredgewidth=1.5, zorder=4)
            if kind == "percent":
                percent_axis(axis.yaxis)
                low = min([v for v in values if not math.isnan(v)] + [1.0])
                axis.set_ylim(max(0.0, low - 0.1), 1.02)
            axis.set_ylabel(ylabel)
            axis.set_xticks(range(len(approaches)))
            axis.set_xticklabels(approaches, rotation=25, ha="right", rotation_mode="anchor",
                                 fontsize=9)
            axis.grid(True, axis="y", alpha=0.3)
        title = f"Edge case: {configuration_title(size, difficulty)}, averages per approach"
        if intervals is not None:
            repeats = min((value[0] for key, value in intervals.items()
                           if key[1] == size and key[2] == difficulty), default=0)
            title += f"\n(mean of {repeats} repeats, 95% bootstrap interval)"
        if published is not None:
            from matplotlib.lines import Line2D
            marker = Line2D([], [], linestyle="none", marker="o", markersize=8,
                            markerfacecolor="none", markeredgecolor="black", markeredgewidth=1.5,
                            label=f"report ({REFERENCE_SOURCE}; its times: i7-1165G7)")
            figure.legend(handles=[marker], loc="lower center", frameon=False, fontsize=9.5)
            figure.suptitle(title, fontsize=13)
            figure.tight_layout(rect=(0, 0.04, 1, 1))
        else:
            figure.suptitle(title, fontsize=13)
            figure.tight_layout()
        save(figure, out_dir / f"{EDGE_PREFIX}summary_{file_token(size)}_{file_token(difficulty)}"
                               ".png", written)


# ----------------------------------------------------------------------------


def run(argv):
    args = parse_arguments(argv)
    if args.compare is not None:
        return run_compare(args)
    if args.study is None:
        raise PlotError("the following arguments are required: DIR (see --help)", EXIT_USAGE)
    study = Path(args.study)
    if not study.is_dir():
        raise PlotError(f"{study}: no such directory", EXIT_USAGE)
    reference_dir = reference_dir_from(args)
    import_libraries()
    warnings.simplefilter("ignore")

    summary_path = study / SUMMARY_FILE
    edge_present = any((study / (EDGE_PREFIX + name)).exists()
                       for name in (SUMMARY_FILE, DETAILED_FILE))
    main_present = summary_path.exists() or (study / DETAILED_FILE).exists()
    if not main_present and not edge_present:
        raise PlotError(f"{study}: no {SUMMARY_FILE} or {DETAILED_FILE} "
                        "(expected the output directory of dynapath run)")
    summary, detailed = read_study(study, "", optional=edge_present)
    edge_summary, edge_detailed = read_study(study, EDGE_PREFIX, optional=True)
    intervals = read_intervals(study / REPEAT_SUMMARY_FILE)
    edge_intervals = read_intervals(study / (EDGE_PREFIX + REPEAT_SUMMARY_FILE))
    repeats = read_repeats(study / REPEATS_FILE)
    edge_repeats = read_repeats(study / (EDGE_PREFIX + REPEATS_FILE))
    sweep = read_sweep(study / SWEEP_SUMMARY_FILE)
    edge_sweep = read_sweep(study / (EDGE_PREFIX + SWEEP_SUMMARY_FILE))

    reference = edge_reference = None
    if reference_dir is not None:
        reference = read_summary(reference_dir / "paper_results.csv")
        edge_file = reference_dir / "paper_edge_results.csv"
        if edge_file.exists():
            edge_reference = read_summary(edge_file)

    approaches = set()
    for frame in (summary, detailed, edge_summary, edge_detailed):
        if frame is not None:
            approaches.update(frame["Approach"].unique())
    styles = Styles(approaches)

    FORMATS[:] = args.format
    out_dir = Path(args.out) if args.out else study / "figures"
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise PlotError(f"{out_dir}: cannot create the output directory: {error.strerror}") \
            from None

    pyplot().rcParams.update({"axes.titlesize": 11.5, "axes.labelsize": 10.5,
                              "xtick.labelsize": 9.5, "ytick.labelsize": 9.5})
    written = []
    if summary is not None:
        plot_by_size(summary, reference, styles, out_dir, written, intervals)
        plot_per_configuration(detailed, styles, out_dir, written)
        if repeats is not None:
            plot_performance_profile(repeats, styles, out_dir, written)
        if sweep is not None:
            plot_sweeps(sweep, styles, out_dir, written)
    if edge_summary is not None:
        plot_per_configuration(edge_detailed, styles, out_dir, written, prefix=EDGE_PREFIX)
        plot_edge_summary(edge_summary, edge_reference, styles, out_dir, written, edge_intervals)
        if edge_repeats is not None:
            plot_performance_profile(edge_repeats, styles, out_dir, written, prefix=EDGE_PREFIX)
        if edge_sweep is not None:
            plot_sweeps(edge_sweep, styles, out_dir, written, prefix=EDGE_PREFIX)
    for path in written:
        print(path)
    return 0


COMPARE_COLUMNS = ["A", "B", "Size", "Difficulty", "Metric", "Pairs", "MeanDifference",
                   "MeanCILow", "MeanCIHigh"]
COMPARE_PANELS = [
    ("AvgSuccessRate", "success rate (percentage points)", 100.0),
    ("AvgPathLength", "path length (steps)", 1.0),
    ("AdaptTimePerStep", "adaptation time per step (ms)", 1000.0),
    ("InitialTime", "initial training time (ms)", 1000.0),
]


def run_compare(args):
    """The figure of `dynapath compare --plot FILE`: one panel per metric,
    one row per configuration (and all of them, stratified), the mean
    difference A - B with its 95% bootstrap interval, a line at 0."""
    if args.study is not None:
        raise PlotError("--compare draws one comparison: give no study directory", EXIT_USAGE)
    if not args.out:
        raise PlotError("--compare needs --out FILE (.png, .svg or .pdf)", EXIT_USAGE)
    out = Path(args.out)
    if out.suffix.lower() not in (".png", ".svg", ".pdf"):
        raise PlotError(f"--out {out}: the figure must end in .png, .svg or .pdf", EXIT_USAGE)
    import_libraries()
    warnings.simplefilter("ignore")
    import pandas as pd
    path = Path(args.compare)
    try:
        frame = pd.read_csv(path, dtype=str, keep_default_na=False)
    except (OSError, pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as error:
        raise PlotError(f"{path}: not a readable CSV table: {error}") from None
    missing = [column for column in COMPARE_COLUMNS if column not in frame.columns]
    if missing or frame.empty:
        raise PlotError(f"{path}: not the CSV of dynapath compare "
                        f"({'missing ' + ', '.join(missing) if missing else 'no rows'})")
    for column in ("MeanDifference", "MeanCILow", "MeanCIHigh"):
        frame[column] = pd.to_numeric(frame[column], errors="coerce")
    configurations = list(dict.fromkeys(zip(frame["Size"], frame["Difficulty"])))
    labels = ["all (stratified)" if size == "all" else configuration_title(size, difficulty)
              for size, difficulty in configurations]
    a, b = frame["A"].iloc[0], frame["B"].iloc[0]
    plt = pyplot()
    figure, axes = plt.subplots(1, len(COMPARE_PANELS), sharey=True,
                                figsize=(15.0, 2.4 + 0.38 * len(configurations)))
    for axis, (metric, label, scale) in zip(axes, COMPARE_PANELS):
        rows = frame[frame["Metric"] == metric]
        for index, (size, difficulty) in enumerate(configurations):
            row = rows[(rows["Size"] == size) & (rows["Difficulty"] == difficulty)]
            if row.empty:
                continue
            mean, low, high = (scale * row[c].iloc[0]
                               for c in ("MeanDifference", "MeanCILow", "MeanCIHigh"))
            resolved = low > 0 or high < 0
            colour = "#0072b2" if resolved else "#777777"
            axis.errorbar([mean], [index], xerr=[[max(0.0, mean - low)], [max(0.0, high - mean)]],
                          fmt="D" if size == "all" else "o", color=colour, capsize=3,
                          markersize=6)
        axis.axvline(0.0, color="black", linewidth=0.9)
        axis.set_title(label)
        axis.set_xlabel("A − B")
        axis.grid(True, axis="x", alpha=0.3)
    axes[0].set_yticks(range(len(configurations)))
    axes[0].set_yticklabels(labels)
    axes[0].invert_yaxis()
    figure.suptitle(f"Paired differences A − B, A = {a}, B = {b}, over the repeats\n(mean and "
                    "95% bootstrap interval; blue: the interval excludes 0)", fontsize=12)
    figure.tight_layout()
    try:
        figure.savefig(out, dpi=DPI)
    except OSError as error:
        raise PlotError(f"{out}: cannot write the figure: {error.strerror}") from None
    pyplot().close(figure)
    print(out)
    return 0


def main():
    try:
        return run(sys.argv[1:])
    except PlotError as error:
        print(f"{PROG}: {error}", file=sys.stderr)
        return error.status
    except KeyboardInterrupt:
        print(f"{PROG}: interrupted", file=sys.stderr)
        return 130
    except OSError as error:
        where = f"{error.filename}: " if error.filename else ""
        print(f"{PROG}: {where}{error.strerror or error}", file=sys.stderr)
        return EXIT_DATA
    except Exception as error:  # noqa: BLE001 - never a traceback, but say what failed
        print(f"{PROG}: failed: {type(error).__name__}: {' '.join(str(error).split())}",
              file=sys.stderr)
        return EXIT_DATA


if __name__ == "__main__":
    sys.exit(main())
