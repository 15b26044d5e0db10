#!/usr/bin/env python3
"""Writes a report of a study: its results beside the report's published
ones (when the study ran the report's mazes), row by row.

Usage: scripts/make_reproduction_report.py STUDY_DIR OUTPUT.md
           [--images DIR] [--intro FILE]
           [--more-sizes STUDY_DIR2] [--report-semantics REPORT_STUDY_DIR]
           [--like-for-like CSV] [--spread SPREAD_DIR] [--dynapath PATH]
           [--figures FIGURES_DIR]

It writes OUTPUT.md and copies the figures it shows into DIR (default: the
folder `images` beside OUTPUT.md, `reproduction/` and `maps/` in it), and
nothing else. Everything it says comes from the studies it is given: a
section whose inputs are missing is left out, and with no --intro the
header states the study's own facts (commands, commit, machine, repeats).
The project's own docs/REPRODUCTION.md is one invocation, with the
project's findings text (--intro scripts/reproduction_intro.md, whose
{{PLACEHOLDERS}} must all be filled from the inputs, or nothing is written);
docs/howto/PLOTTING.md gives the exact command.

STUDY_DIR is a study of `dynapath experiment` (results.csv,
results_detailed.csv, manifest.json; with `--repeats N` also summary.csv,
repeats.csv and their edge_ files); its figures are those `dynapath plot
STUDY_DIR --overlay-reference` drew into STUDY_DIR/figures (or FIGURES_DIR:
those of a study merged from STUDY_DIR and STUDY_DIR2, so that they show
every size). The approaches, their order and which of them learn (those that
train quadtree nodes, NodesTrained > 0) are read from the study. Only a study
of the report's mazes (default seeds and steps, `manifest.json`) is set beside
the report's published values. With repeats every row gives our mean over the
repeats and its 95% bootstrap interval (summary.csv) and says whether the
report's published value lies inside it; without, the single run's values.
STUDY_DIR2 is a study of other sizes (200 and 300, typically with fewer
repeats) whose rows complete the table (sizes of STUDY_DIR take
precedence). REPORT_STUDY_DIR is a study of hard 50x50 (seed 52) and the
edge case run with `--semantics report` (with repeats: the spread of
`singleAgent` against the report code's ten runs under both semantics).
The paired differences fedAsynQ_EqAvg - fedAsynQ_ImAvg are those of
`dynapath compare --csv` (PATH, default build/tools/dynapath), run on the
studies with repeats. CSV is the output of `bench/like_for_like.sh --csv`.
SPREAD_DIR holds the outputs of `bench/semantics_spread ... report`
(VARIANT = double: `--semantics report`, whose tables are doubles as the
report code's) and of `bench/semantics_spread ... report-float` (VARIANT =
float: the same rules on float tables), named VARIANT_APPROACH_SEED.txt, for
seeds 52 and 102. The report's figures, published and run on this machine,
are read from docs/reference/. Standard library only (no pandas needed).

Exit status: 0 written; 1 bad or missing input (nothing written); 2 bad usage.
"""
import csv
import json
import os
import re
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
REFERENCE = os.path.join(HERE, "..", "docs", "reference")
# Figures of `dynapath plot` shown in the report, with their captions; the
# per-configuration ones are chosen from the study (choose_figures).
BY_SIZE_FIGURES = [
    ("success_rate_by_size.png", "Success rate by maze size (dashed, hollow: the report)"),
    ("path_length_by_size.png", "Average path length by maze size"),
    ("initial_time_by_size.png", "Initial training time by maze size (log scale)"),
    ("adapt_time_by_size.png", "Adaptation time per time step by maze size (log scale)"),
]
# Box plots come from the largest size up to this one: beyond it the
# learners' boxes are dominated by the retraining bursts of a few steps.
BOX_SIZE_LIMIT = 100

# The study's approaches in its order and those that learn, set by
# use_approaches() from the study itself.
ORDER = []
RL = []


class InputError(Exception):
    """Bad or missing input: one line on stderr, exit 1, nothing written."""


def use_approaches(studies):
    """ORDER and RL from the studies: the manifest's approach list (else the
    order of results.csv), and the approaches that train quadtree nodes
    (NodesTrained > 0 in a detailed result file) as the learning ones."""
    order, learning = [], set()
    for study in studies:
        listed = study.manifest.get("options", {}).get("study", {}).get("approaches") or []
        for name in listed + [r["Approach"] for r in study.results + study.edge_results]:
            if name not in order:
                order.append(name)
        for name in ("results_detailed.csv", "edge_results_detailed.csv"):
            for r in study._read(name):
                if float(r.get("NodesTrained") or 0) > 0:
                    learning.add(r["Approach"])
    ORDER[:] = order
    RL[:] = [name for name in order if name in learning]


DIFFICULTIES = ["Easy", "Medium", "Hard"]
# The acceptance check for sizes 20 and 50: success >= report - 0.005 and
# path length <= report + 0.3.
SUCCESS_TOLERANCE = 0.005
LENGTH_TOLERANCE = 0.3


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def index(rows):
    return {(r["Approach"], r["Size"], r["Difficulty"]): r for r in rows}


def fmt(value, digits=4):
    return "–" if value is None else f"{value:.{digits}f}"


def ratio(ours, theirs):
    if ours is None or theirs in (None, 0):
        return "–"
    return f"{ours / theirs:.3g}"


METRICS = ("AvgSuccessRate", "AvgPathLength", "InitialTime", "AdaptTimePerStep")


class Stat:
    """One approach's metric on one configuration: over the repeats (mean,
    95% bootstrap interval of the mean, from summary.csv; the repeats' own
    values from repeats.csv) or, for a study without repeats, its one run."""

    def __init__(self, n, mean, low=None, high=None, values=None):
        self.n, self.mean, self.low, self.high = n, mean, low, high
        self.values = values or [mean]

    @property
    def has_interval(self):
        return self.n > 1 and self.low is not None and self.high is not None

    def contains(self, value):
        """True/False whether `value` lies inside the interval; None without one."""
        if value is None or not self.has_interval:
            return None
        return self.low <= value <= self.high


class Study:
    """A study directory of `dynapath experiment`: its result files, and
    with repeats its summary.csv and repeats.csv (and the edge case's)."""

    def __init__(self, directory):
        self.dir = directory
        self.name = os.path.basename(os.path.normpath(directory))
        try:
            with open(os.path.join(directory, "manifest.json")) as f:
                self.manifest = json.load(f)
        except (OSError, ValueError):
            self.manifest = {}
        self.results = [r for r in self._read("results.csv") if is_maze_row(r)]
        self.edge_results = self._read("edge_results.csv")
        self.summary = self._summary("summary.csv")
        self.edge_summary = self._summary("edge_summary.csv")
        self.repeats = self._repeats("repeats.csv")
        self.edge_repeats = self._repeats("edge_repeats.csv")

    def _read(self, name):
        path = os.path.join(self.dir, name)
        return read(path) if os.path.exists(path) else []

    def _summary(self, name):
        return {(r["Approach"], r["Size"], r["Difficulty"], r["Metric"]): r
                for r in self._read(name)}

    def _repeats(self, name):
        runs = {}
        for r in self._read(name):
            runs.setdefault((r["Approach"], r["Size"], r["Difficulty"]), []).append(r)
        for rows in runs.values():
            rows.sort(key=lambda r: int(r["Repeat"]))
        return runs

    @property
    def has_repeats(self):
        return bool(self.summary or self.edge_summary)

    def sizes(self):
        return sorted({r["Size"] for r in self.results}, key=int)

    def repeat_count(self):
        return self.manifest.get("options", {}).get("study", {}).get("repeats") or 1

    def stat(self, approach, size, difficulty, metric, edge=False):
        summary = self.edge_summary if edge else self.summary
        repeats = self.edge_repeats if edge else self.repeats
        row = summary.get((approach, size, difficulty, metric))
        if row is not None:
            values = [float(r[metric]) for r in repeats.get((approach, size, difficulty), [])]
            return Stat(int(row["Repeats"]), float(row["Mean"]), float(row["MeanCILow"]),
                        float(row["MeanCIHigh"]), values or None)
        for r in (self.edge_results if edge else self.results):
            if (r["Approach"], r["Size"], r["Difficulty"]) == (approach, size, difficulty):
                return Stat(1, float(r[metric]))
        return None

    def run(self, approach, size, difficulty, repeat, edge=False):
        """Repeat `repeat`'s row (repeat 1 is the run without repeats)."""
        repeats = self.edge_repeats if edge else self.repeats
        rows = [r for r in repeats.get((approach, size, difficulty), [])
                if int(r["Repeat"]) == repeat]
        if rows:
            return rows[0]
        if repeat == 1:
            for r in (self.edge_results if edge else self.results):
                if (r["Approach"], r["Size"], r["Difficulty"]) == (approach, size, difficulty):
                    return r
        return None

    def mean_rows(self, edge=False):
        """results.csv's rows with every metric replaced by its mean over the repeats."""
        rows = []
        for r in (self.edge_results if edge else self.results):
            row = dict(r)
            for metric in METRICS:
                s = self.stat(r["Approach"], r["Size"], r["Difficulty"], metric, edge)
                if s is not None:
                    row[metric] = repr(s.mean)
            rows.append(row)
        return rows


