#!/usr/bin/env python3
"""Writes the small study that tests/plot/plot_test.py draws (fixtures/study):
sizes 20 and 50 x Easy and Hard x four approaches x time steps 0..10, and an
edge case (50 Hard, without our two extra columns). Deterministic; rerun it
only to change the fixtures: python3 tests/plot/make_fixtures.py"""

import csv
import random
from pathlib import Path

APPROACHES = ["A* Static", "A* Oracle", "BFS Oracle", "fedAsynQ_EqAvg"]
STEPS = 10
SUMMARY = ["Approach", "Size", "Difficulty", "InitialTime", "AdaptTimePerStep", "AvgSuccessRate",
           "AvgPathLength"]
DETAILED = ["Approach", "Size", "Difficulty", "TimeStep", "NumChanges", "AdaptTime",
            "SuccessRate", "AvgPathLength", "NodesTrained", "HighestLevel"]


def study(rng, configurations, approaches):
    summary, detailed = [], []
    for size, difficulty in configurations:
        cells = size * size
        hard = difficulty == "Hard"
        changes = [0] + [rng.choice([1, 1, 1, 2, 3]) for _ in range(STEPS)]
        optimum = 4.0 + (2.5 if hard else 0.0) - size / 100
        for approach in approaches:
            initial = {"A* Static": 2e-7 * cells, "A* Oracle": 2e-7 * cells,
                       "BFS Oracle": 1e-8 * cells, "fedAsynQ_EqAvg": 5e-5 * cells}[approach]
            success = 1.0 if not hard else 0.996
            rows = []
            for step in range(STEPS + 1):
                if approach == "A* Static":
                    adapt, success = 0.0, success - 0.012 * changes[step] * (20 / size)
                    length = optimum - 0.1 * step / STEPS
                    nodes, level = 0, -1
                elif approach == "A* Oracle":
                    adapt, length, nodes, level = 1.5e-7 * cells * rng.uniform(0.95, 1.05), \
                        optimum, 0, -1
                elif approach == "BFS Oracle":
                    adapt, length, nodes, level = 8e-9 * cells * rng.uniform(0.9, 1.2), \
                        optimum, 0, -1
                else:
                    retrain = rng.random() < 0.6
                    adapt = rng.uniform(2e-3, 3e-2) if retrain else rng.uniform(5e-5, 1.5e-4)
                    success = min(1.0, max(0.9, success + rng.uniform(-0.01, 0.008)))
                    length, nodes, level = optimum + 0.4, (rng.randint(1, 4) if retrain else 0), \
                        (rng.randint(1, 2) if retrain else -1)
                if step == 0:
                    adapt = 0.0
                rows.append([approach, size, difficulty, step, changes[step], f"{adapt:.6g}",
                             f"{success:.6g}", f"{length:.6g}", nodes, level])
            detailed += rows
            summary.append([approach, size, difficulty, f"{initial:.6g}",
                            f"{sum(float(r[5]) for r in rows[1:]) / STEPS:.6g}",
                            f"{sum(float(r[6]) for r in rows) / len(rows):.6g}",
                            f"{sum(float(r[7]) for r in rows) / len(rows):.6g}"])
    return summary, detailed


def write(path, header, rows):
    with open(path, "w", newline="") as handle:
        writer = csv.writer(handle, lineterminator="\n")
        writer.writerow(header)
        writer.writerows(rows)


def main():
    rng = random.Random(4)
    out = Path(__file__).resolve().parent / "fixtures" / "study"
    out.mkdir(parents=True, exist_ok=True)
    summary, detailed = study(rng, [(20, "Easy"), (20, "Hard"), (50, "Easy"), (50, "Hard")],
                              APPROACHES)
    write(out / "results.csv", SUMMARY, summary)
    write(out / "results_detailed.csv", DETAILED, detailed)
    edge_summary, edge_detailed = study(rng, [(50, "Hard")], APPROACHES)
    write(out / "edge_results.csv", SUMMARY, edge_summary)
    write(out / "edge_results_detailed.csv", DETAILED[:8], [row[:8] for row in edge_detailed])


if __name__ == "__main__":
    main()
