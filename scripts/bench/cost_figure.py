#!/usr/bin/env python3
"""Seconds per 1M samples of sparse Hopper, side by side: a horizontal bar per setting
(its low and high measurement as a range on the bar) from a CSV of
`setting,low,high,note`, drawn to a PNG beside it.

  .venv/bin/python scripts/bench/cost_figure.py docs/benchmarks/cost-per-1m.csv
"""

import csv
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main() -> None:
    if len(sys.argv) != 2:
        sys.exit("usage: cost_figure.py DATA.csv (writes DATA.png)")
    path = Path(sys.argv[1])
    with path.open() as f:
        rows = list(csv.DictReader(f))
    for row in rows:
        for key in ("low", "high"):
            try:
                row[key] = float(row[key])
            except (KeyError, ValueError):
                sys.exit(f"{path}: row {row.get('setting')!r}: `{key}` must be a number")
    fig, ax = plt.subplots(figsize=(10, 0.55 * len(rows) + 1.2))
    for y, row in enumerate(reversed(rows)):
        ax.barh(y, row["high"], color="#9ecae1")
        ax.barh(y, row["low"], color="#3182bd")
        label = f"{row['low']:.0f}" if row["low"] == row["high"] else f"{row['low']:.0f}–{row['high']:.0f}"
        ax.text(row["high"] + 5, y, f"{label} s  {row['note']}", va="center", fontsize=8)
    ax.set_yticks(range(len(rows)), [r["setting"] for r in reversed(rows)], fontsize=9)
    ax.set_xlabel("seconds per 1M samples, sparse Hopper, 2 vCPUs (dark: lower measurement)")
    ax.set_xlim(0, max(r["high"] for r in rows) * 2.1)
    fig.tight_layout()
    out = path.with_suffix(".png")
    fig.savefig(out, dpi=110)
    print(out)


if __name__ == "__main__":
    main()
