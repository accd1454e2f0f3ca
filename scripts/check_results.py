#!/usr/bin/env python3
"""Recompute every table of docs/results.md from the metrics under docs/results/.

Each table is preceded by a comment saying where its numbers come from, e.g.

    <!-- check summary rows=four-envs/hopper/logo-hopper;four-envs/hopper/trpo-hopper -->

and this script recomputes each cell it knows how to and compares the numbers in it
with the document's, to the precision the document prints (a cell "1611 ± 920" holds
for a recomputed 1610.6 ± 919.8). Cells quoting a paper or another program's output
are not data of docs/results/; their columns are named with `quoted=` and listed.
A table without a check comment is an error: a table can no longer disagree with its data;
so is an option its kind does not read.

Kinds (paths relative to docs/results/; a run folder holds metrics.csv, a group folder
holds seed*/ runs, and a .csv path is one run):
  summary  rows=GROUP;GROUP;...   one row per group, columns by their header
           [iterations=N: each run's first N] [sustained=range] [quoted=3,7]
           [first=N: the iterations a "guidance-step KL" column averages, 25];
           a GROUP of PATH.csv@COLUMN is an outside curve (`logo summary --external`)
           read from that column
  iterations runs=NAME:PATH;...   rows are iteration numbers (1-based: the n-th row of
           metrics.csv); cols=SPEC;SPEC;... one per column after the first, SPEC being
           KIND:COLUMN@RUN with KIND samples | thousands | int | num | last5 (the
           value and the mean of the last 5 evaluations)
  seeds    runs=PATH;PATH;...     one row per run: first >= threshold, final, best, wall
           threshold=RETURN
  points   rows=GROUP;GROUP;...   per seed, the evaluation at each sample count of
           points=S,S,...; then mean ± std at the last
  windows  rows=GROUP;GROUP;...   per group, mean ± std over seeds of each run's mean of a
           cols=COLUMN:A-B;...    metrics.csv column over iterations A..B (0-based, inclusive);
                                  a run folder as the row: its bare mean
  verdicts rows=GROUP>CURVE;...   per row, at each column headed by a budget ("2M"), each
           seeds=N window=W       seed's mean of its W evaluations nearest the budget
                                  against an outside curve's (PATH.csv@COLUMN): "ahead"
                                  when every seed is above it, "behind" when every seed is
                                  below, else "mixed, K of N above"; then "(MEAN vs
                                  CURVE)". Until a row has N seeds that reach the budget
                                  (GROUP "-": none yet), its cell must hold no verdict.
  (intervals, compare: a GROUP of PATH@COLUMN reads that metrics.csv column, as
   `logo summary --metric COLUMN`)
  intervals rows=GROUP;...        `logo summary`'s interval table: per group and column
           window=W               ("final: mean [95% CI]", "at 2.00M: IQM [95% CI]"), the
                                  mean or interquartile mean over seeds of each run's value
                                  (final evaluation, or the mean of its W evaluations
                                  nearest the budget), exact as printed; each interval end
                                  within 5% of the seeds' range of a percentile bootstrap
                                  recomputed here (20,000 resamples; the document's come
                                  from logo-stats' own stream, so only Monte-Carlo error
                                  may separate them)
  compare  groups=A;B window=W     `logo summary --compare A B`'s table: per budget row
                                  ("final", "at 2.00M, mean of 10"), P(A > B) (ties ½)
                                  and the IQM difference A − B over the seeds' values,
                                  exact as printed; interval ends within 0.05 (P) or 5%
                                  of the seeds' range (difference) of a bootstrap over
                                  independent resamples of A and B recomputed here
  arms     rows=SPEC;SPEC;...     configurations against a baseline, a row each, columns
                                  env | budget | configuration | seeds | IQM [95% CI] |
                                  P(configuration > baseline) [95% CI] | IQM difference
                                  [95% CI]; SPEC is GROUP@BUDGET:W (a baseline's row: the
                                  last two cells "—") or GROUP>BASE@BUDGET:W, each seed's
                                  value its mean of the W evaluations nearest BUDGET
                                  (`logo summary --window W --at BUDGET --compare GROUP
                                  BASE`); the seed count exact, each point exact as
                                  printed, interval ends as in intervals and compare
  evaljson rows=GROUP;...         `logo summary`'s end-of-run table from each seed's
                                  eval.json: runs exact; each "[95% CI]" cell's mean
                                  exact as printed (a lone run: its value), its ends
                                  within 5% of the seeds' range of a bootstrap of the
                                  mean; success rates exact as printed
  cells    rXcY=STAT@GROUP ...    single cells (X, Y 1-based over body rows and columns)
           [quoted=...]
  evals    runs=PATH;PATH;...     one row per run: its eval-20.txt (`logo eval` output),
                                  columns by header: "dense return", "x moved" (mean ±
                                  std), "action RMS", "length"; [file=NAME: another
                                  `logo eval` output in each run folder]; "sparse
                                  return" is the first field (the env's own return)

  versus   rows=A>B@BUDGET:W;...  two groups at a budget, a row each, columns task | budget
                                  | A: IQM [95% CI] | seeds | B: IQM [95% CI] | seeds |
                                  P(A > B) [95% CI] | IQM difference [95% CI] | verdict;
                                  each seed's value its mean of the W evaluations nearest
                                  BUDGET (a group may be an outside curve's folder of
                                  seed*.csv); intervals as in arms; the verdict "ahead" or
                                  "behind" where the difference's interval excludes 0,
                                  "level" where it holds 0 and both ends are within 25% of the
                                  smaller IQM (LEVEL_SHARE), else "cannot separate", with
                                  ", suggests" under 5 seeds a side;
           [max=SAMPLES|budget]   every run read up to SAMPLES, or to its row's budget
                                  (`logo summary --max-samples`)
  config   file=PATH              a settings table: the first column `[table] key` or
                                  `key`, the second its value in that TOML file

  suite    rows=GROUP;...         a suite task's final policies (scripts/experiments/suite.py
           demos=K/N |            report), a row per method, the first group LOGO's; each
           demos_return=R         seed*/ folder holds eval.json or BC's policy.eval.json
                                  (the "final" policy, mean action): seeds exact; "final
                                  return: IQM [95% CI]" and "IQM difference" as in arms;
                                  "reached the goal, ... per seed" each seed's k, then "of
                                  n"; "seeds at ≥ the demonstrations'" the seeds whose rate
                                  k/n ≥ K/N (without a goal: whose return ≥ R); "P(LOGO >
                                  method)" as in arms; "—" for LOGO's own row
  matrix   rows=A@BUDGET:W;...    a grid of verdicts, a row per group A (its first cell a free
           rRcC=B ...             label) and a column per method (the header free): each cell
                                  rRcC (1-based body row and column) "VERDICT DIFF [LO, HI]"
                                  for A against B, each seed's mean of its W evaluations nearest
                                  BUDGET, runs read up to BUDGET (whole, as `logo summary`
                                  without --max-samples, where the row ends in +): the IQM
                                  difference A − B and
                                  its interval as in versus, the verdict by versus' rule from
                                  the printed interval (versus' level; ", suggests" under 5
                                  seeds a side);
                                  every other cell after the first column "—"
  answer   rows=MEASURE=G,...;... the README's task × method table, a row per task: the
           [prose=N]              columns after "task" and "measure" are methods, each G the
                                  runs of the column's method (its folder's name says which)
                                  or "-" (a cell "—"); MEASURE "final" (final policies'
                                  return, eval.json) or "window@B:W[+]" (dense evaluations as
                                  matrix rows; a BC folder's final dense return): each cell
                                  the IQM over 5 seeds; the last "**LEADER**; ahead of ...;
                                  level with ...; cannot separate from ..." by versus' rule on
                                  the leader's difference with each; with prose=N, the words of
                                  the section around the table (tables and comments left out)
                                  are at most N
  none                            a table with no data to recompute (a map of the repository)
  target   rows=A>B;...           the suite's target per task, a row each: A a LOGO arm's
                                  group suite/TASK/logo…, B suite/TASK/trpo, 5 seeds each, the
                                  demonstrations' level suite_arms.py's; columns task (TASK in
                                  backticks) | LOGO (A's suite name) | seeds at ≥ the
                                  demonstrations (their rate at the goal, or their return
                                  where the task has none) | P(LOGO > TRPO) [95% CI] (as in
                                  suite) | target: "met" where at least 4 seeds meet the
                                  demonstrations and P's printed lower end is above 0.5, else
                                  "not met: " the demonstrations, TRPO or both; the columns
                                  after these (the page's reading) named in quoted=, and only
           [policy=best]          those; policy=best: every seed's best policy (eval.json's
                                  "best") in place of its final one, for LOGO and TRPO alike
  goal     rows=GROUP;...         a task that ends only at its goal: per group its seeds
                                  (exact), then per column "final: ... per seed" (or
                                  "best: ..."), each seed's count of eval.json episodes
                                  that terminated, in seed order, or "... all episodes",
                                  the seeds whose every episode did

Exit status 1 on any mismatch, listing table, row, column, document and data.
Usage: scripts/check_results.py [PAGE ...]   (default: docs/results.md, docs/findings/*.md)
"""

