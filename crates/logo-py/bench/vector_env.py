"""Steps/s of LogoVectorEnv (Rust threads, GIL released) against Gymnasium's SyncVectorEnv
and AsyncVectorEnv over the same task, each in Gymnasium's same-step autoreset mode.

    .venv/bin/python crates/logo-py/bench/vector_env.py [--env Hopper-v4] [--copies 8]

Random actions drawn beforehand; every method steps `--steps` vector steps after a reset,
repeated `--repeats` times in alternation (A/B/C/A/B/C...); prints the median env steps/s
of each as a markdown table."""

import argparse
import os
import statistics
import time
import warnings

import gymnasium as gym
import numpy as np
from gymnasium.vector import AsyncVectorEnv, AutoresetMode, SyncVectorEnv

import logo_rl
from logo_rl.vector import LogoVectorEnv

warnings.filterwarnings("ignore")


def steps_per_second(venv, actions) -> float:
    venv.reset(seed=0)
    start = time.perf_counter()
    for a in actions:
        venv.step(a)
    return actions.shape[0] * actions.shape[1] / (time.perf_counter() - start)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--env", default="Hopper-v4")
    parser.add_argument("--copies", type=int, default=8)
    parser.add_argument("--steps", type=int, default=2000)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    n = args.copies
    make = lambda: gym.make(args.env)  # noqa: E731
    methods = {
        f"logo_rl LogoVectorEnv, 1 thread": lambda: LogoVectorEnv(args.env, n, threads=1),
        f"logo_rl LogoVectorEnv, {os.cpu_count()} threads": lambda: LogoVectorEnv(args.env, n),
        "gymnasium SyncVectorEnv": lambda: SyncVectorEnv(
            [make] * n, autoreset_mode=AutoresetMode.SAME_STEP
        ),
        f"gymnasium AsyncVectorEnv ({n} processes)": lambda: AsyncVectorEnv(
            [make] * n, autoreset_mode=AutoresetMode.SAME_STEP
        ),
    }
    envs = {name: build() for name, build in methods.items()}
    act_dim = gym.make(args.env).action_space.shape[0]
    actions = np.random.default_rng(0).uniform(-1, 1, (args.steps, n, act_dim))
    results = {name: [] for name in envs}
    for _ in range(args.repeats):
        for name, venv in envs.items():
            results[name].append(steps_per_second(venv, actions))
    for venv in envs.values():
        venv.close()
    base = statistics.median(results["gymnasium SyncVectorEnv"])
    print(f"{args.env}, {n} copies, {args.steps} vector steps, median of {args.repeats}, "
          f"{os.cpu_count()} CPUs (logo_rl {logo_rl.__version__})\n")
    print("| vector env | env steps/s | vs SyncVectorEnv |")
    print("| --- | --- | --- |")
    for name, values in results.items():
        median = statistics.median(values)
        print(f"| {name} | {median:,.0f} | {median / base:.2f}× |")


if __name__ == "__main__":
    main()