class Studies:
    """The main study and those of further sizes (--more-sizes): each size
    is read from the first study that has it."""

    def __init__(self, studies):
        self.studies = studies
        self.by_size = {}
        for study in studies:
            for size in study.sizes():
                self.by_size.setdefault(size, study)

    def sizes(self):
        return sorted(self.by_size, key=int)

    def stat(self, approach, size, difficulty, metric):
        study = self.by_size.get(size)
        return None if study is None else study.stat(approach, size, difficulty, metric)

    def mean_rows(self):
        rows = []
        for size in self.sizes():
            rows += [r for r in self.by_size[size].mean_rows() if r["Size"] == size]
        return rows


def fmt_ci(stat, digits):
    """`mean [low, high]`, or the value alone for one run."""
    if stat is None:
        return "–"
    if not stat.has_interval:
        return f"{stat.mean:.{digits}f}"
    return f"{stat.mean:.{digits}f} [{stat.low:.{digits}f}, {stat.high:.{digits}f}]"


def yes_no(inside):
    return "–" if inside is None else ("yes" if inside else "**no**")


def verdict(approach, size, success, length, ref):
    """The acceptance check on our means over the repeats."""
    if approach not in RL or size not in ("20", "50") or ref is None or success is None:
        return ""
    ok_success = success.mean >= float(ref["AvgSuccessRate"]) - SUCCESS_TOLERANCE
    ok_length = length.mean <= float(ref["AvgPathLength"]) + LENGTH_TOLERANCE
    return "pass" if ok_success and ok_length else "**FAIL**"


class InsideCount:
    """How many rows' published values lie inside our intervals."""

    def __init__(self):
        self.rows = []  # (label, approach, learns, success inside, path inside)

    def add(self, label, approach, success_inside, path_inside):
        if success_inside is None and path_inside is None:
            return
        self.rows.append((label, approach, approach in RL, success_inside, path_inside))

    def counts(self, learns):
        rows = [r for r in self.rows if r[2] == learns]
        return (len(rows), sum(bool(r[3]) for r in rows), sum(bool(r[4]) for r in rows),
                sum(bool(r[3] and r[4]) for r in rows))

    def outside(self, learns):
        return [r for r in self.rows if r[2] == learns and not (r[3] and r[4])]