import csv
import json
import math
import re
import statistics
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
NUMBER = re.compile(r"-?\d[\d,]*(?:\.\d+)?(?:e[-+]?\d+)?")


# ---------------------------------------------------------------- reading runs

def open_kept(path):
    """A kept file as text, decompressed where it ends in .gz (docs/results/README.md)."""
    import gzip
    if path.suffix == ".gz":
        return gzip.open(path, "rt", newline="")
    return open(path, newline="")


def kept_file(folder, name):
    """FOLDER/NAME, or FOLDER/NAME.gz where the run keeps it compressed; None if neither."""
    return next((p for p in (folder / name, folder / f"{name}.gz") if p.is_file()), None)


def read_json(path):
    with open_kept(path) as f:
        return json.load(f)


def read_run(path):
    """Rows of one metrics.csv as dicts of floats (NaN where empty or not a number)."""
    rows = []
    with open_kept(path) as f:
        for raw in csv.DictReader(f):
            row = {}
            for key, value in raw.items():
                try:
                    row[key] = float(value)
                except (TypeError, ValueError):
                    row[key] = math.nan
            rows.append(row)
    if not rows:
        raise SystemExit(f"{path}: no rows")
    return rows


def run_file(path):
    path = ROOT / "docs/results" / path
    if path.suffix == ".csv":
        return path
    if kept_file(path, "metrics.csv"):
        return kept_file(path, "metrics.csv")
    raise SystemExit(f"{path}: neither a .csv nor a run folder with metrics.csv")


def group_runs(path):
    """The runs of a group folder (seed*/metrics.csv, or an outside curve's seed*.csv as
    `logo summary --external FOLDER` reads it, in seed order), or the one run."""
    base = ROOT / "docs/results" / path
    seeds = sorted((f for f in (kept_file(d, "metrics.csv") for d in base.glob("seed*/")) if f),
                   key=lambda p: int(p.parent.name[4:]))
    if seeds:
        return [read_run(p) for p in seeds]
    curves = sorted(base.glob("seed*.csv"), key=lambda p: int(p.stem[4:]))
    if curves:
        return [read_run(p) for p in curves]
    return [read_run(run_file(path))]


def evaluations(rows, metric="eval_dense_return"):
    return [(r["samples"], r[metric]) for r in rows if math.isfinite(r[metric])]


def group_points(spec):
    """Each run's (samples, value) points of a group "PATH[@COLUMN]"."""
    path, _, metric = spec.partition("@")
    return [evaluations(rows, metric or "eval_dense_return") for rows in group_runs(path)]


# ---------------------------------------------------------------- statistics

def interpolate(points, x):
    """The evaluation curve at x samples, linear between evaluations (as `logo summary`)."""
    for i, (x1, y1) in enumerate(points):
        if x1 >= x:
            if i == 0:
                return y1
            x0, y0 = points[i - 1]
            return y1 if x1 == x0 else y0 + (y1 - y0) * (x - x0) / (x1 - x0)
    return points[-1][1]


def mean_std(values):
    if not values:
        return None
    return statistics.fmean(values), (statistics.stdev(values) if len(values) > 1 else 0.0)


def pm(values):
    m, s = mean_std(values)
    return f"{m!r} ± {s!r}"


def samples_text(x):
    return f"{x / 1e6!r}M" if x >= 1e6 else f"{x / 1e3!r}k"


def sustained(rows, length=5):
    """Samples at the first of `length` iterations in a row with a sparse return above 0."""
    streak = 0
    for i, r in enumerate(rows):
        streak = streak + 1 if r["train_sparse_return"] > 0 else 0
        if streak == length:
            return rows[i - length + 1]["samples"]
    return None


def first_hit(rows):
    return next((r["samples"] for r in rows if r["train_sparse_return"] > 0), None)


def window_values(group, x, n, limit=math.inf):
    """Each run's mean of its n evaluations nearest x, the run read up to `limit` samples;
    runs that stop short of x left out."""
    values = (
        window_at([p for p in evaluations(rows) if p[0] <= limit], x, n)
        for rows in group_runs(group)
    )
    return [v for v in values if v is not None]


def window_at(points, x, n):
    """Mean of the n evaluations nearest x, ties to the later one (`logo summary
    --window`); None if the run stops more than its median spacing short of x."""
    gaps = [b[0] - a[0] for a, b in zip(points, points[1:])]
    spacing = statistics.median(gaps) if gaps else 0.0
    if x > points[-1][0] + spacing:
        return None
    nearest = sorted(points, key=lambda p: (abs(p[0] - x), -p[0]))[:n]
    return statistics.fmean(y for _, y in nearest)


def iqm(values):
    """Interquartile mean: drop floor(n/4) values at each end (scipy's trim_mean 0.25)."""
    v = sorted(values)
    cut = len(v) // 4
    return statistics.fmean(v[cut:len(v) - cut])


def probability_of_improvement(x, y):
    """P(X > Y) + P(X = Y) / 2 over all pairs (rliable's, one task)."""
    wins = sum(1.0 if a > b else 0.5 if a == b else 0.0 for a in x for b in y)
    return wins / (len(x) * len(y))


def bootstrap_two(x, y, stat, reps=20_000, seed=0):
    """95% percentile interval of stat(x, y) over independent resamples of x and y."""
    return percentile_interval(bootstrap_two_draws(x, y, stat, reps, seed))


def bootstrap_two_draws(x, y, stat, reps=20_000, seed=0):
    """The sorted draws of bootstrap_two (the same stream)."""
    import random
    rng = random.Random(seed)
    return sorted(
        stat([x[rng.randrange(len(x))] for _ in x], [y[rng.randrange(len(y))] for _ in y])
        for _ in range(reps)
    )


def band_agrees(cell, point, draws, tolerance):
    """interval_agrees for a statistic of few values (P over 5 × 4 pairs moves in steps of
    0.05): each end may lie anywhere between the recomputed draws' quantiles 0.5% either
    side of its own, so a Monte-Carlo stream that lands on the other side of a step still
    agrees (the quantile's sampling error at 20,000 draws is about 0.1%)."""
    doc = numbers(cell)
    if len(doc) < 3 or abs(doc[0][0] - point) > 0.5 * doc[0][1] + 1e-9:
        return False

    for (d, unit), q in zip(doc[1:3], (0.025, 0.975)):
        low, high = quantile(draws, q - 0.005), quantile(draws, q + 0.005)
        if not low - tolerance - 0.5 * unit <= d <= high + tolerance + 0.5 * unit:
            return False
    return True


