#!/usr/bin/env python3
"""End-to-end checks of `dynapath plot` (tools/plot/dynapath_plot.py), run
through the dynapath launcher. Standard library only.

Usage: plot_test.py DYNAPATH FIXTURE_STUDY MODE [REFERENCE_DIR]
  MODE figures:   every expected figure is written, listed and a valid PNG;
                  rectangular size labels; bad input exits 1 or 2 with one
                  line on stderr and no traceback.
  MODE reference: the same figures with the report's values overlaid
                  (--overlay-reference and --reference DIR); bad reference
                  directories and files.
"""

import shutil
import struct
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

failures = []


def fail(message):
    failures.append(message)
    print(f"FAIL: {message}")


def plot(dynapath, *args):
    return subprocess.run([dynapath, "plot", *map(str, args)], capture_output=True, text=True,
                          timeout=300)


def png_size(path):
    """(width, height) of a PNG file, or None when it is not one."""
    data = path.read_bytes()
    if len(data) < 33 or data[:8] != b"\x89PNG\r\n\x1a\n" or data[12:16] != b"IHDR":
        return None
    if not data.endswith(b"IEND\xaeB`\x82"):
        return None
    return struct.unpack(">II", data[16:24])


def expected_figures(sizes, difficulties, edge_configurations):
    names = ["success_rate_by_size", "adapt_time_by_size", "path_length_by_size",
             "initial_time_by_size"]
    per_configuration = ["adapt_box", "cumulative_adapt", "success_over_time"]
    for size in sizes:
        for difficulty in difficulties:
            names += [f"{figure}_{size}_{difficulty}" for figure in per_configuration]
    for size, difficulty in edge_configurations:
        names += [f"edge_{figure}_{size}_{difficulty}" for figure in per_configuration]
        names.append(f"edge_summary_{size}_{difficulty}")
    return {f"{name}.png" for name in names}


def check_figures(result, out_dir, expected, what):
    if result.returncode != 0:
        fail(f"{what}: exit {result.returncode}: {result.stderr.strip()}")
        return
    listed = {Path(line).name for line in result.stdout.split()}
    if listed != expected:
        fail(f"{what}: listed {sorted(listed ^ expected)} differently from the expected figures")
    for name in sorted(expected):
        path = out_dir / name
        if not path.is_file():
            fail(f"{what}: {name} was not written")
            continue
        if not name.endswith(".png"):
            continue
        size = png_size(path)
        if size is None:
            fail(f"{what}: {name} is not a complete PNG")
        elif size[0] < 300 or size[1] < 300 or size[0] > 5000 or size[1] > 5000:
            fail(f"{what}: {name} is {size[0]}x{size[1]} pixels")
    extra = {path.name for path in out_dir.iterdir()} - expected if out_dir.is_dir() else set()
    if extra:
        fail(f"{what}: unexpected files {sorted(extra)}")


def expect_errors(dynapath, cases):
    """Runs expect_error on each (status, needle, *args), two at a time."""
    with ThreadPoolExecutor(max_workers=2) as pool:
        list(pool.map(lambda case: expect_error(dynapath, *case), cases))


def expect_error(dynapath, status, needle, *args):
    result = plot(dynapath, *args)
    what = "dynapath plot " + " ".join(map(str, args))
    lines = result.stderr.splitlines()
    if result.returncode != status:
        fail(f"{what}: exit {result.returncode}, expected {status} ({result.stderr.strip()})")
    if len(lines) != 1:
        fail(f"{what}: {len(lines)} lines on stderr, expected 1: {result.stderr!r}")
    if "Traceback" in result.stderr or needle not in result.stderr:
        fail(f"{what}: stderr does not mention '{needle}': {result.stderr!r}")


def study_copy(fixtures, work, name, edit=None, drop=()):
    """A copy of the fixture study with `edit(file name, text) -> text` applied."""
    directory = work / name
    directory.mkdir()
    for source in fixtures.glob("*.csv"):
        if source.name in drop:
            continue
        text = source.read_text()
        (directory / source.name).write_text(edit(source.name, text) if edit else text)
    return directory