def table(lookup, ref_rows, sizes, difficulties, count, edge=False):
    """Every approach of every configuration: our mean and 95% interval over
    the repeats against the report's published row. `lookup(approach, size,
    difficulty, metric)` gives our Stat."""
    ref = index(ref_rows)
    lines = [
        "| Size | Difficulty | Approach | Runs | Success: ours, mean [95% CI] | Success (report) "
        "| report inside | Path: ours, mean [95% CI] | Path (report) | report inside "
        "| Initial s (ours, mean) | Initial s (report) | Adapt s/step (ours, mean) "
        "| Adapt s/step (report) | Adapt ratio | Check |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    failures = 0
    for size, difficulty, approach, success, length, initial, adapt in configuration_stats(
            lookup, sizes, difficulties):
        r = ref.get((approach, size, difficulty))
        g = lambda key: None if r is None else float(r[key])
        check = verdict(approach, size, success, length, r)
        failures += check == "**FAIL**"
        in_s = success.contains(g("AvgSuccessRate"))
        in_p = length.contains(g("AvgPathLength"))
        label = "edge case" if edge else f"{size} {difficulty.lower()}"
        count.add(label, approach, in_s, in_p)
        lines.append(
            f"| {size} | {difficulty} | {approach} | {success.n} | {fmt_ci(success, 4)} "
            f"| {fmt(g('AvgSuccessRate'))} | {yes_no(in_s)} | {fmt_ci(length, 3)} "
            f"| {fmt(g('AvgPathLength'), 3)} | {yes_no(in_p)} "
            f"| {fmt(initial.mean, 3)} | {fmt(g('InitialTime'), 3)} "
            f"| {fmt(adapt.mean, 5)} | {fmt(g('AdaptTimePerStep'), 5)} "
            f"| {ratio(adapt.mean, g('AdaptTimePerStep'))} | {check} |")
    return lines, failures


def rl_vs_bfs(ours_rows, sizes):
    ours = index(ours_rows)
    lines = [
        "| Size | Difficulty | BFS Oracle adapt s/step | best RL adapt s/step (approach) | RL / BFS | "
        "BFS success | best RL success |",
        "|---|---|---|---|---|---|---|",
    ]
    for size in sizes:
        for difficulty in DIFFICULTIES:
            bfs = ours.get(("BFS Oracle", size, difficulty))
            if bfs is None:
                continue
            candidates = [ours[(a, size, difficulty)] for a in RL if (a, size, difficulty) in ours]
            fastest = min(candidates, key=lambda r: float(r["AdaptTimePerStep"]))
            best = max(float(r["AvgSuccessRate"]) for r in candidates)
            b = float(bfs["AdaptTimePerStep"])
            f = float(fastest["AdaptTimePerStep"])
            lines.append(f"| {size} | {difficulty} | {b:.2e} | {f:.2e} ({fastest['Approach']}) | "
                         f"{f / b:.2g}x | {float(bfs['AvgSuccessRate']):.4f} | {best:.4f} |")
    return lines


def bfs_facts(ours_rows, sizes):
    """Where the BFS Oracle adapts faster than the fastest RL approach, and
    whether its success rate is at least the best RL approach's everywhere."""
    ours = index(ours_rows)
    faster, slower, accurate, total = [], [], 0, 0
    for size in sizes:
        for difficulty in DIFFICULTIES:
            bfs = ours.get(("BFS Oracle", size, difficulty))
            candidates = [ours[(a, size, difficulty)] for a in RL if (a, size, difficulty) in ours]
            if bfs is None or not candidates:
                continue
            total += 1
            fastest = min(float(r["AdaptTimePerStep"]) for r in candidates)
            best = max(float(r["AvgSuccessRate"]) for r in candidates)
            label = f"{size} {difficulty.lower()}"
            (faster if float(bfs["AdaptTimePerStep"]) < fastest else slower).append(label)
            accurate += float(bfs["AvgSuccessRate"]) >= best
    text = f"{len(faster)} of {total} mazes"
    if slower:
        text += f"; not on {', '.join(slower)}"
    return {"BFS_FASTER": text, "BFS_ACCURATE": f"on {accurate} of {total} mazes"}


def oracle_table(ours_rows, ref_rows, sizes):
    ours = index(ours_rows)
    ref = index(ref_rows)
    lines = ["| Size | Difficulty | BFS Oracle success / path (ours) | A* Oracle success / path (report) | same to 6 digits |",
             "|---|---|---|---|---|"]
    for size in sizes:
        for difficulty in DIFFICULTIES:
            o = ours.get(("BFS Oracle", size, difficulty))
            r = ref.get(("A* Oracle", size, difficulty))
            if o is None or r is None:
                continue
            mine = (f"{float(o['AvgSuccessRate']):.6g}", f"{float(o['AvgPathLength']):.6g}")
            theirs = (f"{float(r['AvgSuccessRate']):.6g}", f"{float(r['AvgPathLength']):.6g}")
            lines.append(f"| {size} | {difficulty} | {mine[0]} / {mine[1]} | {theirs[0]} / {theirs[1]} | "
                         f"{'yes' if mine == theirs else 'no'} |")
    return lines


def speedups(ours_rows, ref_rows, key):
    """Range of report / ours over the RL rows where both are positive."""
    ours = index(ours_rows)
    values = []
    for r in ref_rows:
        o = ours.get((r["Approach"], r["Size"], r["Difficulty"]))
        if r["Approach"] in RL and o is not None and float(o[key]) > 0 and float(r[key]) > 0:
            values.append(float(r[key]) / float(o[key]))
    if not values:
        return "–"
    return f"{min(values):.0f} to {max(values):.0f}"


# Spread of the report's code run here (docs/reference/README.md): hard
# 50x50 seed 52 about +-0.003 success and +-0.05 path around the median; the
# edge case success 0.966-0.977, path 9.29-10.58.
HARD50_SPREAD = (0.003, 0.05)
EDGE_SPREAD = ((0.966, 0.977), (9.29, 10.58))


def inside_spread(success, path, ref, edge):
    if edge:
        (s0, s1), (p0, p1) = EDGE_SPREAD
        return s0 <= success <= s1 and p0 <= path <= p1
    return (abs(success - float(ref["AvgSuccessRate"])) <= HARD50_SPREAD[0] and
            abs(path - float(ref["AvgPathLength"])) <= HARD50_SPREAD[1])


def code_here_table(ours, report, here_rows, published_rows, seed, edge, closeness):
    """Ours (default) and ours under --semantics report (means and intervals
    over the repeats), the report's code run here and its published row, for
    one maze (hard 50x50 of `seed`). Appends to `closeness` per learning
    approach whether the report-semantics mean is at least as close to the
    report code's median as repeat 1 (the single run) is, for both metrics."""
    published = index(published_rows)
    here = {r["Approach"]: r for r in here_rows if r["Seed"] == seed}
    lines = ["| Approach | | ours (default), mean [95% CI] | ours, `--semantics report`, mean "
             "[95% CI] | report's code run here (median of 3) | report's published row "
             "| `report`: distance to its code's median, mean (one run) "
             "| `report` mean inside its code's spread |",
             "|---|---|---|---|---|---|---|---|"]
    for approach in ["A* Oracle"] + RL:
        h = here.get(approach)
        if h is None:
            continue
        stats = {}
        for metric, digits in (("AvgSuccessRate", 4), ("AvgPathLength", 3)):
            o = ours.stat(approach, "50", "Hard", metric, edge) if ours else None
            r = report.stat(approach, "50", "Hard", metric, edge) if report else None
            stats[metric] = r
            p = published.get((approach, "50", "Hard"))
            reference = float(h[metric])
            distance = "–"
            one = report.run(approach, "50", "Hard", 1, edge) if report else None
            if r is not None and approach in RL:
                distance = f"{abs(r.mean - reference):.{digits}f}"
                if one is not None and r.n > 1:
                    one_distance = abs(float(one[metric]) - reference)
                    distance += f" ({one_distance:.{digits}f})"
                    closeness.append((seed, approach, metric,
                                      abs(r.mean - reference) <= one_distance + 10 ** -(digits + 2)))
            name = "success" if metric == "AvgSuccessRate" else "path"
            spread = ""
            if metric == "AvgPathLength":
                s, l = stats["AvgSuccessRate"], stats["AvgPathLength"]
                spread = "–" if s is None or l is None or approach not in RL else yes_no(
                    inside_spread(s.mean, l.mean, h, edge))
            lines.append(
                f"| {approach if metric == 'AvgSuccessRate' else ''} | {name} | {fmt_ci(o, digits)} "
                f"| {fmt_ci(r, digits)} | {reference:.{digits}f} "
                f"| {fmt(None if p is None else float(p[metric]), digits)} | {distance} | {spread} |")
    return lines


def spread_of(values):
    values = sorted(values)
    return values[0], median(values), values[-1], sum(values) / len(values)


def single_agent_runs_table(ours, report, seed, edge, verdicts):
    """singleAgent's repeats under both semantics against the report code's
    own ten runs of it (reference_code_singleAgent_runs.csv), for one maze.
    Appends (seed, semantics, metric, mean, low, high, inside) to `verdicts`."""
    runs_path = os.path.join(REFERENCE, "reference_code_singleAgent_runs.csv")
    if not os.path.exists(runs_path):
        return []
    runs = [r for r in read(runs_path) if r["Seed"] == seed]
    if not runs:
        return []
    lines = ["| | runs | success min – max | success median | success mean [95% CI] "
             "| path min – max | path median | path mean [95% CI] |",
             "|---|---|---|---|---|---|---|---|"]
    theirs = {m: [float(r[m]) for r in runs] for m in ("AvgSuccessRate", "AvgPathLength")}
    cells = []
    for metric, digits in (("AvgSuccessRate", 4), ("AvgPathLength", 3)):
        lo, med, hi, mean = spread_of(theirs[metric])
        cells += [f"{lo:.{digits}f} – {hi:.{digits}f}", f"{med:.{digits}f}", f"{mean:.{digits}f}"]
    lines.append(f"| report's code (`reference_code_singleAgent_runs.csv`) | {len(runs)} | "
                 + " | ".join(cells) + " |")
    sentences = []
    for label, study, semantics in (("ours (default)", ours, "default"),
                                    ("ours, `--semantics report`", report, "report")):
        if study is None:
            continue
        stats = {m: study.stat("singleAgent", "50", "Hard", m, edge)
                 for m in ("AvgSuccessRate", "AvgPathLength")}
        if any(s is None for s in stats.values()):
            continue
        cells = []
        parts = []
        for metric, digits in (("AvgSuccessRate", 4), ("AvgPathLength", 3)):
            s = stats[metric]
            lo, med, hi, _ = spread_of(s.values)
            cells += [f"{lo:.{digits}f} – {hi:.{digits}f}", f"{med:.{digits}f}", fmt_ci(s, digits)]
            t0, t1 = min(theirs[metric]), max(theirs[metric])
            inside = t0 <= s.mean <= t1
            verdicts.append((seed, semantics, metric, s.mean, s.low, s.high, inside, t0, t1))
            parts.append(f"mean {'success' if metric == 'AvgSuccessRate' else 'path'} "
                         f"{s.mean:.{digits}f} is {'inside' if inside else '**outside**'} its "
                         f"ten-run range {t0:.{digits}f} – {t1:.{digits}f}")
        lines.append(f"| {label} | {stats['AvgSuccessRate'].n} | " + " | ".join(cells) + " |")
        sentences.append(f"{label[0].upper() + label[1:]}: " + ", ".join(parts) + ".")
    return lines + [""] + [" ".join(sentences)]


def read_spread(path):
    """Per-stream (success, path) pairs of one semantics_spread output."""
    pairs = []
    with open(path) as f:
        for line in f:
            fields = line.strip().split(",")
            if len(fields) == 5 and fields[0].isdigit():
                pairs.append((float(fields[2]), float(fields[3])))
    return pairs


def median(values):
    values = sorted(values)
    n = len(values)
    return values[n // 2] if n % 2 else 0.5 * (values[n // 2 - 1] + values[n // 2])


def spread_table(spread_dir, here_rows, seed):
    """Ours under --semantics report over learner seed streams (its double
    tables, and the same rules on float tables), against the report's code
    run here, for one maze."""
    here = {r["Approach"]: r for r in here_rows if r["Seed"] == seed}
    lines = ["| Approach | report's code run here (median of 3) | ours: streams | success "
             "min / median / max | path min / median / max | its median inside ours |",
             "|---|---|---|---|---|---|"]
    for approach in RL:
        h = here.get(approach)
        if h is None:
            continue
        ref_s, ref_p = float(h["AvgSuccessRate"]), float(h["AvgPathLength"])
        for variant, label in (("double", "`--semantics report`"),
                               ("float", "same rules, float tables")):
            path = os.path.join(spread_dir, f"{variant}_{approach}_{seed}.txt")
            if not os.path.exists(path):
                continue
            pairs = read_spread(path)
            success = [p[0] for p in pairs]
            length = [p[1] for p in pairs]
            inside_s = min(success) <= ref_s <= max(success)
            inside_p = min(length) <= ref_p <= max(length)
            verdict = ("yes" if inside_s and inside_p else
                       "success only" if inside_s else "path only" if inside_p else "**no**")
            lines.append(
                f"| {approach} | {ref_s:.4f} / {ref_p:.3f} | {label}: {len(pairs)} | "
                f"{min(success):.4f} / {median(success):.4f} / {max(success):.4f} | "
                f"{min(length):.3f} / {median(length):.3f} / {max(length):.3f} | {verdict} |")
    return lines


def like_for_like_table(rows):
    lines = ["| Approach | initial s, ours (min / median) | initial s, report's code | initial "
             "speed-up | adapt s/step, ours (min / median) | adapt s/step, report's code | "
             "adapt speed-up |", "|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['Approach']} | {float(r['InitialMin']):.4f} / "
                     f"{float(r['InitialMedian']):.4f} | {float(r['InitialReference']):.4f} | "
                     f"**{float(r['InitialSpeedup']):.0f}x** | {float(r['AdaptMin']):.5f} / "
                     f"{float(r['AdaptMedian']):.5f} | {float(r['AdaptReference']):.5f} | "
                     f"**{float(r['AdaptSpeedup']):.0f}x** |")
    return lines


def like_for_like_range(rows, key):
    values = [float(r[key]) for r in rows if r["Approach"] in RL]
    return "–" if not values else f"{min(values):.0f} to {max(values):.0f}"


def choose_figures(studies):
    """(file, caption) of the figures to show: the by-size ones and, for the
    hardest difficulty of the study, the box plots of the largest size up to
    BOX_SIZE_LIMIT and the cumulative adaptation and success over time of
    the largest size."""
    figures = list(BY_SIZE_FIGURES)
    sizes = [int(size) for size in studies.sizes()]
    difficulties = {r["Difficulty"] for study in studies.studies for r in study.results}
    hardest = [d for d in DIFFICULTIES if d in difficulties][-1:]
    if sizes and hardest:
        difficulty = hardest[0]
        boxed = max([size for size in sizes if size <= BOX_SIZE_LIMIT] or sizes)
        largest = max(sizes)
        word = difficulty.lower()
        figures += [
            (f"adapt_box_{boxed}_{difficulty}.png",
             f"Adaptation time per step, {word} {boxed}x{boxed} (box plots over the steps)"),
            (f"cumulative_adapt_{largest}_{difficulty}.png",
             f"Cumulative adaptation time over the time steps, {word} {largest}x{largest}"),
            (f"success_over_time_{largest}_{difficulty}.png",
             f"Success rate over the time steps, {word} {largest}x{largest}"),
        ]
    if any(study.edge_results for study in studies.studies):
        figures.append(("edge_summary_50_Hard.png", "Edge case (hard 50x50, seed 102)"))
    return figures


def copy_figures(source, figures, images, output, copies):
    """Markdown for those of `figures` found in `source` (the folder of
    `dynapath plot`'s figures); appends (source, target) to `copies`, made
    into `images` once the report is written."""
    lines = []
    for name, caption in figures:
        path = os.path.join(source, name)
        if not os.path.exists(path):
            print(f"note: {path} missing (run dynapath plot --overlay-reference); not shown",
                  file=sys.stderr)
            continue
        target = os.path.join(images, name)
        copies.append((path, target))
        lines.append(f"**{caption}**\n\n![{caption}]({link(target, output)})\n")
    return lines


def link(target, output):
    """`target`'s path relative to the folder of `output`, for markdown."""
    return os.path.relpath(target, os.path.dirname(os.path.abspath(output))).replace(os.sep, "/")


def is_maze_row(row):
    """A generated maze of the report (size "50", difficulty "Hard"), not a map."""
    return row["Size"].isdigit() and row["Difficulty"] in DIFFICULTIES


def maps_section(rows, results_dir, output, images, copies):
    """Markdown for the MovingAI maps of a study (`experiment --maps`): per map its
    approaches' figures, and its success-over-time figure (copied into `images`)."""
    if not rows:
        return ""
    text = ("\n## Maps\n\nThe study's MovingAI maps (`dynapath experiment --maps`): no published "
            "figures exist for them, so ours alone, per map in study order. Success rate and path "
            "length averaged over the time steps; times in seconds (initial) and milliseconds per "
            "step (adaptation).\n")
    maps = []
    for row in rows:
        key = (row["Size"], row["Difficulty"])
        if key not in maps:
            maps.append(key)
    for size, label in maps:
        text += f"\n### {label} ({size})\n\n"
        text += "| Approach | Avg success | Avg path | Initial s | Adapt ms/step |\n"
        text += "|---|---|---|---|---|\n"
        for row in rows:
            if (row["Size"], row["Difficulty"]) != (size, label):
                continue
            text += (f"| {row['Approach']} | {float(row['AvgSuccessRate']):.4f} | "
                     f"{float(row['AvgPathLength']):.3f} | {float(row['InitialTime']):.3f} | "
                     f"{1000 * float(row['AdaptTimePerStep']):.3f} |\n")
        figure = f"success_over_time_{size}_{label}.png"
        source = os.path.join(results_dir, "figures", figure)
        if os.path.exists(source):
            target = os.path.join(images, "maps", figure)
            copies.append((source, target))
            text += f"\n![success over time on {label}]({link(target, output)})\n"
    return text


DYNAPATH = os.path.join(HERE, "..", "build", "tools", "dynapath")
PAIR = ("fedAsynQ_EqAvg", "fedAsynQ_ImAvg")


def compare(dynapath, study, a, b, edge=False):
    """`dynapath compare STUDY A B [--edge]`: {(size, difficulty, metric): row}, or
    None when it cannot run (no binary, no repeats)."""
    command = [dynapath, "compare", study.dir, a, b, "--csv"] + (["--edge"] if edge else [])
    try:
        done = subprocess.run(command, capture_output=True, text=True, check=True)
    except (OSError, subprocess.CalledProcessError) as error:
        print(f"note: {' '.join(command)} failed: {error}", file=sys.stderr)
        return None
    rows = list(csv.DictReader(done.stdout.splitlines()))
    return {(r["Size"], r["Difficulty"], r["Metric"]): r for r in rows}


# (metric, heading, scale, digits, unit) of the paired-difference table.
DIFFERENCE_COLUMNS = (("AvgSuccessRate", "success", 1, 4, ""),
                      ("AvgPathLength", "path", 1, 3, ""),
                      ("AdaptTimePerStep", "adapt ms/step", 1000, 3, ""),
                      ("InitialTime", "initial s", 1, 3, ""))


def signed(value, digits):
    """`+0.012`, never `-0.000`."""
    value = round(value, digits) + 0.0
    return f"{value:+.{digits}f}"


def difference_cell(row, scale, digits):
    if row is None:
        return "–"
    m, lo, hi = (scale * float(row[k]) for k in ("MeanDifference", "MeanCILow", "MeanCIHigh"))
    mark = "" if lo <= 0 <= hi else " *"
    return f"{signed(m, digits)} [{signed(lo, digits)}, {signed(hi, digits)}]{mark}"


def difference_table(blocks):
    """blocks: (label, semantics, rows of `compare`, keys (size, difficulty))."""
    lines = ["| Configuration | semantics | pairs | " +
             " | ".join(f"{h}, EqAvg − ImAvg [95% CI]" for _, h, _, _, _ in DIFFERENCE_COLUMNS)
             + " |", "|---|---|---|" + "---|" * len(DIFFERENCE_COLUMNS)]
    for label, semantics, rows, key in blocks:
        if rows is None:
            continue
        first = rows.get(key + ("AvgSuccessRate",))
        if first is None:
            continue
        cells = [difference_cell(rows.get(key + (metric,)), scale, digits)
                 for metric, _, scale, digits, _ in DIFFERENCE_COLUMNS]
        lines.append(f"| {label} | {semantics} | {first['Pairs']} | " + " | ".join(cells) + " |")
    return lines


def claim_sentence(row, metric, smaller_is_claimed):
    """What the interval of EqAvg - ImAvg says about the report's claim."""
    if row is None:
        return "not measured"
    m, lo, hi = (float(row[k]) for k in ("MeanDifference", "MeanCILow", "MeanCIHigh"))
    scale, digits, unit = {"AvgSuccessRate": (1, 4, ""), "AvgPathLength": (1, 3, " steps"),
                           "AdaptTimePerStep": (1000, 3, " ms/step"),
                           "InitialTime": (1, 3, " s")}[metric]
    text = (f"{signed(scale * m, digits)}{unit} [{signed(scale * lo, digits)}, "
            f"{signed(scale * hi, digits)}]")
    if smaller_is_claimed is None:  # "similar": the interval should hold 0 or be tiny
        return text + (" (the interval holds 0)" if lo <= 0 <= hi else
                       f" (the interval excludes 0: EqAvg {'higher' if lo > 0 else 'lower'})")
    if hi < 0:
        return text + (" (below 0: as claimed)" if smaller_is_claimed else " (below 0)")
    if lo > 0:
        return text + (" (above 0: **against** the claim)" if smaller_is_claimed else " (above 0)")
    return text + " (the interval holds 0: no difference resolved)"


def findings(studies, main_study, report, count, closeness, verdicts, claim, has_edge):
    """The numbers the findings quote, as {placeholder: text}."""
    values = {}
    for key, learns in (("INSIDE_RL", True), ("INSIDE_BASE", False)):
        n, s, p, both = count.counts(learns)
        values[key] = (f"{both} of {n} (success rate {s} of {n}, path length {p} of {n})")
    outside = [f"{approach} {label} ({', '.join(x for x, ok in (('success', s), ('path', p)) if not ok)})"
               for label, approach, _, s, p in count.outside(True)]
    values["OUTSIDE_RL"] = "; ".join(outside) if outside else "none"
    otln = [studies.stat("onlyTrainLeafNodes", size, "Hard", "AvgSuccessRate") for size in ("50", "100")]
    values["OTLN_HARD"] = " / ".join("–" if s is None else f"{s.mean:.2f}" for s in otln)
    values["OTLN50_DEFAULT"] = mean_pair(main_study, "onlyTrainLeafNodes")
    values["OTLN50_REPORT"] = mean_pair(report, "onlyTrainLeafNodes")
    if has_edge:
        success = [main_study.stat(a, "50", "Hard", "AvgSuccessRate", True) for a in RL[1:]]
        path = [main_study.stat(a, "50", "Hard", "AvgPathLength", True) for a in RL[1:]]
        values["EDGE_DEFAULT_SUCCESS"] = range_text([s.mean for s in success if s], 3)
        values["EDGE_DEFAULT_PATH"] = range_text([p.mean for p in path if p], 1)
        values["EDGE_REPORT"] = ", ".join(
            f"`{a}` {mean_pair(report, a, edge=True, ci=False)}"
            for a in ("fedAsynQ_EqAvg", "fedAsynQ_ImAvg", "singleAgent"))
    # singleAgent against the report code's ten runs.
    names = {"52": "hard 50x50", "102": "the edge case"}
    for semantics, key in (("report", "SA_TEN_REPORT"), ("default", "SA_TEN_DEFAULT")):
        parts = []
        inside_all = True
        for seed in ("52", "102"):
            got = [v for v in verdicts if v[0] == seed and v[1] == semantics]
            if len(got) < 2:
                continue
            text = []
            for _, _, metric, mean, _, _, inside, t0, t1 in got:
                digits = 4 if metric == "AvgSuccessRate" else 3
                inside_all &= inside
                text.append(f"{'success' if metric == 'AvgSuccessRate' else 'path'} "
                            f"{mean:.{digits}f} {'in' if inside else '**outside**'} "
                            f"{t0:.{digits}f}–{t1:.{digits}f}")
            parts.append(f"{names[seed]}: " + ", ".join(text))
        if not parts:
            values[key] = "not measured"
            continue
        verdict = ("lies inside the report code's ten-run range for success and path on both "
                   "mazes" if inside_all else
                   "does **not** lie inside the report code's ten-run range everywhere")
        values[key] = f"{verdict} ({'; '.join(parts)})"
    others = [c for c in closeness if c[1] != "singleAgent"]
    if others:
        further = [f"`{a}` {'edge case' if seed == '102' else 'hard 50x50'} "
                   f"{'success' if m == 'AvgSuccessRate' else 'path'}"
                   for seed, a, m, ok in others if not ok]
        values["CLOSENESS"] = (
            f"{sum(ok for *_, ok in others)} of {len(others)} means (approach, maze and metric) "
            "are at least as close to the report code's median as our single run (repeat 1) "
            "was" + (f"; further away: {', '.join(further)}" if further else ""))
    halves = {"AvgSuccessRate": [], "AvgPathLength": []}
    for size in studies.sizes():
        for difficulty in DIFFICULTIES:
            for approach in RL:
                for metric, widths in halves.items():
                    s = studies.stat(approach, size, difficulty, metric)
                    if s is not None and s.has_interval:
                        widths.append((s.high - s.low) / 2)
    if halves["AvgSuccessRate"]:
        values["CI_WIDTH"] = (f"{median(halves['AvgSuccessRate']):.4f} in success rate, "
                              f"{median(halves['AvgPathLength']):.3f} in path length")
    values["EQIM_SIZES"] = ", ".join(main_study.sizes())
    # fedAsynQ_EqAvg - fedAsynQ_ImAvg against the report's claim.
    for scope, key in (("all", "EQIM_ALL"), ("edge", "EQIM_EDGE")):
        rows = claim.get(scope)
        if rows is None:
            continue
        k = ("all", "all") if scope == "all" else ("50", "Hard")
        pairs = rows.get(k + ("AvgPathLength",), {}).get("Pairs", "?")
        values[key] = (
            f"path {claim_sentence(rows.get(k + ('AvgPathLength',)), 'AvgPathLength', True)}, "
            f"adaptation {claim_sentence(rows.get(k + ('AdaptTimePerStep',)), 'AdaptTimePerStep', True)}, "
            f"success {claim_sentence(rows.get(k + ('AvgSuccessRate',)), 'AvgSuccessRate', None)}, "
            f"initial training {claim_sentence(rows.get(k + ('InitialTime',)), 'InitialTime', True)} "
            f"({pairs} pairs)")
    return values


DEFAULT_SIZES = [20, 50, 100, 200, 300]


def experiment_command(study, note):
    """The `dynapath experiment` command line of a study, from its manifest."""
    options = study.manifest.get("options", {})
    s, e = options.get("study", {}), options.get("execution", {})
    mode = e.get("mode", "local")
    words = ["build/tools/dynapath experiment", "--local" if mode == "local" else
             f"--agents {e.get('agents')}" if mode == "agents" else f"--{mode}"]
    if s.get("sizes") and s["sizes"] != DEFAULT_SIZES:
        words.append("--sizes " + ",".join(str(x) for x in s["sizes"]))
    if s.get("difficulties") and s["difficulties"] != ["easy", "medium", "hard"]:
        words.append("--difficulties " + ",".join(s["difficulties"]))
    if s.get("edge_case") is False:
        words.append("--no-edge-case")
    if s.get("semantics") == "report":
        words.append("--semantics report")
    if s.get("maps"):
        words.append("--maps " + ",".join(s["maps"]))
    for key in ("seed", "steps", "learner_seed"):
        if s.get(key) is not None:
            words.append(f"--{key.replace('_', '-')} {s[key]}")
    if s.get("maze_seeds"):
        words.append("--maze-seeds " + ",".join(str(x) for x in s["maze_seeds"]))
    if (s.get("repeats") or 1) > 1:
        words.append(f"--repeats {s['repeats']}")
    if e.get("parallel") and e["parallel"] > 1:
        words.append(f"--parallel {e['parallel']}")
    lines = [" ".join(words)]
    if s.get("approaches") and s["approaches"] != ORDER:
        lines.append('  --approaches "' + ",".join(s["approaches"]) + '"')
    lines[-1] += f" --out {study.name}"
    lines[-1] = f"{lines[-1]:<60} # {note}" if len(lines[-1]) < 60 else lines[-1] + f"  # {note}"
    return " \\\n".join(lines)


def elapsed(study):
    """Wall-clock time of the study's sessions, e.g. `3 min 5 s`."""
    from datetime import datetime
    m = study.manifest
    try:
        if m.get("sessions", 1) == 1:
            seconds = (datetime.fromisoformat(m["ended"]) -
                       datetime.fromisoformat(m["started"])).total_seconds()
        else:
            raise KeyError
    except (KeyError, TypeError, ValueError):
        seconds = sum(c.get("wall_seconds") or 0 for c in m.get("configurations", []))
    return f"{int(seconds // 60)} min {seconds % 60:.0f} s" if seconds >= 60 else f"{seconds:.0f} s"


def study_facts(study):
    """Commit, mode, machine and wall time of a study, from its manifest.json."""
    m = study.manifest
    if not m:
        return f"`{study.name}`: no manifest"
    execution = m.get("options", {}).get("execution", {})
    mode = execution.get("mode", "local")
    if mode == "local":
        mode_text = f"`--local`, {execution.get('threads')} threads"
        if (execution.get("parallel") or 1) > 1:
            mode_text += f", {execution['parallel']} runs at once"
    else:
        mode_text = f"`--{mode}` with {execution.get('agents')} agents"
    machine = m.get("machine", {})
    configurations = m.get("configurations", [])
    return (f"`{study.name}`: commit `{m.get('git_commit', 'unknown')}`, {mode_text}, "
            f"{machine.get('cpu_model', '?')} ({machine.get('cores', '?')} cores), "
            f"{len(configurations)} runs in {elapsed(study)}")


def few_repeats_note(studies):
    """A sentence on the sizes run with fewer than 5 repeats, if any."""
    few = [size for size in studies.sizes() if 1 < studies.by_size[size].repeat_count() < 5]
    single = [size for size in studies.sizes() if studies.by_size[size].repeat_count() == 1]
    text = ""
    if few:
        counts = sorted({studies.by_size[size].repeat_count() for size in few})
        text += (f" Size{'s' if len(few) > 1 else ''} {', '.join(few)} ran "
                 f"{' or '.join(map(str, counts))} repeats only (time): "
                 "a bootstrap interval of so few values lies within their range and understates "
                 "the uncertainty.")
    if single:
        text += (f" Size{'s' if len(single) > 1 else ''} {', '.join(single)} "
                 f"{'are **single runs**' if len(single) > 1 else 'is a **single run**'} (no repeats, no interval: "
                 "`Runs` 1).")
    return text


def range_text(values, digits):
    lo, hi = min(values), max(values)
    return f"{lo:.{digits}f}" if f"{lo:.{digits}f}" == f"{hi:.{digits}f}" else \
        f"{lo:.{digits}f} to {hi:.{digits}f}"


def mean_pair(study, approach, edge=False, size="50", difficulty="Hard", ci=True):
    if study is None:
        return "–"
    s = study.stat(approach, size, difficulty, "AvgSuccessRate", edge)
    p = study.stat(approach, size, difficulty, "AvgPathLength", edge)
    if s is None or p is None:
        return "–"
    if ci:
        return f"{fmt_ci(s, 4)} / {fmt_ci(p, 3)}"
    return f"{s.mean:.4f} / {p.mean:.3f}"


USAGE = ("usage: scripts/make_reproduction_report.py STUDY_DIR OUTPUT.md [--images DIR] "
         "[--intro FILE] [--more-sizes DIR] [--report-semantics DIR] [--like-for-like CSV] "
         "[--spread DIR] [--dynapath PATH] [--figures DIR] (see --help)")
VALUE_OPTIONS = ("--report-semantics", "--like-for-like", "--spread", "--more-sizes",
                 "--dynapath", "--figures", "--images", "--intro")


def parse_arguments(argv):
    """(study, output, options); exits 2 on bad usage."""
    def usage(message):
        print(f"make_reproduction_report.py: {message}\n{USAGE}", file=sys.stderr)
        sys.exit(2)

    args, options = [], {"--more-sizes": []}
    argv = list(argv)
    while argv:
        arg = argv.pop(0)
        if arg in ("-h", "--help"):
            print(__doc__)
            sys.exit(0)
        if arg in VALUE_OPTIONS:
            if not argv:
                usage(f"{arg} needs a value")
            if arg == "--more-sizes":
                options[arg].append(argv.pop(0))
            else:
                options[arg] = argv.pop(0)
        elif arg.startswith("--"):
            usage(f"unknown option {arg}")
        else:
            args.append(arg)
    if len(args) != 2:
        usage("give the study and the output file (it writes only where it is told: "
              "there is no default output)" if len(args) < 2 else "too many arguments")
    if not os.path.isdir(args[0]):
        usage(f"{args[0]}: no such study directory")
    if os.path.isdir(args[1]):
        usage(f"{args[1]}: a directory; give the markdown file to write")
    for key in ("--intro", "--like-for-like"):
        if key in options and not os.path.isfile(options[key]):
            usage(f"{key} {options[key]}: no such file")
    for key in ("--report-semantics", "--spread", "--figures"):
        if key in options and not os.path.isdir(options[key]):
            usage(f"{key} {options[key]}: no such directory")
    for directory in options["--more-sizes"]:
        if not os.path.isdir(directory):
            usage(f"--more-sizes {directory}: no such directory")
    return args[0], args[1], options


def report_mazes(study):
    """Whether the study ran the report's mazes and change sequences (its
    default seeds and steps), the only ones its published values are for."""
    s = study.manifest.get("options", {}).get("study")
    if not s:
        return False
    return s.get("seed") is None and s.get("steps") is None and not s.get("maze_seeds")


def run_conditions(study):
    """How the study's runs shared the machine, from its manifest."""
    e = study.manifest.get("options", {}).get("execution", {})
    machine = study.manifest.get("machine", {})
    parallel = e.get("parallel") or 1
    at_once = "one at a time" if parallel == 1 else f"{parallel} at a time"
    where = machine.get("cpu_model")
    cores = machine.get("cores")
    text = f"ours ran {at_once}"
    if where:
        text += f" on {where}" + (f" ({cores} cores)" if cores else "")
    return text


def ours_table(lookup, sizes, difficulties):
    """Every approach of every configuration, ours alone (a study whose
    mazes the report did not publish)."""
    lines = ["| Size | Difficulty | Approach | Runs | Success, mean [95% CI] "
             "| Path, mean [95% CI] | Initial s (mean) | Adapt s/step (mean) |",
             "|---|---|---|---|---|---|---|---|"]
    for size, difficulty, approach, success, length, initial, adapt in configuration_stats(
            lookup, sizes, difficulties):
        lines.append(f"| {size} | {difficulty} | {approach} | {success.n} "
                     f"| {fmt_ci(success, 4)} | {fmt_ci(length, 3)} "
                     f"| {initial.mean:.3f} | {adapt.mean:.5f} |")
    return lines


def configuration_stats(lookup, sizes, difficulties):
    """(size, difficulty, approach, success, length, initial, adapt) of
    every approach of every configuration that `lookup` has, in order."""
    for size in sizes:
        for difficulty in difficulties:
            for approach in ORDER:
                success = lookup(approach, size, difficulty, "AvgSuccessRate")
                if success is None:
                    continue
                yield (size, difficulty, approach, success,
                       *(lookup(approach, size, difficulty, metric)
                         for metric in ("AvgPathLength", "InitialTime", "AdaptTimePerStep")))


def study_note(study):
    """What a study holds, for the comment after its command."""
    sizes = study.sizes()
    parts = [f"size{'s' if len(sizes) > 1 else ''} {', '.join(sizes)}"] if sizes else []
    if study.edge_results:
        parts.append("the edge case")
    maps = study.manifest.get("options", {}).get("study", {}).get("maps")
    if maps:
        parts.append(f"{len(maps)} map{'s' if len(maps) > 1 else ''}")
    text = " and ".join(parts) or "no configuration"
    if study.repeat_count() > 1:
        text += f", {study.repeat_count()} repeats"
    return text


def generic_header(main_study, studies, more, report, values, reference_rows, count, failures,
                   edge_failures):
    """The header of a report without --intro: the study's own facts, and
    what comparing it with the report's published rows found."""
    names = ", ".join(f"`{s.name}`" for s in [main_study] + more + ([report] if report else []))
    text = (f"# Results of {names}\n\nMade by `scripts/make_reproduction_report.py` from "
            f"{'the study' if not more and not report else 'the studies'} run with\n\n"
            f"```sh\n{values['COMMANDS']}\n```\n\n({values['FACTS']}). "
            f"Sizes (repeats): {values['SIZES']}.")
    if any(s.repeat_count() > 1 for s in studies.studies):
        text += (" Repeat k of a configuration runs the same maze and changes with learner "
                 "seed = maze seed + (k − 1) x 1000003; each row of ours is the mean over the "
                 "repeats with its 95% stratified-bootstrap interval (`summary.csv`).")
    text += "\n"
    if not reference_rows:
        if report_mazes(main_study):
            text += ("\nThe report published no row for the study's configurations, so its "
                     "rows are not set beside the report's.\n")
        else:
            text += ("\nThe study's mazes are not the report's (other seeds, steps or maze "
                     "seeds, or no `manifest.json` to tell), so its rows are not set beside the "
                     "report's published values.\n")
        return text
    text += ("\nThe study ran the report's mazes and change sequences (default seeds and "
             "steps), so its rows are set beside the report's published values "
             "(`docs/reference/`, measured on an 8-thread i7-1165G7: compare time *ratios*, "
             "not absolute times).\n")
    checked = [size for size in studies.sizes() if size in ("20", "50")]
    if checked and RL:
        text += (f"\n**Acceptance check** (size{'s' if len(checked) > 1 else ''} "
                 f"{', '.join(checked)}): each learning "
                 "approach's mean success rate is at least the report's minus "
                 f"{SUCCESS_TOLERANCE} and its mean path length at most the report's plus "
                 f"{LENGTH_TOLERANCE}. Failing rows: **{failures}**"
                 + (f" (edge case, not part of the check: {edge_failures})"
                    if main_study.edge_results else "") + ".\n")
    rl = count.counts(True)
    base = count.counts(False)
    if rl[0] or base[0]:
        parts = []
        if rl[0]:
            parts.append(f"for the learning approaches in {values['INSIDE_RL']} rows")
        if base[0]:
            parts.append(f"for the approaches that do not learn (a point interval) in "
                         f"{values['INSIDE_BASE']}")
        text += ("\n**Published values inside our intervals**: the report's published success "
                 "rate and path length both lie inside our 95% intervals " + "; ".join(parts)
                 + ".\n")
    return text


def main():
    results_dir, output, options = parse_arguments(sys.argv[1:])
    try:
        text, copies, summary = build_report(results_dir, output, options)
    except InputError as error:
        print(f"make_reproduction_report.py: {error} (nothing written)", file=sys.stderr)
        return 1
    except (OSError, ValueError, KeyError, csv.Error) as error:
        print(f"make_reproduction_report.py: cannot read the study: {error} (nothing written)",
              file=sys.stderr)
        return 1
    with open(output, "w") as f:
        f.write(text)
    for source, target in copies:
        os.makedirs(os.path.dirname(target), exist_ok=True)
        shutil.copyfile(source, target)
    print(f"wrote {output}" + (f" and {len(copies)} figure{'s' if len(copies) > 1 else ''}"
                               if copies else "") + f" ({summary})")
    return 0


def build_report(results_dir, output, options):
    """(markdown, figures to copy, a one-line summary)."""
    if not os.path.exists(os.path.join(results_dir, "results.csv")):
        raise InputError(f"{results_dir}: no results.csv (expected a dynapath experiment study)")
    images = options.get("--images", os.path.join(os.path.dirname(os.path.abspath(output)),
                                                  "images"))
    copies = []
    rows = read(os.path.join(results_dir, "results.csv"))
    map_rows = [r for r in rows if not is_maze_row(r)]
    main_study = Study(results_dir)
    more = [Study(d) for d in options["--more-sizes"]]
    report = Study(options["--report-semantics"]) if "--report-semantics" in options else None
    use_approaches([main_study] + more + ([report] if report else []))
    if not main_study.results:  # a study of maps only: nothing to set beside the report
        text = ("# Study of MovingAI maps\n\nMade by `scripts/make_reproduction_report.py` from the "
                f"study in `{results_dir}` (`dynapath experiment --maps`).\n")
        text += maps_section(map_rows, results_dir, output, images, copies)
        return text, copies, f"{len(map_rows)} rows of maps"
    studies = Studies([main_study] + more)
    dynapath = options.get("--dynapath", DYNAPATH)
    # Set beside the report's published rows only when the study ran its
    # mazes and the report published some of the study's configurations.
    ref = edge_ref = []
    if report_mazes(main_study):
        ref = read(os.path.join(REFERENCE, "paper_results.csv"))
        edge_ref = read(os.path.join(REFERENCE, "paper_edge_results.csv"))
        ours = {(r["Approach"], r["Size"], r["Difficulty"])
                for study in studies.studies for r in study.results}
        if not ours & set(index(ref)):
            ref = edge_ref = []
    published = bool(ref)
    here = read(os.path.join(REFERENCE, "reference_code_run_here.csv"))
    sizes = studies.sizes()
    means = studies.mean_rows()
    count = InsideCount()
    has_edge = bool(main_study.edge_results)
    failures = edge_failures = 0
    edge_lines = []
    if published:
        main_lines, failures = table(studies.stat, ref, sizes, DIFFICULTIES, count)
        if has_edge:
            edge_lines, edge_failures = table(
                lambda a, s, d, m: main_study.stat(a, s, d, m, True), edge_ref, ["50"], ["Hard"],
                count, edge=True)
    else:
        main_lines = ours_table(studies.stat, sizes, DIFFICULTIES)
        if has_edge:
            edge_lines = ours_table(lambda a, s, d, m: main_study.stat(a, s, d, m, True), ["50"],
                                    ["Hard"])
    like = read(options["--like-for-like"]) if "--like-for-like" in options else []
    # Sections after the findings, and the facts the findings quote.
    values = {}
    body = ""
    if like:
        body += ("\n## Speed, like for like\n\nThe report's code built `-O3` and run on this machine "
                 "(`docs/reference/reference_code_run_here.csv`, median of 3 runs) against ours "
                 "(`bench/like_for_like.sh`, " + like[0]["Runs"] + " runs on an otherwise idle "
                 "machine; `docs/PERFORMANCE.md`), hard 50x50, seed 52. Speed-up = its median / "
                 "our median.\n\n")
        body += "\n".join(like_for_like_table(like)) + "\n"
    closeness, verdicts = [], []
    if report is not None:
        body += ("\n## Against the report's code run here\n\nSuccess rate and average path "
                 "length, our means over the repeats with their 95% bootstrap intervals. The "
                 "report's code is not deterministic; its spread over 3 runs is about +-0.003 / "
                 "+-0.05 on hard 50x50 and 0.966-0.977 / 9.29-10.58 on the edge case "
                 "(`docs/reference/README.md`). `--semantics report` is the report code's "
                 "bootstrap, first-training rule, single-agent learner (SPEC 11) and double "
                 "tables (`docs/concepts/DECISIONS.md`). The distance column gives "
                 "|our mean − its median| and, in brackets, the same for our repeat 1 alone "
                 "(the single run this report used to show).\n\n")
        body += "### Hard 50x50, seed 52\n\n"
        body += "\n".join(code_here_table(main_study, report, here, ref, "52", False,
                                          closeness)) + "\n"
        if has_edge:
            body += "\n### Edge case (hard 50x50, seed 102)\n\n"
            body += "\n".join(code_here_table(main_study, report, here, edge_ref, "102", True,
                                              closeness)) + "\n"
        body += ("\n### Single agent against the report code's ten runs\n\n"
                 "`singleAgent` over our repeats (repeat k: learner seed = maze seed + (k − 1) x "
                 "1000003, the same maze and changes), under our semantics and under "
                 "`--semantics report` (SPEC 11: the report code's single-agent learner), "
                 "against ten runs of the report's code on this machine "
                 "(`docs/reference/reference_code_singleAgent_runs.csv`). The acceptance test "
                 "is that the mean of our ten repeats under `--semantics report` lies inside "
                 "the report code's ten-run range, for success and path.\n")
        for seed, name, edge in (("52", "Hard 50x50, seed 52", False),
                                 ("102", "Edge case (hard 50x50, seed 102)", True)):
            if edge and not has_edge:
                continue
            lines = single_agent_runs_table(main_study, report, seed, edge, verdicts)
            if lines:
                body += f"\n{name}:\n\n" + "\n".join(lines) + "\n"
        if "--spread" in options:
            body += ("\n### Our spread over learner seed streams (`semantics_spread`)\n\n"
                     "`bench/semantics_spread` runs one approach on one maze with N learner "
                     "seed streams (stream k uses run seed = maze seed + k * 1000003, which is "
                     "repeat k + 1 of `--repeats`: every learner's random numbers change, the "
                     "maze and changes do not). `--semantics report` keeps the tables in "
                     "`double`, as the report's code does; `report-float` (a `semantics_spread` "
                     "variant, not a run option) applies the same rules to our `float` tables, "
                     "to show what the precision alone does. The reference CSV has only the "
                     "median of the report code's 3 runs per approach, so *inside* tests that "
                     "median against our min-max range.\n")
            for seed, name in (("52", "Hard 50x50, seed 52"),
                               ("102", "Edge case (hard 50x50, seed 102)")):
                body += f"\n{name}:\n\n"
                body += "\n".join(spread_table(options["--spread"], here, seed)) + "\n"

    # fedAsynQ_EqAvg against fedAsynQ_ImAvg: paired differences over the repeats.
    blocks = []
    claim = {}
    pair_present = all(name in ORDER for name in PAIR)
    if main_study.has_repeats and pair_present:
        rows_main = compare(dynapath, main_study, *PAIR)
        for size in main_study.sizes():
            for difficulty in DIFFICULTIES:
                blocks.append((f"{size} {difficulty.lower()}", "ours", rows_main, (size, difficulty)))
        blocks.append(("**all of the above** (stratified)", "ours", rows_main, ("all", "all")))
        claim["all"] = rows_main
        for study in more:
            if study.has_repeats:
                rows_more = compare(dynapath, study, *PAIR)
                for size in study.sizes():
                    if studies.by_size.get(size) is study:
                        for difficulty in DIFFICULTIES:
                            blocks.append((f"{size} {difficulty.lower()}", "ours", rows_more,
                                           (size, difficulty)))
        if has_edge:
            rows_edge = compare(dynapath, main_study, *PAIR, edge=True)
            blocks.append(("edge case", "ours", rows_edge, ("50", "Hard")))
            claim["edge"] = rows_edge
    if report is not None and report.has_repeats and pair_present:
        blocks.append(("50 hard", "`report`", compare(dynapath, report, *PAIR), ("50", "Hard")))
        if report.edge_summary:
            blocks.append(("edge case", "`report`", compare(dynapath, report, *PAIR, edge=True),
                           ("50", "Hard")))
    blocks = [block for block in blocks if block[2] is not None]
    if blocks:
        body += ("\n## fedAsynQ_EqAvg against fedAsynQ_ImAvg\n\n"
                 "The report concludes that `fedAsynQ_EqAvg` did slightly better than "
                 "`fedAsynQ_ImAvg`: less cumulative adaptation time and marginally shorter "
                 "paths at a similar accuracy (its Conclusion; its discussion also gives EqAvg "
                 "the shorter initial training). Below, the paired differences EqAvg − ImAvg "
                 "over the repeats (`dynapath compare STUDY fedAsynQ_EqAvg fedAsynQ_ImAvg`, "
                 "`--edge` for the edge case): repeat k of one against repeat k of the other, "
                 "same maze, changes and learner seed; the mean difference and its 95% "
                 "bootstrap interval (over all configurations stratified by configuration). "
                 "Negative: EqAvg lower. `*`: the interval excludes 0. For the times: "
                 f"{run_conditions(main_study)}.\n\n")
        body += "\n".join(difference_table(blocks)) + "\n"

    if published:
        body += ("\n## All configurations (against the report's published rows)\n\n"
                 "Our mean over the repeats (`Runs`) with its 95% stratified-bootstrap interval "
                 "(`summary.csv`), the report's published value (– where it published none), and "
                 "whether that value lies inside our interval. The interval covers our learner "
                 "streams on the report's maze; the approaches that do not learn are "
                 "deterministic, so theirs is a point, and any difference in the published "
                 "figure's 4th or 5th digit puts it outside. Times are means; "
                 f"{run_conditions(main_study)}, the report's on an 8-thread laptop."
                 + few_repeats_note(studies) + "\n\n" + "\n".join(main_lines) + "\n")
    else:
        body += ("\n## All configurations\n\nOur mean over the repeats (`Runs`), with its 95% "
                 "stratified-bootstrap interval when there are repeats. Times are means; "
                 f"{run_conditions(main_study)}." + few_repeats_note(studies) + "\n\n"
                 + "\n".join(main_lines) + "\n")
    if edge_lines:
        body += "\n## Edge case (hard 50x50, seed 102)\n\n" + "\n".join(edge_lines) + "\n"
    bfs_lines = rl_vs_bfs(means, sizes)
    if len(bfs_lines) > 2:
        body += "\n## RL adaptation time against the BFS Oracle\n\n"
        body += ("The report compares its RL approaches with A* Oracle only. A single "
                 "multi-source BFS gives the same optimal answer; this is the comparison the "
                 "report does not make. Means over the repeats.\n\n")
        body += "\n".join(bfs_lines) + "\n"
    oracle_lines = oracle_table(means, ref, sizes)
    if len(oracle_lines) > 2:
        body += "\n## Oracle over the change sequence\n\n" + "\n".join(oracle_lines) + "\n"
    figures_dir = options.get("--figures", os.path.join(results_dir, "figures"))
    figures = copy_figures(figures_dir, choose_figures(studies),
                           os.path.join(images, "reproduction"), output, copies)
    if figures:
        body += ("\n## Figures\n\nDrawn by `dynapath plot` from the study; solid lines and filled "
                 "markers are ours (with repeats: means over the repeats with their 95% intervals "
                 "as error bars)" + (", dashed lines and hollow markers the report's published "
                                     "values" if published else "") + ". "
                 "All figures of the study (per configuration too) are in the study's "
                 "`figures/`." + (" The by-size figures' titles give the fewest repeats of any "
                                  "size; the sizes' own counts are those of the table."
                                  if len({s.repeat_count() for s in studies.studies}) > 1
                                  else "") + "\n\n")
        body += "\n".join(figures)
    body += maps_section(map_rows, results_dir, output, images, copies)

    # The header and findings (scripts/reproduction_intro.md) with the numbers of these runs.
    commands = [experiment_command(main_study, study_note(main_study))]
    for study in more:
        commands.append(experiment_command(study, study_note(study)))
    if report is not None:
        commands.append(experiment_command(report, study_note(report) + ", report semantics"))
    plotted = main_study.name
    if "--figures" in options and more:
        # The figures of a study merged from the main one and those of more sizes.
        plotted = os.path.basename(os.path.dirname(os.path.normpath(figures_dir)))
        others = " ".join(f"tail -n +2 {s.name}/$f;" for s in more)
        commands.append(
            f"mkdir {plotted}; for f in results.csv results_detailed.csv summary.csv; do  "
            f"# {' and '.join(s.name for s in [main_study] + more)} in one, for the figures\n"
            f"  {{ cat {main_study.name}/$f; {others} }} | grep -v ',all,all,' > {plotted}/$f; "
            f"done; cp {main_study.name}/edge_* {plotted}/")
    if figures:
        commands.append(f"build/tools/dynapath plot {plotted}"
                        f"{' --overlay-reference' if published else ''}{'':<20} # {plotted}/figures")
    if blocks:
        names = " ".join(s.name for s in [main_study] + more + ([report] if report else [])
                         if s.has_repeats)
        commands.append(f"for s in {names}; do for e in '' --edge; do  # run by this script\n"
                        f"  build/tools/dynapath compare $s fedAsynQ_EqAvg fedAsynQ_ImAvg --csv $e; "
                        f"done; done")
    if like:
        commands.append(f"bench/like_for_like.sh --runs {like[0]['Runs']} --csv "
                        f"{options['--like-for-like']}  # earlier, on an idle machine")
    if "--spread" in options:
        commands.append(
            "mkdir spread; for seed in 52 102; do for a in onlyTrainLeafNodes singleAgent "
            "fedAsynQ_EqAvg fedAsynQ_ImAvg; do\n"
            "  build/bench/semantics_spread 50 hard $seed $a 15 report > spread/double_${a}_$seed.txt\n"
            "  build/bench/semantics_spread 50 hard $seed $a 15 report-float > "
            "spread/float_${a}_$seed.txt\n"
            "done; done                                                   # our spread over 15 "
            "learner seed streams")
    script = [f"scripts/make_reproduction_report.py {main_study.name} {output}"]
    if "--images" in options:
        script.append(f"--images {options['--images']}")
    if "--intro" in options:
        script.append(f"--intro {options['--intro']}")
    script += [f"--more-sizes {s.name}" for s in more]
    if report is not None:
        script.append(f"--report-semantics {report.name}")
    if like:
        script.append(f"--like-for-like {options['--like-for-like']}")
    if "--spread" in options:
        script.append("--spread spread")
    if "--figures" in options:
        script.append(f"--figures {plotted}/figures")
    commands.append(" \\\n  ".join([" ".join(script[:3])] + [" ".join(script[3:])]
                                   if len(script) > 3 else [" ".join(script)])
                    + f"  # writes {output}" + "".join(
                        f" and {folder}/" for folder in sorted(
                            {link(os.path.dirname(target), output) for _, target in copies})))
    values["COMMANDS"] = "\n".join(commands)
    facts = [study_facts(s) for s in [main_study] + more + ([report] if report else [])]
    values["FACTS"] = "; ".join(facts)
    values["SIZES"] = ", ".join(
        f"{size} ({studies.by_size[size].repeat_count()} repeat"
        f"{'s' if studies.by_size[size].repeat_count() > 1 else ''})" for size in sizes)
    values["FAILURES"] = str(failures)
    values["EDGE_FAILURES"] = str(edge_failures)
    values["INITIAL_SPEEDUP"] = speedups(means, ref, "InitialTime")
    values["ADAPT_SPEEDUP"] = speedups(means, ref, "AdaptTimePerStep")
    values["LFL_INITIAL"] = like_for_like_range(like, "InitialSpeedup")
    values["LFL_ADAPT"] = like_for_like_range(like, "AdaptSpeedup")
    values.update(findings(studies, main_study, report, count, closeness, verdicts, claim,
                           has_edge))
    values.update(bfs_facts(means, sizes))
    # A value that could not be computed is no value ("–", "not measured").
    values = {key: value for key, value in values.items()
              if value.strip() not in ("–", "not measured")}
    if "--intro" in options:
        # The findings text (the project's: scripts/reproduction_intro.md)
        # with the numbers of these runs; every placeholder must be filled.
        with open(options["--intro"]) as f:
            text = f.read()
        for key, value in values.items():
            text = text.replace("{{" + key + "}}", value)
        missing = sorted(set(re.findall(r"\{\{([A-Z_0-9]+)\}\}", text)))
        if missing:
            raise InputError(f"--intro {options['--intro']}: no value for {', '.join(missing)} "
                             "from these inputs (the studies or options they need are missing)")
    else:
        text = generic_header(main_study, studies, more, report, values, ref, count, failures,
                              edge_failures)
    rl = count.counts(True)
    summary = (f"{failures} failing rows of the 20/50 acceptance check; published value inside "
               f"our interval for {rl[3]} of {rl[0]} learning rows, success and path"
               if published and rl[0] else "not set beside the report's published values"
               if not published else "no learning rows beside published values")
    return text + body, copies, summary


if __name__ == "__main__":
    sys.exit(main())