def bootstrap_interval(values, stat, reps=20_000, seed=0):
    """95% percentile bootstrap interval of stat over values (numpy's linear quantiles)."""
    import random
    rng = random.Random(seed)
    n = len(values)
    return percentile_interval(stat([values[rng.randrange(n)] for _ in range(n)]) for _ in range(reps))


def quantile(draws, q):
    """numpy's linear quantile q of sorted draws."""
    h = (len(draws) - 1) * q
    lo = math.floor(h)
    return draws[lo] + (h - lo) * (draws[min(lo + 1, len(draws) - 1)] - draws[lo])


def percentile_interval(draws):
    """The 2.5% and 97.5% quantiles of the bootstrap draws (numpy's linear quantiles)."""
    draws = sorted(draws)
    return quantile(draws, 0.025), quantile(draws, 0.975)


def late_mean(points):
    late = math.ceil(len(points) / 10)
    return statistics.fmean(y for _, y in points[-late:])


def parse_samples(text):
    m = re.fullmatch(r"([\d.]+)\s*([kM]?)", text.strip())
    if not m:
        return None
    return float(m.group(1)) * {"": 1, "k": 1e3, "M": 1e6}[m.group(2)]


def first_iterations(runs, n):
    """Each run's first `n` iterations (None: whole)."""
    return runs if n is None else [rows[:n] for rows in runs]


def column_value(header, runs, opts, metric="eval_dense_return"):
    """The recomputed cell of a summary-like column, or None if the header is unknown."""
    h = header.strip().replace("**", "")
    points = [evaluations(rows, metric) for rows in runs]
    finals = [p[-1][0] for p in points]
    if h == "seeds":
        return str(len(runs))
    if h.startswith("samples (min"):
        return f"{samples_text(min(finals))}–{samples_text(max(finals))}"
    if h == "samples":
        return samples_text(min(finals))
    if h == "final":
        return pm([p[-1][1] for p in points])
    if h == "peak":
        return pm([max(y for _, y in p) for p in points])
    if h.startswith("samples at peak"):
        return samples_text(statistics.median(max(p, key=lambda q: q[1])[0] for p in points))
    if h == "mean of last 10%":
        return pm([late_mean(p) for p in points])
    m = re.match(r"at ([\d.]+\s*[kM]?)(?:, mean of (\d+))?", h)
    if m:
        x = parse_samples(m.group(1))
        if m.group(2):
            values = [v for p in points if (v := window_at(p, x, int(m.group(2)))) is not None]
        else:
            values = [interpolate(p, x) for p in points if x <= p[-1][0]]
        if len(values) < len(points):
            seeds = "1 seed" if len(values) == 1 else f"{len(values)} seeds"
            return f"{pm(values)} ({seeds})" if values else "—"
        return pm(values)
    m = re.match(r"seeds ≥ (\d+)", h)
    if m:
        t = float(m.group(1))
        reached = [next(x for x, y in p if y >= t) for p in points if any(y >= t for _, y in p)]
        if not reached:
            return f"0/{len(runs)}"
        return f"{len(reached)}/{len(runs)} ({samples_text(statistics.median(reached))})"
    if "sustained" in h or h.startswith("first sparse reward"):
        at = [sustained(rows) if "sustained" in h else first_hit(rows) for rows in runs]
        if "seeds 0 / 1 / 2" in h:
            return " / ".join("never" if a is None else f"{a / 1e6!r}M" for a in at)
        hits = sorted(a for a in at if a is not None)
        if opts.get("sustained") == "range":
            if hits:
                return f"{hits[0] / 1e6!r}–{hits[-1] / 1e6!r}M"
            firsts = sorted(a for a in map(first_hit, runs) if a is not None)
            by = round(max(finals) / 1e6)
            return f"never by {by}M (first hits {firsts[0] / 1e6!r}–{firsts[-1] / 1e6!r}M)"
        if not hits:
            return f"0/{len(runs)}"
        if h.startswith("first sparse reward"):
            listing = ", ".join(f"{a / 1e6!r}M" for a in hits)
        elif len(hits) == 1:
            listing = f"{hits[0] / 1e6!r}M"
        else:
            listing = f"{hits[0] / 1e6!r}–{hits[-1] / 1e6!r}M"
        return f"{len(hits)}/{len(runs)} ({listing})"
    m = re.match(r"evaluations < (\d+) after reaching (\d+)", h)
    if m:
        low, high = float(m.group(1)), float(m.group(2))
        fell = total = 0
        for p in points:
            reached = False
            for _, y in p:
                if reached:
                    total += 1
                    fell += y < low
                reached = reached or y >= high
        return f"{fell} / {total} ({100 * fell / total!r}%)"
    m = re.match(r"(guidance-step KL|improvement-step epochs)", h)
    if m:
        column = {"guidance-step KL": "guidance_kl", "improvement-step epochs": "update_epochs"}[m.group(1)]
        first = int(opts.get("first", 25))
        return repr(statistics.fmean(r[column] for rows in runs for r in rows[:first]))
    return None


def suite_finals(group, policy="final"):
    """Each finished seed's final policy (mean action) of a suite group, in seed order, or
    the policy its run kept as best (`policy="best"`), as eval.json scores it."""
    base = ROOT / "docs/results" / group
    finals = []
    for folder in sorted(base.glob("seed*"), key=lambda p: int(p.name[4:])):
        file = kept_file(folder, "eval.json") or kept_file(folder, "policy.eval.json")
        if file is not None:
            finals.append(read_json(file)["policies"][policy]["mean_action"]["summary"])
    return finals


sys.path.insert(0, str(Path(__file__).resolve().parent / "experiments"))
from suite_arms import ARM_NAMES as SUITE_ARMS, DEMONSTRATED  # noqa: E402 (the suite's own)


def seeds_at_demonstrations(task, finals):
    """How many of a suite task's seeds (their eval.json summaries) are at or above the
    demonstrations: their rate at the goal, or their return where the task has none."""
    demo = DEMONSTRATED[task]
    if demo["reached"] is None:
        return sum(f["return"] >= demo["return"] for f in finals)
    k, n = demo["reached"]
    return sum(f["reached"][0] / f["reached"][1] >= k / n for f in finals)


def improvement_agrees(cell, xs, ys):
    """A cell "P [LO, HI]" of P(X > Y): the point exact, each end within the band of the
    bootstrap's quantiles (P moves in steps of 1/pairs, see band_agrees)."""
    draws = bootstrap_two_draws(xs, ys, probability_of_improvement)
    return band_agrees(cell, probability_of_improvement(xs, ys), draws, 0.0)


# "Level" is an interval narrow against the values compared: both its ends within this
# share of the smaller of the two IQMs. The one rule every page's verdicts follow.
LEVEL_SHARE = 0.25


def verdict(lo, hi, seeds, scale):
    """The verdict on an interval [LO, HI] of a difference A − B whose smaller IQM is
    SCALE: "ahead" or "behind" where it excludes 0; "level" where it holds 0 and both
    ends are within LEVEL_SHARE of SCALE (a positive SCALE); else "cannot separate";
    ", suggests" where a side has fewer than 5 seeds."""
    narrow = scale > 0 and max(abs(lo), abs(hi)) <= LEVEL_SHARE * scale
    word = ("ahead" if lo > 0 else "behind" if hi < 0 else "level" if narrow
            else "cannot separate")
    return word + (", suggests" if min(seeds) < 5 else "")


def verdict_agrees(printed, cell, draws, seeds, scale):
    """The printed verdict is its cell's printed interval's, and one the recomputed draws
    give with each end anywhere in its band (quantiles 0.5% either side, as band_agrees):
    an end printed across 0, or across the level's bound, within the interval's tolerance
    still fails."""
    ends = numbers(cell)
    if len(ends) < 3 or printed != verdict(ends[1][0], ends[2][0], seeds, scale):
        return False
    lows = (quantile(draws, 0.02), quantile(draws, 0.03))
    highs = (quantile(draws, 0.97), quantile(draws, 0.98))
    return printed in {verdict(lo, hi, seeds, scale) for lo in lows for hi in highs}


