"""logo_rl.compare at toy scale: two methods, two seeds, two iterations."""

import csv

import numpy as np
import pytest

import logo_rl
from conftest import ROOT

TINY = {
    "env": "SparseInvertedDoublePendulum-v4",
    "iterations": 2,
    "samples_per_iter": 300,
    "policy_hidden": [16, 16],
    "eval_steps": 100,
    "critic": {"hidden": [16, 16], "fit": {"method": "lbfgs", "iterations": 3}},
    "guidance": {
        "demos": str(ROOT / "data/logo/inverted_double_pendulum"),
        "delta0": 0.2,
        "alpha": 0.9,
        "warmup": 0,
    },
}


def last_return(run_dir):
    with open(run_dir / "metrics.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    return float(rows[-1]["eval_dense_return"]), float(rows[-1]["samples"])


def at_budget(run_dir, key, budget):
    """The run's `key` at `budget` samples, linear between rows."""
    with open(run_dir / "metrics.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    x = [float(r["samples"]) for r in rows]
    return float(np.interp(budget, x, [float(r[key]) for r in rows]))


def column(table, key):
    return list(table[key])


def test_compare_trains_each_method_once_and_answers(tmp_path):
    out = tmp_path / "cmp"
    table = logo_rl.compare(TINY, algorithms=("logo", "trpo"), seeds=2, out=out, reps=200,
                            progress=False)
    assert column(table, "method") == ["logo", "trpo"]
    assert column(table, "seeds") == [2, 2]
    assert (out / "configs" / "trpo.toml").is_file()
    for method, returns in zip(column(table, "method"), column(table, "returns")):
        for seed, value in enumerate(returns):
            last, samples = last_return(out / method / f"seed{seed}")
            # At the budget (600 samples), between the last two evaluations.
            assert samples >= 600
            assert np.isfinite(value)
        assert min(returns) <= column(table, "iqm")[column(table, "method").index(method)]
    p = column(table, "p_logo_better")[1]
    assert 0.0 <= p <= 1.0
    # Again: the runs are read, not trained again.
    stamp = (out / "logo" / "seed0" / "metrics.csv").stat().st_mtime_ns
    again = logo_rl.compare(TINY, algorithms=("logo", "trpo"), seeds=2, out=out, reps=200,
                            progress=False)
    assert (out / "logo" / "seed0" / "metrics.csv").stat().st_mtime_ns == stamp
    assert column(again, "iqm") == column(table, "iqm")
    # The same runs read by the sparse task's own return.
    sparse = logo_rl.compare(TINY, algorithms=("logo", "trpo"), seeds=2, out=out, reps=200,
                             metric="train_sparse_return", progress=False)
    for method, returns in zip(column(sparse, "method"), column(sparse, "returns")):
        for seed, value in enumerate(returns):
            run = out / method / f"seed{seed}"
            assert value == pytest.approx(at_budget(run, "train_sparse_return", 600))
            assert value != pytest.approx(at_budget(run, "eval_dense_return", 600))


def test_compare_misuse_is_a_python_error(tmp_path):
    with pytest.raises(ValueError, match="sac"):
        logo_rl.compare(TINY, algorithms=("logo", "sac"), out=tmp_path)
    with pytest.raises(ValueError, match="seeds"):
        logo_rl.compare(TINY, seeds=0, out=tmp_path)
    # A column metrics.csv does not have: refused before any run is trained.
    with pytest.raises(ValueError, match="metric='sparse_return'.*train_sparse_return"):
        logo_rl.compare(TINY, metric="sparse_return", out=tmp_path / "none")
    assert not (tmp_path / "none").exists()
    trpo = {k: v for k, v in TINY.items() if k != "guidance"}
    with pytest.raises(ValueError, match="LOGO config"):
        logo_rl.compare(trpo, algorithms=("trpo",), out=tmp_path)
