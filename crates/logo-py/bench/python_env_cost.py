"""What stepping a Python env from the Rust sampler costs: LOGO on sparse Hopper with the
Rust env (SparseHopper-v4) against the same config on Gymnasium's own Python Hopper-v4
made sparse by logo_rl.SparseReward (LOGO's rule, 2 m), alternated, and Gymnasium's
Hopper stepped alone from Python for the env's own share.

    .venv/bin/python crates/logo-py/bench/python_env_cost.py [--iterations 3] [--repeats 2]

Prints per-iteration wall time and sampling time (metrics.csv's wall_s and t_sampling,
the first iteration left out), and the extra seconds per env step."""

import argparse
import statistics
import tempfile
import time
import warnings
from pathlib import Path

import gymnasium as gym
import numpy as np

import logo_rl

warnings.filterwarnings("ignore")
ROOT = Path(__file__).resolve().parents[3]
CONFIG = ROOT / "configs" / "logo" / "hopper.toml"


def sparse_hopper():
    return logo_rl.SparseReward(gym.make("Hopper-v4"), "distance", threshold=2.0)


def per_iteration(run) -> tuple[float, float, float]:
    m = run.metrics
    wall = np.diff(np.asarray(m["wall_s"], dtype=float))  # iterations 2.. (1 has start-up)
    samples = np.diff(np.asarray(m["samples"], dtype=float))
    return float(np.median(wall)), float(np.median(m["t_sampling"][1:])), float(np.median(samples))


def gymnasium_alone(steps: int = 20000) -> float:
    env, rng = gym.make("Hopper-v4"), np.random.default_rng(0)
    env.reset(seed=0)
    actions = rng.uniform(-1, 1, (steps, 3))
    start = time.perf_counter()
    for a in actions:
        _, _, term, trunc, _ = env.step(a)
        if term or trunc:
            env.reset()
    return (time.perf_counter() - start) / steps


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--iterations", type=int, default=3)
    parser.add_argument("--repeats", type=int, default=2)
    args = parser.parse_args()
    results = {"Rust SparseHopper-v4": [], "Python Hopper-v4 + SparseReward": []}
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(args.repeats):
            common = dict(seed=0, iterations=args.iterations, progress=False, tensorboard=False)
            run = logo_rl.train(CONFIG, out=Path(tmp) / f"rust{r}", **common)
            results["Rust SparseHopper-v4"].append(per_iteration(run))
            run = logo_rl.train(
                CONFIG, env=sparse_hopper, demos=ROOT / "data" / "logo" / "hopper",
                out=Path(tmp) / f"python{r}", **common,
            )
            results["Python Hopper-v4 + SparseReward"].append(per_iteration(run))
    alone = gymnasium_alone()
    print(f"LOGO on sparse Hopper, {args.iterations} iterations x {args.repeats} repeats, medians\n")
    print("| env | s per iteration | sampling s per iteration | samples per iteration |")
    print("| --- | --- | --- | --- |")
    medians = {}
    for name, rows in results.items():
        wall, sampling, samples = (statistics.median(col) for col in zip(*rows))
        medians[name] = (wall, sampling, samples)
        print(f"| {name} | {wall:.2f} | {sampling:.2f} | {samples:,.0f} |")
    (w_rust, s_rust, n), (w_py, s_py, _) = medians.values()
    print(f"\nextra per env step: {1e6 * (s_py - s_rust) / n:.1f} µs of sampling; "
          f"Gymnasium's Hopper-v4 stepped alone from Python: {1e6 * alone:.1f} µs per step; "
          f"iteration time x{w_py / w_rust:.2f}")


if __name__ == "__main__":
    main()