def exact_cell(body, header, wrong, r, c, text):
    """A cell without numbers to round (a label, "—", a verdict) is TEXT; returns the
    cells checked (1), for the caller's count."""
    if body[r][c] != text:
        wrong.append((r + 1, header[c], body[r][c], text))
    return 1


def check_suite(opts, header, body, compare, wrong):
    """The `suite` kind (see the module's docstring); returns how many cells it checked
    itself (`compare`, for numbers to their printed precision, counts its own)."""
    checked = 0
    groups = opts["rows"].split(";")
    if len(groups) != len(body):
        raise SystemExit(f"suite: {len(groups)} groups for {len(body)} rows")
    task = Path(groups[0]).parent.name
    goal = "demos" in opts
    demo = DEMONSTRATED.get(task)
    if demo is not None:
        said = tuple(int(v) for v in opts["demos"].split("/")) if goal else float(opts["demos_return"])
        if said != (demo["reached"] if goal else demo["return"]):
            raise SystemExit(f"suite: demos of {task} are {demo}, not {said} (suite_arms.py)")
    target = f"seeds at ≥ the demonstrations' {opts['demos']}" if goal else (
        f"seeds at ≥ the demonstrations' return {float(opts['demos_return']):.1f}")
    expected = ["method", "seeds", "final return: IQM [95% CI]",
                "reached the goal, final policy per seed" if goal else "reached the goal",
                target, "P(LOGO > method) [95% CI]", "IQM difference LOGO − method [95% CI]"]
    if header != expected:
        raise SystemExit(f"suite: header {header} is not suite.py's {expected}")
    finals = [suite_finals(g) for g in groups]
    returns = [[f["return"] for f in group] for group in finals]
    logo = returns[0]
    for r, (path, group, values) in enumerate(zip(groups, finals, returns)):
        checked += exact_cell(body, header, wrong, r, 0, SUITE_ARMS.get(Path(path).name, Path(path).name))
        compare(r, 1, str(len(values)))
        if not values:
            for c in range(2, len(header)):
                checked += exact_cell(body, header, wrong, r, c, "—")
            continue
        spread = max(values) - min(values)
        lo, hi = bootstrap_interval(values, iqm)
        checked += 1
        if not interval_agrees(body[r][2], iqm(values), (lo, hi), 0.05 * spread):
            wrong.append((r + 1, header[2], body[r][2], f"{iqm(values):.1f} [{lo:.1f}, {hi:.1f}]"))
        if goal:
            counts = [f["reached"] for f in group]
            compare(r, 3, ", ".join(str(k) for k, _ in counts) + f" of {counts[0][1]}")
            k, n = (int(v) for v in opts["demos"].split("/"))
            met = sum(a / b >= k / n for a, b in counts)
        else:
            checked += exact_cell(body, header, wrong, r, 3, "— (no goal)")
            met = sum(v >= float(opts["demos_return"]) for v in values)
        compare(r, 4, f"{met} of {len(values)}")
        if r == 0 or not logo:
            checked += exact_cell(body, header, wrong, r, 5, "—")
            checked += exact_cell(body, header, wrong, r, 6, "—")
            continue
        checked += 1
        if not improvement_agrees(body[r][5], logo, values):
            wrong.append((r + 1, header[5], body[r][5], f"{probability_of_improvement(logo, values):.2f}"))
        difference = lambda u, v: iqm(u) - iqm(v)  # noqa: E731
        point = difference(logo, values)
        lo, hi = bootstrap_two(logo, values, difference)
        checked += 1
        if not interval_agrees(body[r][6], point, (lo, hi), 0.05 * (max(logo + values) - min(logo + values))):
            wrong.append((r + 1, header[6], body[r][6], f"{point:.1f} [{lo:.1f}, {hi:.1f}]"))
    return checked


TARGET_HEADER = ["task", "LOGO", "seeds at ≥ the demonstrations", "P(LOGO > TRPO) [95% CI]", "target"]


def check_target(opts, header, body, compare, wrong):
    """The `target` kind (see the module's docstring); returns the cells it checked itself."""
    checked = 0
    rows = opts["rows"].split(";")
    if len(rows) != len(body):
        raise SystemExit(f"target: {len(rows)} rows named for {len(body)} in the table")
    if header[:len(TARGET_HEADER)] != TARGET_HEADER:
        raise SystemExit(f"target: header {header[:len(TARGET_HEADER)]} is not {TARGET_HEADER}")
    quoted = {int(c) for c in opts.get("quoted", "").split(",") if c}
    if quoted != set(range(len(TARGET_HEADER) + 1, len(header) + 1)):
        raise SystemExit(f"target: quoted= must name the columns after the {len(TARGET_HEADER)}th "
                         f"(the page's reading), and only those")
    policy = opts.get("policy", "final")
    if policy not in ("final", "best"):
        raise SystemExit(f"target: policy={policy}: expected final or best")
    for r, spec in enumerate(rows):
        m = re.fullmatch(r"(suite/([^/>]+)/(logo[^/>]*))>(suite/([^/>]+)/trpo)", spec)
        if not m or m.group(2) != m.group(5):
            raise SystemExit(f"target: row {spec!r} is not suite/TASK/LOGO-ARM>suite/TASK/trpo")
        task = m.group(2)
        if task not in DEMONSTRATED:
            raise SystemExit(f"target: {task} is not a suite task (suite_arms.py DEMONSTRATED)")
        logo, trpo = suite_finals(m.group(1), policy), suite_finals(m.group(4), policy)
        if len(logo) != 5 or len(trpo) != 5:
            raise SystemExit(f"target: {spec}: {len(logo)} and {len(trpo)} seeds; the target is "
                             "read over 5 seeds a side")
        checked += exact_cell(body, header, wrong, r, 0, f"`{task}`")
        checked += exact_cell(body, header, wrong, r, 1, SUITE_ARMS.get(m.group(3), m.group(3)))
        met = seeds_at_demonstrations(task, logo)
        compare(r, 2, f"{met} of {len(logo)}")
        xs, ys = [f["return"] for f in logo], [f["return"] for f in trpo]
        checked += 1
        if not improvement_agrees(body[r][3], xs, ys):
            wrong.append((r + 1, header[3], body[r][3], f"{probability_of_improvement(xs, ys):.2f}"))
            continue
        # The verdict reads the printed lower end, just checked against the bootstrap.
        beats_trpo = numbers(body[r][3])[1][0] > 0.5
        missed = [name for name, ok in (("the demonstrations", met >= 4), ("TRPO", beats_trpo)) if not ok]
        checked += exact_cell(body, header, wrong, r, 4, "met" if not missed else
                              "not met: " + ("both" if len(missed) == 2 else missed[0]))
    return checked


MATRIX_LABEL = re.compile(r"\((\d+)(?: seeds)? × ([\d.]+[kM])\)")

# The last cell of an answer row: the leader, then whom its interval puts it ahead of,
# level with and cannot separate it from (each list may be absent).
ANSWER_LEADER = re.compile(
    r"\*\*(?P<leader>[^*]+)\*\*"
    r"(?:; ahead of (?P<ahead>[^;]+))?(?:; level with (?P<level>[^;]+))?"
    r"(?:; cannot separate from (?P<open>[^;]+))?")


