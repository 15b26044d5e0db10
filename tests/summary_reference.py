#!/usr/bin/env python3
"""An independent reference for summary.csv (study/repeat_statistics,
study_results): recomputes every row of SUMMARY from REPEATS (repeats.csv)
and compares the text of each number (%.10g) to the last digit.

The bootstrap intervals are recomputed for the rows named by --bootstrap
(a substring of "Approach,Size,Difficulty,Metric"), with xoshiro256** seeded
by SplitMix64 written here from the generators' published definitions, so a
mistake in the C++ draws, the stratification or the quantile shows.

Usage: summary_reference.py REPEATS SUMMARY [--bootstrap TEXT]...
Exit status 0 when every row agrees, 1 otherwise (each difference printed).
"""
import csv
import sys

MASK = (1 << 64) - 1
METRICS = ["AvgSuccessRate", "AvgPathLength", "InitialTime", "AdaptTimePerStep"]


class Xoshiro256StarStar:
    def __init__(self, seed):
        self.s = []
        state = seed
        for _ in range(4):  # SplitMix64
            state = (state + 0x9E3779B97F4A7C15) & MASK
            z = state
            z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK
            z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK
            self.s.append(z ^ (z >> 31))

    @staticmethod
    def rotl(x, k):
        return ((x << k) | (x >> (64 - k))) & MASK

    def next(self):
        s = self.s
        result = (self.rotl((s[1] * 5) & MASK, 7) * 9) & MASK
        t = (s[1] << 17) & MASK
        s[2] ^= s[0]
        s[3] ^= s[1]
        s[1] ^= s[2]
        s[0] ^= s[3]
        s[2] ^= t
        s[3] = self.rotl(s[3], 45)
        return result

    def below(self, n):
        return ((self.next() >> 32) * n) >> 32


def mean(values):
    total = 0.0
    for v in values:  # in order, as the C++ sums
        total += v
    return total / len(values)


def std(values):
    if len(values) == 1:
        return 0.0
    m = mean(values)
    squares = 0.0
    for v in values:
        squares += (v - m) * (v - m)
    return (squares / (len(values) - 1)) ** 0.5


def median(values):
    v = sorted(values)
    n = len(v)
    return v[n // 2] if n % 2 else (v[n // 2 - 1] + v[n // 2]) / 2


def iqm(values):
    v = sorted(values)
    cut = len(v) // 4
    return mean(v[cut:len(v) - cut])


def quantile(sorted_values, q):
    position = q * (len(sorted_values) - 1)
    below = int(position)
    if below + 1 >= len(sorted_values):
        return sorted_values[-1]
    fraction = position - below
    return sorted_values[below] + fraction * (sorted_values[below + 1] - sorted_values[below])


def bootstrap(strata, statistic, resamples, seed, confidence=0.95):
    rng = Xoshiro256StarStar(seed)
    estimates = []
    for _ in range(resamples):
        pooled = []
        for stratum in strata:
            n = len(stratum)
            pooled.extend(stratum[rng.below(n)] for _ in range(n))
        estimates.append(statistic(pooled))
    estimates.sort()
    tail = (1 - confidence) / 2
    return quantile(estimates, tail), quantile(estimates, 1 - tail)


def text(value):
    return "%.10g" % value


def main(argv):
    repeats_path, summary_path = argv[1], argv[2]
    wanted = [argv[i + 1] for i, a in enumerate(argv) if a == "--bootstrap"]
    groups = {}  # (approach, size, difficulty) -> metric -> values
    order = []
    for row in csv.DictReader(open(repeats_path)):
        key = (row["Approach"], row["Size"], row["Difficulty"])
        if key not in groups:
            groups[key] = {m: [] for m in METRICS}
            order.append(key)
        for m in METRICS:
            groups[key][m].append(float(row[m]))
    failures = 0
    checked_bootstrap = 0
    rows = list(csv.DictReader(open(summary_path)))
    expected_rows = len(order) * len(METRICS)
    approaches = list(dict.fromkeys(k[0] for k in order))
    for a in approaches:
        if sum(1 for k in order if k[0] == a) > 1:
            expected_rows += len(METRICS)
    if len(rows) != expected_rows:
        print(f"summary.csv has {len(rows)} rows, expected {expected_rows}")
        failures += 1
    for row in rows:
        a, size, difficulty, m = row["Approach"], row["Size"], row["Difficulty"], row["Metric"]
        if size == "all":
            strata = [groups[k][m] for k in order if k[0] == a]
        else:
            strata = [groups[(a, size, difficulty)][m]]
        pooled = [v for s in strata for v in s]
        expected = {"Repeats": str(len(pooled)), "Mean": text(mean(pooled)),
                    "Std": text(std(pooled)), "Median": text(median(pooled)),
                    "IQM": text(iqm(pooled))}
        label = ",".join([a, size, difficulty, m])
        if any(w in label for w in wanted):
            checked_bootstrap += 1
            resamples, seed = int(row["Resamples"]), int(row["BootstrapSeed"])
            low, high = bootstrap(strata, mean, resamples, seed)
            expected["MeanCILow"], expected["MeanCIHigh"] = text(low), text(high)
            low, high = bootstrap(strata, iqm, resamples, seed)
            expected["IQMCILow"], expected["IQMCIHigh"] = text(low), text(high)
        for column, value in expected.items():
            if row[column] != value:
                print(f"{label}: {column} {row[column]} in summary.csv, {value} recomputed")
                failures += 1
    if wanted and checked_bootstrap == 0:
        print("no row matched --bootstrap")
        failures += 1
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