def figures_mode(dynapath, fixtures, work):
    help_result = plot(dynapath, "--help")
    if help_result.returncode != 0 or "--overlay-reference" not in help_result.stdout:
        fail("dynapath plot --help")

    # The fixture study: default output directory DIR/figures.
    study = study_copy(fixtures, work, "study")
    expected = expected_figures([20, 50], ["Easy", "Hard"], [(50, "Hard")])
    check_figures(plot(dynapath, study), study / "figures", expected, "fixture study")

    # Rectangular size labels, lower-case difficulties, no edge case, --out.
    def rectangular(name, text):
        return text.replace(",50,Hard,", ",40x60,hard,").replace(",50,Easy,", ",40x60,easy,")

    rect = study_copy(fixtures, work, "rect", rectangular,
                      drop=("edge_results.csv", "edge_results_detailed.csv"))
    out = work / "rect-figures"
    check_figures(plot(dynapath, rect, "--out", out), out,
                  expected_figures(["20", "40x60"], ["Easy", "Hard"], []), "rectangular sizes")

    # Only the edge case.
    edge = study_copy(fixtures, work, "edge-only", drop=("results.csv", "results_detailed.csv"))
    names = expected_figures([], [], [(50, "Hard")])
    names -= expected_figures([], [], [])
    check_figures(plot(dynapath, edge), edge / "figures", names, "edge case only")

    # --format png,svg: every figure in both formats (on the edge case's four
    # figures: every figure is written by the same save()).
    vector = work / "vector-figures"
    result = plot(dynapath, edge, "--out", vector, "--format", "png,svg")
    svg = {name[:-4] + ".svg" for name in names}
    check_figures(result, vector, names | svg, "--format png,svg")
    for name in sorted(svg):
        if (vector / name).is_file() and b"<svg" not in (vector / name).read_bytes()[:2000]:
            fail(f"--format png,svg: {name} is not an SVG image")

    # Bad usage: exit 2; bad data: exit 1, naming the file.
    errors = [
        (2, "required"),
        (2, "no such directory", work / "missing"),
        (2, "--bogus", study, "--bogus"),
        (2, "--format", study, "--format", "gif"),
    ]
    empty = work / "empty"
    empty.mkdir()
    errors.append((1, "results.csv", empty))
    cases = {
        "no-detailed": (None, ("results_detailed.csv",), "results_detailed.csv: no such file"),
        "missing-column": (lambda name, text: text.replace("AvgSuccessRate", "Accuracy")
                           if name == "results.csv" else text, (), "AvgSuccessRate"),
        "not-a-number": (lambda name, text: text.replace(",0.0275194,", ",fast,")
                         if name == "results_detailed.csv" else text, (), "'fast' is not a number"),
        "ragged": (lambda name, text: text + "A* Oracle,20,Easy,1,2,3,4,5,6,7,8,9\n"
                   if name == "results.csv" else text, (), "results.csv"),
        "empty-file": (lambda name, text: "" if name == "results.csv" else text, (),
                       "results.csv: empty file"),
        "header-only": (lambda name, text: text.splitlines()[0] + "\n"
                        if name == "results_detailed.csv" else text, (), "no data rows"),
        "duplicate": (lambda name, text: text + text.splitlines()[1] + "\n"
                      if name == "results.csv" else text, (), "a second row"),
        "bad-step": (lambda name, text: text.replace("fedAsynQ_EqAvg,20,Easy,3,", "fedAsynQ_EqAvg,"
                     "20,Easy,3.5,") if name == "results_detailed.csv" else text, (), "TimeStep"),
        "edge-half": (None, ("edge_results_detailed.csv",), "edge_results_detailed.csv"),
    }
    for name, (edit, drop, needle) in cases.items():
        errors.append((1, needle, study_copy(fixtures, work, name, edit, drop)))
    binary = study_copy(fixtures, work, "binary")
    (binary / "results.csv").write_bytes(bytes(range(256)) * 8)
    errors.append((1, "results.csv", binary))
    expect_errors(dynapath, errors)


def reference_mode(dynapath, fixtures, work, reference):
    study = study_copy(fixtures, work, "study")
    expected = expected_figures([20, 50], ["Easy", "Hard"], [(50, "Hard")])
    plain = work / "plain"
    check_figures(plot(dynapath, study, "--out", plain), plain, expected, "without overlay")
    overlaid = work / "overlaid"
    check_figures(plot(dynapath, study, "--out", overlaid, "--overlay-reference"), overlaid,
                  expected, "--overlay-reference")
    explicit = work / "explicit"
    check_figures(plot(dynapath, study, "--out", explicit, "--reference", reference), explicit,
                  expected, "--reference DIR")
    # The overlay changes the by-size figures and the edge summary only.
    for name in ["success_rate_by_size", "adapt_time_by_size", "path_length_by_size",
                 "initial_time_by_size", "edge_summary_50_Hard"]:
        if not all((directory / f"{name}.png").is_file() for directory in (plain, overlaid, explicit)):
            continue  # reported above
        if (plain / f"{name}.png").read_bytes() == (overlaid / f"{name}.png").read_bytes():
            fail(f"--overlay-reference did not change {name}.png")
        if (explicit / f"{name}.png").read_bytes() != (overlaid / f"{name}.png").read_bytes():
            fail(f"--reference {reference} and --overlay-reference differ in {name}.png")

    no_table = work / "reference-without-tables"
    no_table.mkdir()
    broken = work / "broken-reference"
    broken.mkdir()
    shutil.copy(Path(reference) / "paper_results.csv", broken / "paper_results.csv")
    (broken / "paper_edge_results.csv").write_text("Approach,Size\nA* Oracle,50\n")
    expect_errors(dynapath, [
        (2, "--reference", study, "--reference", work / "no-reference"),
        (1, "paper_results.csv", study, "--reference", no_table),
        (1, "paper_edge_results.csv", study, "--reference", broken),
    ])


def main():
    if len(sys.argv) < 4 or sys.argv[3] not in ("figures", "reference"):
        print(__doc__, file=sys.stderr)
        return 2
    dynapath, fixtures, mode = sys.argv[1], Path(sys.argv[2]), sys.argv[3]
    with tempfile.TemporaryDirectory(prefix="plot_test.") as temporary:
        work = Path(temporary)
        if mode == "figures":
            figures_mode(dynapath, fixtures, work)
        else:
            reference_mode(dynapath, fixtures, work, sys.argv[4])
    if failures:
        print(f"{len(failures)} check(s) failed")
        return 1
    print(f"plot_test {mode}: all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