def answer_values(measure, group):
    """One method's values on an answer row, a seed each: `final`, the final policies'
    return on the task's own reward (eval.json, BC's policy.eval.json); `window@B:W[+]`,
    each run's mean of its W dense evaluations nearest B (read up to B, or whole with +),
    or for a BC folder (no curve) its final policy's dense return over its episodes."""
    if measure == "final":
        return [f["return"] for f in suite_finals(group)]
    m = re.fullmatch(r"window@([\d.]+[kM]?):(\d+)(\+?)", measure)
    if not m:
        raise SystemExit(f"answer: measure {measure!r} is not final or window@BUDGET:W[+]")
    budget, window = parse_samples(m.group(1)), int(m.group(2))
    if not any((ROOT / "docs/results" / group).glob("seed*/metrics.csv*")):
        return [f["dense_return"] for f in suite_finals(group)]
    return window_values(group, budget, window, math.inf if m.group(3) else budget)


# The method an answer column names, by the folder its runs are in.
ANSWER_METHODS = {"logo": "LOGO", "trpo": "TRPO", "bc": "BC", "gail": "GAIL", "pofd": "POfD",
                  "bc-trpo": "BC-TRPO", "dapg": "DAPG", "bc-logo": "LOGO from the clone"}


def check_answer(opts, header, body, wrong):
    """The `answer` kind (see the module's docstring); returns the cells checked."""
    checked = 0
    specs = opts["rows"].split(";")
    if len(specs) != len(body):
        raise SystemExit(f"answer: {len(specs)} row specs for {len(body)} rows")
    methods = header[2:-1]
    for r, spec in enumerate(specs):
        measure, _, groups = spec.partition("=")
        groups = groups.split(",")
        if len(groups) != len(methods):
            raise SystemExit(f"answer: row {r + 1} names {len(groups)} groups for "
                             f"{len(methods)} methods")
        values = {}
        for c, (method, group) in enumerate(zip(methods, groups), start=2):
            if group == "-":
                checked += exact_cell(body, header, wrong, r, c, "—")
                continue
            named = ANSWER_METHODS.get(Path(group).name.lower())
            if named != method:
                raise SystemExit(f"answer: row {r + 1}: {group} is {named}'s runs, in the "
                                 f"column of {method}")
            xs = answer_values(measure, group)
            if len(xs) < 5:
                raise SystemExit(f"answer: {group}: {len(xs)} seeds, 5 expected")
            values[method] = xs
            checked += 1
            cell = numbers(body[r][c])
            if len(cell) != 1 or abs(cell[0][0] - iqm(xs)) > 0.5 * cell[0][1] + 1e-9:
                wrong.append((r + 1, header[c], body[r][c], f"{iqm(xs):.1f}"))
        leader = max(values, key=lambda m: iqm(values[m]))
        groups_of = {"ahead": [], "level": [], "open": []}
        for method, ys in values.items():
            if method == leader:
                continue
            xs = values[leader]
            lo, hi = percentile_interval(bootstrap_two_draws(xs, ys, lambda u, v: iqm(u) - iqm(v)))
            word = verdict(lo, hi, (len(xs), len(ys)), min(iqm(xs), iqm(ys)))
            groups_of["ahead" if word == "ahead" else "level" if word == "level" else "open"].append(method)
        said = ANSWER_LEADER.fullmatch(body[r][-1].strip())
        expected = f"**{leader}**" + "".join(
            f"; {words} {', '.join(groups_of[key])}" for key, words in
            (("ahead", "ahead of"), ("level", "level with"), ("open", "cannot separate from"))
            if groups_of[key])
        checked += 1
        if said is None or body[r][-1].strip() != expected:
            wrong.append((r + 1, header[-1], body[r][-1], expected))
    prose = opts.get("prose")
    return checked, prose


def prose_words(lines, table_line):
    """The words of the section holding the table at TABLE_LINE (1-based: its header),
    its tables and comments left out: from the heading above it to the next heading."""
    start = max((i for i in range(table_line) if lines[i].startswith("#")), default=-1)
    end = next((i for i in range(table_line, len(lines)) if lines[i].startswith("#")), len(lines))
    text = [x for x in lines[start + 1:end] if not x.startswith(("|", "<!--"))]
    return len(" ".join(text).split())



def check_matrix(opts, header, body, wrong):
    """The `matrix` kind (see the module's docstring); returns the cells it checked."""
    checked = 0
    rows = opts["rows"].split(";")
    if len(rows) != len(body):
        raise SystemExit(f"matrix: {len(rows)} rows named for {len(body)} in the table")
    named = {}
    for key, other in opts.items():
        m = re.fullmatch(r"r(\d+)c(\d+)", key)
        if m:
            r, c = int(m.group(1)) - 1, int(m.group(2)) - 1
            if not (0 <= r < len(body) and 1 <= c < len(header)):
                raise SystemExit(f"matrix: {key} is outside the body's rows and columns 2–{len(header)}")
            named[(r, c)] = other
    for r, row in enumerate(body):
        for c in range(1, len(row)):
            if (r, c) not in named:
                checked += exact_cell(body, header, wrong, r, c, "—")
    columns = {}
    for (r, c), other in named.items():
        columns.setdefault(c, set()).add(SUITE_ARMS.get(Path(other).name, Path(other).name))
    for c, names in sorted(columns.items()):
        if names != {header[c]}:
            raise SystemExit(f"matrix: column {c + 1} `{header[c]}` holds {sorted(names)}")
    for r, spec in enumerate(rows):
        m = re.fullmatch(r"([^@]+)@([\d.]+[kM]?):(\d+)(\+?)", spec)
        if not m:
            raise SystemExit(f"matrix: row {spec!r} is not GROUP@BUDGET:W[+]")
        budget, window = parse_samples(m.group(2)), int(m.group(3))
        limit = math.inf if m.group(4) else budget
        xs = window_values(m.group(1), budget, window, limit)
        # The row's label says its seeds and budget: "(5 seeds × 200k)".
        label = MATRIX_LABEL.search(body[r][0])
        checked += 1
        if label is None or int(label.group(1)) != len(xs) or parse_samples(label.group(2)) != budget:
            wrong.append((r + 1, header[0], body[r][0], f"… ({len(xs)} × {m.group(2)})"))
        for c in sorted(c for (row, c) in named if row == r):
            ys = window_values(named[(r, c)], budget, window, limit)
            difference = lambda u, v: iqm(u) - iqm(v)  # noqa: E731
            draws = bootstrap_two_draws(xs, ys, difference)
            point, (lo, hi) = difference(xs, ys), percentile_interval(draws)
            scale = min(iqm(xs), iqm(ys))
            cell = body[r][c]
            split = re.search(r"[−-]?\d", cell)
            printed, figures = (cell[:split.start()].strip(), cell[split.start():]) if split else (cell, "")
            checked += 1
            if len(numbers(figures)) != 3 or not interval_agrees(
                    figures, point, (lo, hi), 0.05 * (max(xs + ys) - min(xs + ys))):
                wrong.append((r + 1, header[c], cell, f"{point:.1f} [{lo:.1f}, {hi:.1f}]"))
            elif not verdict_agrees(printed, figures, draws, (len(xs), len(ys)), scale):
                wrong.append((r + 1, header[c], cell, verdict(lo, hi, (len(xs), len(ys)), scale)))
    return checked

# ---------------------------------------------------------------- comparing

def numbers(text):
    text = text.replace("−", "-").replace("**", "")
    found = []
    for m in NUMBER.finditer(text):
        token = m.group(0).replace(",", "")
        mantissa = token.split("e")[0]
        decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
        exponent = int(token.split("e")[1]) if "e" in token else 0
        found.append((float(token), 10.0 ** (exponent - decimals)))
    return found


def agrees(document, computed):
    """Every number the document prints is the recomputed one, rounded as printed."""
    doc, data = numbers(document), numbers(computed)
    if len(doc) != len(data):
        return False
    return all(abs(d - c) <= 0.5 * unit * (1 + 1e-9) + 1e-12 for (d, unit), (c, _) in zip(doc, data))


