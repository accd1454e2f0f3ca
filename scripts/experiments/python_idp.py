"""LOGO from Python on Gymnasium's own InvertedDoublePendulum-v4 (Python physics, Gymnasium's
reset noise) made sparse by logo_rl.SparseReward("delayed"), with the project's IDP
demonstrations (the LOGO paper's), seeds 0-4, 200k samples each (issue 39's check:
an evaluation return >= 9000 within 200k samples on at least 4 of the 5 seeds).

    .venv/bin/python scripts/experiments/python_idp.py [OUT]   # default runs/python-idp

Each run is configs/logo/inverted_double_pendulum.toml with env= the Python env; a run
already done is read back, not trained again. Prints one line per seed and the count."""

import sys
import warnings
from pathlib import Path

import gymnasium as gym

import logo_rl

warnings.filterwarnings("ignore")
ROOT = Path(__file__).resolve().parents[2]
CONFIG = ROOT / "configs" / "logo" / "inverted_double_pendulum.toml"
SEEDS = range(5)
TARGET = 9000.0


def sparse_idp():
    return logo_rl.SparseReward(gym.make("InvertedDoublePendulum-v4"), "delayed")


def main() -> None:
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "runs" / "python-idp"
    reached = 0
    for seed in SEEDS:
        folder = out / f"seed{seed}"
        if (folder / "eval.json").is_file():
            run = logo_rl.Run(folder)
        else:
            run = logo_rl.train(CONFIG, env=sparse_idp, seed=seed, out=folder, progress=False)
        m = run.metrics
        evals, samples = list(m["eval_dense_return"]), list(m["samples"])
        first = next((s for e, s in zip(evals, samples) if e >= TARGET), None)
        reached += first is not None
        best = max(evals)
        print(
            f"seed {seed}: best evaluation {best:.1f}, first >= {TARGET:.0f} at "
            f"{'-' if first is None else f'{first:,} samples'}, "
            f"{samples[-1]:,} samples, wall {list(m['wall_s'])[-1]:.0f} s",
            flush=True,
        )
    print(f"{reached} of {len(SEEDS)} seeds reach {TARGET:.0f} within 200k samples")


if __name__ == "__main__":
    main()
