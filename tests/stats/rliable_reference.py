"""rliable's estimates on fixed data: the oracle for logo-stats (crates/logo-stats/tests/rliable.rs).

Writes tests/stats/rliable.json: for each data set (tasks x runs), rliable's mean and IQM
with their stratified-bootstrap 95% percentile intervals, and for pairs of data
sets the probability of improvement with its interval. rliable draws its resamples from
numpy's global stream, seeded here, so the file is reproducible for the pinned packages.

    python tests/stats/rliable_reference.py tests/stats/rliable.json          # write
    python tests/stats/rliable_reference.py --check tests/stats/rliable.json  # compare
"""

import argparse
import json
import math
import sys

import numpy as np
from rliable import library as rly
from rliable import metrics

# 20,000 resamples (rliable's default is 50,000): the check takes about a minute.
REPS = 20_000


def data_sets():
    rng = np.random.default_rng(20261203)
    # Returns shaped like the paper-scale runs: a few seeds, wide spread, one far low.
    five = np.array([[3420.0, 3556.0, 1996.0, 2870.0, 245.0]])
    ten_with_ties = np.round(rng.normal(2500.0, 900.0, size=(1, 10)) / 250.0) * 250.0
    three = np.array([[2518.0, 1183.0, 3011.0]])
    two_tasks = np.stack([rng.normal(3000.0, 700.0, 5), rng.normal(1500.0, 1200.0, 5)])
    other_five = np.array([[2069.0, 3721.0, 455.0, 2029.0, 3100.0]])
    other_two_tasks = np.stack([rng.normal(2600.0, 900.0, 5), rng.normal(1700.0, 1000.0, 5)])
    # (tasks x runs) here, as logo-stats takes them; rliable wants runs x tasks.
    return {
        "five": five,
        "ten_with_ties": ten_with_ties,
        "three": three,
        "two_tasks": two_tasks,
        "other_five": other_five,
        "other_two_tasks": other_two_tasks,
    }


PAIRS = [("five", "other_five"), ("ten_with_ties", "five"), ("two_tasks", "other_two_tasks")]

AGGREGATES = {
    "mean": metrics.aggregate_mean,
    "iqm": metrics.aggregate_iqm,
}


def estimate(scores, func):
    np.random.seed(0)
    point, interval = rly.get_interval_estimates({"x": scores}, lambda s: np.array([func(s)]), reps=REPS)
    return {"point": float(point["x"][0]), "lo": float(interval["x"][0][0]), "hi": float(interval["x"][1][0])}


def estimate_pair(x, y):
    np.random.seed(0)
    point, interval = rly.get_interval_estimates(
        {"xy": [x, y]}, lambda a, b: np.array([metrics.probability_of_improvement(a, b)]), reps=REPS
    )
    return {"point": float(point["xy"][0]), "lo": float(interval["xy"][0][0]), "hi": float(interval["xy"][1][0])}


def build():
    sets = data_sets()
    out = {"reps": REPS, "confidence": 0.95, "sets": {}, "improvement": []}
    for name, tasks in sets.items():
        runs_by_tasks = tasks.T
        out["sets"][name] = {
            "tasks": tasks.tolist(),
            **{agg: estimate(runs_by_tasks, f) for agg, f in AGGREGATES.items()},
        }
    for x, y in PAIRS:
        out["improvement"].append({"x": x, "y": y, **estimate_pair(sets[x].T, sets[y].T)})
    return out


def close(a, b):
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(close(a[k], b[k]) for k in a)
    if isinstance(a, list):
        return len(a) == len(b) and all(close(p, q) for p, q in zip(a, b))
    if isinstance(a, float) or isinstance(b, float):
        return math.isclose(a, b, rel_tol=1e-12, abs_tol=1e-9)
    return a == b


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("path")
    parser.add_argument("--check", action="store_true", help="compare with the file instead of writing it")
    args = parser.parse_args()
    fresh = build()
    if args.check:
        with open(args.path) as f:
            committed = json.load(f)
        if not close(committed, fresh):
            sys.exit(f"{args.path}: rliable's estimates differ from the committed fixture; regenerate it")
        print(f"{args.path}: rliable {len(fresh['sets'])} data sets and {len(PAIRS)} pairs: ok")
    else:
        with open(args.path, "w") as f:
            json.dump(fresh, f, indent=1)
            f.write("\n")


if __name__ == "__main__":
    main()