def interval_agrees(cell, point, interval, tolerance):
    """A cell "POINT [LO, HI]": the point exact as printed, each end within `tolerance`
    (plus half its printed unit) of a bootstrap recomputed here."""
    doc = numbers(cell)
    return len(doc) >= 3 and abs(doc[0][0] - point) <= 0.5 * doc[0][1] + 1e-9 and all(
        abs(d - e) <= tolerance + 0.5 * unit for (d, unit), e in zip(doc[1:3], interval)
    )


# ---------------------------------------------------------------- tables

def tables(lines):
    """(check comment or None, header cells, body rows, line number) per table."""
    found, i = [], 0
    while i < len(lines):
        if lines[i].startswith("|") and i + 1 < len(lines) and re.match(r"^\|( *-+ *\|)+ *$", lines[i + 1]):
            comment = None
            j = i - 1
            while j >= 0 and not lines[j].strip():
                j -= 1
            if j >= 0 and lines[j].strip().startswith("<!-- check"):
                comment = lines[j].strip()[len("<!-- check"):-len("-->")].strip()
            cells = lambda line: [c.strip() for c in line.strip().strip("|").split("|")]
            header = cells(lines[i])
            body, k = [], i + 2
            while k < len(lines) and lines[k].startswith("|"):
                body.append(cells(lines[k]))
                k += 1
            found.append((comment, header, body, i + 1))
            i = k
        else:
            i += 1
    return found


def options(comment):
    kind, _, rest = comment.partition(" ")
    opts = dict(part.split("=", 1) for part in rest.split())
    return kind, opts


# The options each kind reads (rXcY: its cells); any other is refused rather than ignored.
OPTIONS = {
    "summary": {"rows", "iterations", "quoted", "sustained", "first"},
    "cells": {"rXcY", "quoted", "sustained", "first"},
    "iterations": {"runs", "cols", "quoted"},
    "seeds": {"runs", "threshold"},
    "points": {"rows", "points"},
    "windows": {"rows", "cols", "quoted"},
    "evals": {"runs", "file", "quoted"},
    "verdicts": {"rows", "seeds", "window", "quoted"},
    "intervals": {"rows", "window"},
    "compare": {"groups", "window"},
    "arms": {"rows"},
    "versus": {"rows", "max"},
    "evaljson": {"rows"},
    "suite": {"rows", "demos", "demos_return"},
    "matrix": {"rows", "rXcY"},
    "target": {"rows", "policy", "quoted"},
    "goal": {"rows"},
    "config": {"file"},
    "answer": {"rows", "prose"},
    "none": set(),
}


