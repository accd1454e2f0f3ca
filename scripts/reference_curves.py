#!/usr/bin/env python3
"""The LOGO reference code's learning curves, from its run logs into CSVs.

The reference code (github.com/DesikRengarajan/LOGO at 994592f, adapted only to run on
Gymnasium 1.4.0's -v4 envs: docs/results/reference-curves/README.md) prints one line per
iteration:

    BENCH iter=I samples=S cum_samples=C train_R=T eval_R=E kl=K ... wall=W

This turns a log into `<out>/<task>/seed<N>.csv` (iteration, samples, eval_dense_return,
train_sparse_return, delta_k: the columns of the earlier reruns) and adds or replaces the
run's row in `<out>/provenance.csv`. `logo summary --external <out>/<task>,samples,
eval_dense_return,reference` reads a task's folder as one configuration of its seeds.

    scripts/reference_curves.py LOG --task hopper --seed 3 --env-num 1 --wall-s 1300 \
        --cpu "Intel Xeon" --out docs/results/reference-curves/v4
"""

import argparse
import csv
import re
import sys
from datetime import date
from pathlib import Path

BENCH = re.compile(
    r"^BENCH iter=(\d+) samples=(\d+) cum_samples=(\d+) train_R=(\S+) eval_R=(\S+) kl=(\S+)"
)
PROVENANCE = [
    "task", "seed", "env_num", "iterations", "samples", "wall_s", "cpu", "date",
    "source", "torch", "command",
]


def rows_of(log: Path):
    rows = []
    for line in log.read_text().splitlines():
        m = BENCH.match(line)
        if m:
            it, _, cum, train, evaluation, kl = m.groups()
            rows.append([int(it), int(cum), float(evaluation), float(train), float(kl)])
    if not rows:
        sys.exit(f"{log}: no BENCH line (not a log of the adapted reference code)")
    for i, row in enumerate(rows):
        if row[0] != i:
            sys.exit(f"{log}: iteration {row[0]} where {i} was expected (two runs in one log?)")
    return rows


def torch_version(log: Path) -> str:
    m = re.search(r"torch threads: \d+ torch (\S+)", log.read_text())
    return m.group(1) if m else "unknown"


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("log", type=Path)
    p.add_argument("--task", required=True, help="the folder: hopper, walker2d, halfcheetah, idp")
    p.add_argument("--seed", type=int, required=True)
    p.add_argument("--env-num", type=int, required=True, help="run_logo.py's --env-num")
    p.add_argument("--wall-s", type=float, required=True)
    p.add_argument("--cpu", required=True)
    p.add_argument("--date", default=date.today().isoformat())
    p.add_argument("--out", type=Path, required=True)
    args = p.parse_args()

    rows = rows_of(args.log)
    folder = args.out / args.task
    folder.mkdir(parents=True, exist_ok=True)
    with open(folder / f"seed{args.seed}.csv", "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["iteration", "samples", "eval_dense_return", "train_sparse_return", "delta_k"])
        for it, cum, evaluation, train, kl in rows:
            w.writerow([it, cum, f"{evaluation:.6f}", f"{train:.6f}", f"{kl:.6g}"])

    provenance = args.out / "provenance.csv"
    kept = []
    if provenance.is_file():
        with open(provenance, newline="") as f:
            kept = [r for r in csv.DictReader(f)
                    if (r["task"], r["seed"]) != (args.task, str(args.seed))]
    kept.append({
        "task": args.task, "seed": args.seed, "env_num": args.env_num,
        "iterations": len(rows), "samples": rows[-1][1], "wall_s": f"{args.wall_s:.0f}",
        "cpu": args.cpu, "date": args.date,
        "source": "DesikRengarajan/LOGO@994592f + adaptation.diff (Gymnasium 1.4.0 -v4, MuJoCo 3.17.0)",
        "torch": torch_version(args.log),
        "command": f"run_logo.py --env-num {args.env_num} --seed {args.seed} --num-threads 1",
    })
    kept.sort(key=lambda r: (r["task"], int(r["seed"])))
    with open(provenance, "w", newline="") as f:
        w = csv.DictWriter(f, PROVENANCE, lineterminator="\n")
        w.writeheader()
        w.writerows(kept)
    print(f"{folder / f'seed{args.seed}.csv'}: {len(rows)} iterations, {rows[-1][1]} samples")


if __name__ == "__main__":
    main()
