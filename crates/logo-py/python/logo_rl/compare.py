"""``logo_rl.compare``: ``logo compare`` from Python: every method made from one LOGO
config, each seed trained in this process, and the answer as a table."""

from __future__ import annotations

import csv
import json
import math
import os
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np

from ._errors import LogoValueError
from . import _logo_rl
from .run import _plain, train
from .presets import preset_path
from .stats import interval, interval_two, iqm, probability_of_improvement

# The methods logo compare makes, as the table of methods lists them (logo first).
METHODS = tuple(name for name, _, _, comparable in _logo_rl.methods() if comparable)


def compare(
    config: str | os.PathLike | Mapping[str, Any],
    *,
    algorithms: Sequence[str] = METHODS,
    seeds: Sequence[int] | int = 5,
    samples: float | None = None,
    out: str | os.PathLike | None = None,
    reps: int = 20_000,
    metric: str = "eval_dense_return",
    engine: str | None = None,
    backend: str | None = None,
    dtype: str | None = None,
    progress: bool = True,
):
    """Trains each of ``algorithms`` on ``seeds`` from one LOGO ``config`` (a preset's
    name, a TOML file or a dict), as ``logo compare`` does, and returns one row per
    method: its seeds' returns at the budget, their interquartile mean (IQM) with a 95%
    bootstrap interval, and P(LOGO > method) with its interval.

    Each method is the config made into it by its own keys alone (``trpo`` drops
    ``[guidance]``, ``bc-trpo`` clones the demonstrations first, ``gail`` and ``pofd``
    keep the discriminator without the guidance step, ``dapg`` clones and then takes
    natural-gradient steps with the demonstrations as weighted rows: docs/algorithms.md). Runs go to
    ``out/<method>/seed<N>`` (default ``runs/compare-<config name>``); a finished run is
    read, not trained again, and an interrupted one is resumed. ``samples``: the budget
    per run (iterations = ⌈samples / samples_per_iter⌉), default the config's.
    ``metric``: the metrics.csv column read at the budget, the mean action's dense
    evaluation by default (the LOGO paper's Figure 1), or e.g. ``"train_sparse_return"``
    (the sampled episodes' sparse return: the sparse task itself) or ``"eval_success"``.

    Returns a pandas DataFrame where pandas is installed, else a dict of columns.
    """
    algorithms = list(algorithms)
    unknown = [a for a in algorithms if a not in METHODS]
    if unknown or not algorithms:
        raise LogoValueError(f"algorithms={algorithms!r}: expected some of {', '.join(METHODS)}")
    seed_list = list(range(seeds)) if isinstance(seeds, int) else list(seeds)
    if not seed_list or not all(isinstance(s, int) and s >= 0 for s in seed_list):
        raise LogoValueError(f"seeds={seeds!r}: expected a count or a list of seeds ≥ 0")
    if not (isinstance(reps, int) and reps >= 1):
        raise LogoValueError(f"reps={reps!r}: expected an integer ≥ 1")
    columns = _logo_rl.metric_columns()
    if metric not in columns:
        raise LogoValueError(f"metric={metric!r}: not a numeric column of metrics.csv; "
                         f"expected one of {', '.join(columns)}")
    path, table, name = _config_arg(config)
    out = Path(out) if out is not None else Path("runs") / f"compare-{name}"
    (out / "configs").mkdir(parents=True, exist_ok=True)
    budget = None
    for method in algorithms:
        text = _logo_rl.configure(
            name=method,
            config=path,
            table_json=json.dumps(table, default=_plain),
            base=os.getcwd(),
        )
        made = out / "configs" / f"{method}.toml"
        made.write_text(f"# {method}, made by logo_rl.compare\n{text}")
        per_iter = _value(text, "samples_per_iter")
        iterations = _value(text, "iterations")
        if samples is not None:
            iterations = math.ceil(samples / per_iter)
        budget = iterations * per_iter
        for seed in seed_list:
            _train_once(made, out / method / f"seed{seed}", seed, iterations,
                        dict(engine=engine, backend=backend, dtype=dtype, progress=progress))
    return _answer(out, algorithms, seed_list, budget, reps, metric)


def _config_arg(config):
    """(file path or None, the dict's keys, a name for the folder)."""
    if isinstance(config, Mapping):
        return None, dict(config), "dict"
    config = os.fspath(config)
    if not os.path.exists(config) and not config.endswith(".toml"):
        config = preset_path(config)
    return config, {}, Path(config).stem


def _value(toml_text: str, key: str) -> int:
    for line in toml_text.splitlines():
        if line.startswith(f"{key} = "):
            return int(line.split("=", 1)[1])
    raise LogoValueError(f"the made config has no {key}")


def _train_once(config: Path, run_dir: Path, seed: int, iterations: int, common: dict) -> None:
    """Trains the run unless it has done `iterations`; resumes (extends) it where a
    checkpoint is."""
    if (run_dir / "eval.json").is_file() and len(_metrics(run_dir)) >= iterations:
        return
    if (run_dir / "checkpoint.safetensors").is_file():
        train(resume=run_dir, iterations=iterations, **common)
    else:
        train(config, seed=seed, iterations=iterations, out=run_dir, **common)


def _metrics(run_dir: Path) -> list[dict]:
    """The run's metrics.csv rows."""
    with open(run_dir / "metrics.csv", newline="") as f:
        return list(csv.DictReader(f))


def _value_at(run_dir: Path, budget: float, metric: str) -> float:
    """The run's `metric` at `budget` samples, linear between the rows that have it."""
    rows = _metrics(run_dir)
    x = np.array([float(r["samples"]) for r in rows])
    if not rows or x[-1] < budget:
        raise LogoValueError(f"{run_dir}: the run stops before {budget:.0f} samples")
    y = np.array([float(r[metric]) for r in rows])
    keep = ~np.isnan(y)
    return float(np.interp(budget, x[keep], y[keep]))


def _answer(out: Path, algorithms, seeds, budget, reps, metric):
    rng = np.random.default_rng(0)
    returns = {m: np.array([_value_at(out / m / f"seed{s}", budget, metric) for s in seeds])
               for m in algorithms}
    rows = []
    for m in algorithms:
        x = returns[m]
        lo, hi = interval(x, iqm, reps, rng)
        row = {"method": m, "seeds": len(x), "samples": budget,
               "returns": x.tolist(), "iqm": iqm(x), "iqm_lo": lo, "iqm_hi": hi}
        if "logo" in returns and m != "logo":
            y = returns["logo"]
            p_lo, p_hi = interval_two(y, x, probability_of_improvement, reps, rng)
            row.update(p_logo_better=probability_of_improvement(y, x), p_lo=p_lo, p_hi=p_hi)
        rows.append(row)
    try:
        import pandas
    except ImportError:
        keys = list(dict.fromkeys(key for row in rows for key in row))
        return {key: [row.get(key) for row in rows] for key in keys}
    return pandas.DataFrame(rows)