def check_table(kind, opts, header, body):
    """(checked cells, mismatches, quoted columns) of one table."""
    if kind not in OPTIONS:
        raise SystemExit(f"unknown kind {kind}")
    unread = sorted(k for k in opts if k not in OPTIONS[kind]
                    and not (re.fullmatch(r"r\d+c\d+", k) and "rXcY" in OPTIONS[kind]))
    if unread:
        raise SystemExit(f"{kind}: option(s) {', '.join(unread)} not read by this kind "
                         f"(it reads {', '.join(sorted(OPTIONS[kind]))})")
    quoted = {int(c) for c in opts.get("quoted", "").split(",") if c}
    checked, wrong = 0, []

    def compare(r, c, computed, words=False):
        """words: the cell is `computed` as text (agrees() reads only numbers)."""
        nonlocal checked
        checked += 1
        same = (body[r][c].strip().strip("`") == computed.strip("`") if words
                else agrees(body[r][c], computed))
        if not same:
            wrong.append((r + 1, header[c], body[r][c], computed))

    if kind == "summary":
        groups = opts["rows"].split(";")
        if len(groups) != len(body):
            raise SystemExit(f"{len(groups)} groups for {len(body)} rows")
        limit = int(opts["iterations"]) if "iterations" in opts else None
        for r, group in enumerate(groups):
            path, _, metric = group.partition("@")
            runs = first_iterations(group_runs(path), limit)
            for c in range(1, len(header)):
                if c + 1 in quoted:
                    continue
                value = column_value(header[c], runs, opts, metric or "eval_dense_return")
                if value is None:
                    raise SystemExit(f"column {c + 1} `{header[c]}`: unknown; name it in quoted=")
                compare(r, c, value)
    elif kind == "iterations":
        runs = {}
        for part in opts["runs"].split(";"):
            name, path = part.split(":", 1)
            runs[name] = read_run(run_file(path))
        specs = opts["cols"].split(";")
        for r, row in enumerate(body):
            n = int(numbers(row[0])[0][0])
            for c, spec in enumerate(specs, start=1):
                if c + 1 in quoted:
                    continue
                what, name = spec.split(":", 1)
                column, _, run = name.partition("@")
                rows = runs[run]
                if what == "samples":
                    compare(r, c, repr(rows[n - 1]["samples"]))
                elif what == "thousands":
                    compare(r, c, f"{rows[n - 1]['samples'] / 1e3!r}k")
                elif what in ("int", "num"):
                    compare(r, c, repr(rows[n - 1][column]))
                elif what == "last5":
                    upto = [x for x in rows[:n] if math.isfinite(x[column])]
                    compare(r, c, f"{rows[n - 1][column]!r} ({statistics.fmean(x[column] for x in upto[-5:])!r})")
                else:
                    raise SystemExit(f"unknown column kind {what}")
    elif kind == "seeds":
        threshold = float(opts["threshold"])
        for r, path in enumerate(opts["runs"].split(";")):
            rows = read_run(run_file(path))
            hit = next((i for i, x in enumerate(rows) if x["eval_dense_return"] >= threshold), None)
            cells = {
                "first ≥": "never" if hit is None else f"{hit + 1} ({rows[hit]['samples']!r})",
                "final": repr(rows[-1]["eval_dense_return"]),
                "best": repr(max(x["eval_dense_return"] for x in rows)),
                "wall": repr(rows[-1]["wall_s"]),
            }
            compare(r, 0, str(r) if "seed" in header[0] else body[r][0])
            for c in range(1, len(header)):
                key = next(k for k in cells if header[c].startswith(k))
                compare(r, c, cells[key])
    elif kind == "points":
        xs = [float(x) for x in opts["points"].split(",")]
        groups = opts["rows"].split(";")
        for r, group in enumerate(groups):
            points = [evaluations(rows) for rows in group_runs(group)]
            for s, p in enumerate(points, start=1):
                compare(r, s, " / ".join(repr(interpolate(p, x)) for x in xs))
            compare(r, len(points) + 1, pm([interpolate(p, xs[-1]) for p in points]))
    elif kind == "windows":
        specs = opts["cols"].split(";")
        for r, group in enumerate(opts["rows"].split(";")):
            runs = group_runs(group)
            for c, spec in enumerate(specs, start=1):
                if c + 1 in quoted:
                    continue
                column, _, span = spec.partition(":")
                a, b = (int(x) for x in span.split("-"))
                means = []
                for rows in runs:
                    values = [x[column] for x in rows[a : b + 1] if math.isfinite(x[column])]
                    if len(values) < b + 1 - a:
                        raise SystemExit(f"{group}: fewer than {b + 1} iterations with {column}")
                    means.append(statistics.fmean(values))
                # One run has no spread over seeds: its cell is the bare mean.
                compare(r, c, pm(means) if len(means) > 1 else repr(means[0]))
    elif kind == "evals":
        for r, path in enumerate(opts["runs"].split(";")):
            text = (ROOT / "docs/results" / path / opts.get("file", "eval-20.txt")).read_text()
            line = next(l for l in text.splitlines() if "dense return" in l)
            fields = {}
            parts = line.split("|")
            for part in parts:
                for name in ("dense return", "x moved", "action RMS", "length"):
                    if name in part:
                        fields[name] = part.split(name, 1)[1].strip()
            # The first part is "<env> return R ± S": the trained task's (sparse) return.
            if " return " in parts[0]:
                fields["sparse return"] = parts[0].split(" return ", 1)[1].strip()
            for c in range(1, len(header)):
                if c + 1 in quoted:
                    continue
                name = next((n for n in fields if n in header[c]), None)
                if name is None:
                    raise SystemExit(f"column {c + 1} `{header[c]}`: unknown; name it in quoted=")
                compare(r, c, fields[name])
    elif kind == "verdicts":
        seeds, window = int(opts["seeds"]), int(opts["window"])
        for r, spec in enumerate(opts["rows"].split(";")):
            group, _, curve = spec.partition(">")
            path, _, metric = curve.partition("@")
            reference = evaluations(read_run(run_file(path)), metric)
            runs = [] if group == "-" else [evaluations(rows) for rows in group_runs(group)]
            for c in range(len(header)):
                x = parse_samples(header[c])
                if x is None or c + 1 in quoted:
                    continue
                values = [v for p in runs if (v := window_at(p, x, window)) is not None]
                checked += 1
                if len(values) < seeds:
                    if re.search(r"ahead|behind|mixed", body[r][c]):
                        wrong.append((r + 1, header[c], body[r][c], f"no verdict: {len(values)} of {seeds} seeds reach it"))
                    continue
                ref = window_at(reference, x, window)
                above = sum(v > ref for v in values)
                word = "ahead" if above == len(values) else "behind" if above == 0 else f"mixed, {above} of {len(values)} above"
                computed = f"{word} ({statistics.fmean(values)!r} vs {ref!r})"
                if body[r][c].split("(")[0].strip() != word or not agrees(body[r][c], computed):
                    wrong.append((r + 1, header[c], body[r][c], computed))
    elif kind == "intervals":
        window = int(opts["window"])
        for r, group in enumerate(opts["rows"].split(";")):
            runs = group_points(group)
            for c in range(2, len(header)):
                m = re.fullmatch(r"(final|at (.+?)(?:, mean of \d+)?): (mean|IQM) \[95% CI\]",
                                 header[c].strip())
                if not m:
                    raise SystemExit(f"intervals: column {header[c]!r} is not `logo summary`'s")
                x = None if m.group(1) == "final" else parse_samples(m.group(2))
                if m.group(1) != "final" and x is None:
                    raise SystemExit(f"intervals: no sample count in column {header[c]!r}")
                values = [p[-1][1] if x is None else window_at(p, x, window) for p in runs]
                values = [v for v in values if v is not None]
                stat = statistics.fmean if m.group(3) == "mean" else iqm
                point = stat(values)
                lo, hi = bootstrap_interval(values, stat)
                checked += 1
                spread = max(values) - min(values)
                if not interval_agrees(body[r][c], point, (lo, hi), 0.05 * spread):
                    wrong.append((r + 1, header[c], body[r][c], f"{point:.0f} [{lo:.0f}, {hi:.0f}]"))
    elif kind == "compare":
        # `logo summary --compare A B`: a row per budget, P(A > B) and the IQM difference
        # A − B, each with its bootstrap interval (checked to 5% of the spread, as above).
        window = int(opts["window"])
        a_runs, b_runs = (group_points(g) for g in opts["groups"].split(";"))
        for r, row in enumerate(body):
            label = row[0].strip()
            m = re.fullmatch(r"final|at (.+?)(?:, mean of \d+)?", label)
            if not m:
                raise SystemExit(f"compare: budget {label!r} is not `logo summary`'s")
            x = None if label == "final" else parse_samples(m.group(1))
            at = lambda runs: [p[-1][1] if x is None else window_at(p, x, window) for p in runs]
            xs, ys = at(a_runs), at(b_runs)
            iqm_diff = lambda u, v: iqm(u) - iqm(v)
            spread = max(xs + ys) - min(xs + ys)
            for c, stat, tolerance in ((2, probability_of_improvement, 0.05), (3, iqm_diff, 0.05 * spread)):
                point = stat(xs, ys)
                lo, hi = bootstrap_two(xs, ys, stat)
                checked += 1
                if not interval_agrees(row[c], point, (lo, hi), tolerance):
                    wrong.append((r + 1, header[c], row[c], f"{point:.2f} [{lo:.2f}, {hi:.2f}]"))
    elif kind == "arms":
        specs = opts["rows"].split(";")
        if len(specs) != len(body):
            raise SystemExit(f"arms: {len(specs)} row specs for {len(body)} rows")
        for r, (spec, row) in enumerate(zip(specs, body)):
            m = re.fullmatch(r"([^>@]+)(?:>([^@]+))?@([\d.]+[kM]?):(\d+)", spec)
            if not m:
                raise SystemExit(f"arms: row spec {spec!r} is not GROUP[>BASE]@BUDGET:W")
            x, window = parse_samples(m.group(3)), int(m.group(4))
            at = lambda group: window_values(group, x, window)  # noqa: E731
            xs = at(m.group(1))
            compare(r, 3, str(len(xs)))
            spread = max(xs) - min(xs)
            cells = [(4, lambda u, v: iqm(u), 0.05 * spread)]
            if m.group(2):
                ys = at(m.group(2))
                spread = max(xs + ys) - min(xs + ys)
                cells += [(5, probability_of_improvement, 0.05),
                          (6, lambda u, v: iqm(u) - iqm(v), 0.05 * spread)]
            else:
                ys = []
                for c in (5, 6):
                    checked += 1
                    if row[c] != "—":
                        wrong.append((r + 1, header[c], row[c], "— (the baseline)"))
            for c, stat, tolerance in cells:
                point = stat(xs, ys)
                lo, hi = (bootstrap_two(xs, ys, stat) if ys else
                          bootstrap_interval(xs, lambda v: stat(v, [])))
                checked += 1
                if not interval_agrees(row[c], point, (lo, hi), tolerance):
                    wrong.append((r + 1, header[c], row[c], f"{point:.2f} [{lo:.2f}, {hi:.2f}]"))
    elif kind == "versus":
        specs = opts["rows"].split(";")
        if len(specs) != len(body):
            raise SystemExit(f"versus: {len(specs)} row specs for {len(body)} rows")
        for r, (spec, row) in enumerate(zip(specs, body)):
            m = re.fullmatch(r"([^>@]+)>([^@]+)@([\d.]+[kM]?):(\d+)", spec)
            if not m:
                raise SystemExit(f"versus: row spec {spec!r} is not GROUP>OTHER@BUDGET:W")
            x, window = parse_samples(m.group(3)), int(m.group(4))
            # max=SAMPLES: every run read up to it, as `logo summary --max-samples`.
            given = opts.get("max")
            limit = math.inf if given is None else x if given == "budget" else parse_samples(given)
            xs, ys = (window_values(g, x, window, limit) for g in (m.group(1), m.group(2)))
            compare(r, 3, str(len(xs)))
            compare(r, 5, str(len(ys)))
            spread = max(xs + ys) - min(xs + ys)
            # The difference's draws serve its interval and the verdict alike.
            differences = bootstrap_two_draws(xs, ys, lambda u, v: iqm(u) - iqm(v))
            cells = [
                (2, lambda u, v: iqm(u), lambda: bootstrap_interval(xs, iqm), 0.05 * spread),
                (4, lambda u, v: iqm(v), lambda: bootstrap_interval(ys, iqm), 0.05 * spread),
                (7, lambda u, v: iqm(u) - iqm(v), lambda: percentile_interval(differences),
                 0.05 * spread),
            ]
            for c, stat, interval, tolerance in cells:
                point, (lo, hi) = stat(xs, ys), interval()
                checked += 1
                if not interval_agrees(row[c], point, (lo, hi), tolerance):
                    wrong.append((r + 1, header[c], row[c], f"{point:.2f} [{lo:.2f}, {hi:.2f}]"))
            # P moves in steps of 1/(pairs): its ends are checked against a band of quantiles.
            draws = bootstrap_two_draws(xs, ys, probability_of_improvement)
            point = probability_of_improvement(xs, ys)
            checked += 1
            if not band_agrees(row[6], point, draws, 0.0):
                lo, hi = percentile_interval(draws)
                wrong.append((r + 1, header[6], row[6], f"{point:.2f} [{lo:.2f}, {hi:.2f}]"))
            # The verdict: the printed interval's, and one the bootstrap gives (verdict()).
            seeds = (len(xs), len(ys))
            checked += 1
            scale = min(iqm(xs), iqm(ys))
            if not verdict_agrees(row[8].strip().split(" (")[0], row[7], differences, seeds, scale):
                wrong.append((r + 1, header[8], row[8],
                              verdict(*percentile_interval(differences), seeds, scale)))
    elif kind == "evaljson":
        columns = {
            "final: return": ("final", "mean_action", "return"),
            "final: dense return": ("final", "mean_action", "dense_return"),
            "final: dense, clipped": ("final", "clipped", "dense_return"),
            "best: return": ("best", "mean_action", "return"),
            "best: dense return": ("best", "mean_action", "dense_return"),
            "final: success": ("final", "mean_action", "success_rate"),
            "best: success": ("best", "mean_action", "success_rate"),
        }
        groups = opts["rows"].split(";")
        if len(groups) != len(body):
            raise SystemExit(f"evaljson: {len(groups)} groups for {len(body)} rows")
        for r, group in enumerate(groups):
            base = ROOT / "docs/results" / group
            docs = [read_json(p) for p in sorted(f for f in (kept_file(d, "eval.json")
                                                             for d in base.glob("seed*/")) if f)]
            if not docs:
                raise SystemExit(f"evaljson: no seed*/eval.json under {base}")
            compare(r, 1, str(len(docs)))
            for c in range(2, len(header)):
                name = header[c].replace(" [95% CI]", "").strip()
                if name not in columns:
                    raise SystemExit(f"evaljson: column {header[c]!r} is not `logo summary`'s")
                policy, acting, key = columns[name]
                values = [d["policies"][policy][acting]["summary"][key] for d in docs]
                if key == "success_rate":
                    compare(r, c, f"{100 * statistics.fmean(values)!r}%")
                elif len(values) == 1:
                    compare(r, c, repr(values[0]))
                else:
                    point = statistics.fmean(values)
                    lo, hi = bootstrap_interval(values, statistics.fmean)
                    checked += 1
                    spread = max(values) - min(values)
                    if not interval_agrees(body[r][c], point, (lo, hi), 0.05 * spread):
                        wrong.append((r + 1, header[c], body[r][c], f"{point:.0f} [{lo:.0f}, {hi:.0f}]"))
    elif kind == "suite":
        intervals = check_suite(opts, header, body, compare, wrong)
        checked += intervals  # after the call: `compare` counts its cells into `checked`
    elif kind == "matrix":
        checked += check_matrix(opts, header, body, wrong)
    elif kind == "answer":
        n, _ = check_answer(opts, header, body, wrong)
        checked += n
    elif kind == "none":
        pass  # a map of the repository, no data: nothing to recompute
    elif kind == "target":
        intervals = check_target(opts, header, body, compare, wrong)
        checked += intervals  # after the call, as for `suite`
    elif kind == "goal":
        groups = opts["rows"].split(";")
        if len(groups) != len(body):
            raise SystemExit(f"goal: {len(groups)} groups for {len(body)} rows")
        seed_number = lambda p: int(re.sub(r"\D", "", p.parent.name) or 0)  # noqa: E731
        for r, group in enumerate(groups):
            files = sorted((f for f in (kept_file(d, "eval.json")
                                        for d in (ROOT / "docs/results" / group).glob("seed*/")) if f),
                           key=seed_number)
            if not files:
                raise SystemExit(f"goal: no seed*/eval.json under {group}")
            docs = [read_json(p) for p in files]
            compare(r, 1, str(len(docs)))
            for c in range(2, len(header)):
                name = header[c].lower()
                policy = "best" if name.startswith("best") else "final"
                episodes = [d["policies"][policy]["mean_action"]["episodes"] for d in docs]
                # An episode of a task that ends only at its goal reached it if it terminated.
                counts = [sum(bool(e["terminated"]) for e in eps) for eps in episodes]
                if "per seed" in name:
                    compare(r, c, ", ".join(map(str, counts)))
                elif "all episodes" in name:
                    compare(r, c, str(sum(k == len(eps) for k, eps in zip(counts, episodes))))
                else:
                    raise SystemExit(f"goal: column {header[c]!r}: expected '... per seed' or '... all episodes'")
    elif kind == "config":
        # Each row's first cell names a key (`[table] key` or `key`); the second holds its
        # value in that TOML file, as TOML writes it (a string with its quotes).
        import tomllib

        config = tomllib.loads((ROOT / opts["file"]).read_text())
        for r, row in enumerate(body):
            m = re.fullmatch(r"`(?:\[(\w+)\] )?(\w+)`", row[0].strip())
            if not m:
                raise SystemExit(f"config: row {r + 1}: expected `[table] key` or `key`, got {row[0]!r}")
            table, key = m.groups()
            value = (config.get(table, {}) if table else config).get(key)
            if value is None:
                raise SystemExit(f"config: {opts['file']} has no {row[0]}")
            words = isinstance(value, (str, bool))
            shown = (f'`"{value}"`' if isinstance(value, str) else
                     str(value).lower() if isinstance(value, bool) else str(value))
            compare(r, 1, shown, words)
    elif kind == "cells":
        for key, spec in opts.items():
            m = re.fullmatch(r"r(\d+)c(\d+)", key)
            if not m:
                continue
            r, c = int(m.group(1)) - 1, int(m.group(2)) - 1
            stat, _, group = spec.partition("@")
            value = column_value(stat.replace("_", " "), group_runs(group), opts)
            if value is None:
                raise SystemExit(f"{key}: unknown statistic {stat}")
            compare(r, c, value)
    else:
        raise SystemExit(f"unknown kind {kind}")
    return checked, wrong, sorted(quoted)


def main():
    docs = [Path(a) for a in sys.argv[1:]] or [
        ROOT / "README.md",
        ROOT / "docs/results.md",
        *sorted((ROOT / "docs/findings").glob("*.md")),
        ROOT / "docs/history.md",
    ]
    failures = cells = count = 0
    for doc in docs:
        f, c, n = check_doc(doc)
        failures, cells, count = failures + f, cells + c, count + n
    print(f"{count} tables, {cells} cells recomputed, {failures} failing")
    return 1 if failures else 0


def check_doc(doc):
    """(failing tables, cells recomputed, tables) of one page."""
    lines = doc.read_text().splitlines()
    failures = cells = 0
    found = tables(lines)
    for comment, header, body, line in found:
        where = f"{doc.name}:{line}"
        if comment is None:
            print(f"{where}: table without a `<!-- check ... -->` comment")
            failures += 1
            continue
        kind, opts = options(comment)
        try:
            checked, wrong, quoted = check_table(kind, opts, header, body)
        except SystemExit as e:
            print(f"{where}: {e}")
            failures += 1
            continue
        except (KeyError, IndexError, ValueError, StopIteration, OSError) as e:
            print(f"{where}: cannot check ({type(e).__name__}: {e})")
            failures += 1
            continue
        if kind == "answer" and "prose" in opts:
            words, limit = prose_words(lines, line), int(opts["prose"])
            checked += 1
            if words > limit:
                wrong.append((0, "prose", f"{words} words", f"at most {limit}"))
        cells += checked
        note = f", quoted columns {quoted}" if quoted else ""
        print(f"{where}: {kind}, {checked} cells{note}: {'ok' if not wrong else 'MISMATCH'}")
        for r, column, document, computed in wrong:
            print(f"    row {r}, `{column}`: document `{document}`, data `{computed}`")
        failures += bool(wrong)
    return failures, cells, len(found)


if __name__ == "__main__":
    sys.exit(main())
