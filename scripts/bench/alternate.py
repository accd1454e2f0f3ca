#!/usr/bin/env python3
"""Per-iteration wall time of `logo train` variants, alternated (A/B/C, A/B/C, ...) so the
VM's drift between minutes falls on every variant alike; prints medians per phase as a
markdown table (the form docs/benchmarks.md records).

Each variant is NAME=ARGS, the arguments of `logo train` (without --out/--iterations);
ARGS may start with @BINARY to use another build (e.g. one with --features wgpu):

  scripts/bench/alternate.py --iterations 3 --skip 1 --rounds 3 \
    'f64=--config configs/logo/hopper.toml' \
    'f32=--config configs/logo/hopper.toml --dtype f32'

The first `--skip` iterations of each run (warm-up: page faults, shader compilation) are
left out; the rest are averaged per run, and the table shows the median over rounds.
"total" is wall time per iteration; the critic fits run beside the policy steps, so the
phases add up to more than it.

With --physics ENV_ID, each round first measures the single-thread raw mj_step rate of
that env (`logo bench envs`), and the table adds each variant's iteration ÷ physics floor
(SAMPLES env steps at that rate, spread over THREADS cores), taken within each round
and then the median over rounds:

  scripts/bench/alternate.py --iterations 5 --skip 1 --rounds 3 \
    --physics Hopper-v4 --samples 20000 --threads 2 \
    'before=@/tmp/logo-before --config configs/logo/hopper.toml' \
    'after=--config configs/logo/hopper.toml'
"""

import argparse
import csv
import json
import os
import shlex
import statistics
import subprocess
import sys
import tempfile

PHASES = [
    ("t_sampling", "sampling"),
    ("t_advantages", "advantages"),
    ("t_critics", "critic fits"),
    ("t_policy_step", "improvement"),
    ("t_guidance", "guidance"),
    ("t_discriminator", "discriminator"),
    ("t_evaluation", "evaluation"),
]


def run_once(binary, args, iterations, out):
    command = [binary, "train", *args, "--iterations", str(iterations), "--out", out]
    done = subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if done.returncode != 0:
        sys.exit(f"{shlex.join(command)} failed:\n{done.stderr.strip()}")
    with open(os.path.join(out, "metrics.csv"), newline="") as f:
        return list(csv.DictReader(f))


def physics_rate(binary, env_id):
    """The single-thread raw mj_step rate of `env_id`, in env steps/s."""
    command = [binary, "bench", "envs", "--envs", env_id, "--json", "--repeats", "3"]
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"{shlex.join(command)} failed:\n{done.stderr.strip()}")
    return json.loads(done.stdout)["envs"][0]["raw_env_steps_per_s"]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("variants", nargs="+", help="NAME=ARGS")
    parser.add_argument("--logo", default="target/release/logo")
    parser.add_argument("--iterations", type=int, default=2)
    parser.add_argument("--skip", type=int, default=1)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--physics", help="env id whose raw mj_step rate gives the physics floor")
    parser.add_argument("--samples", type=int, default=20000, help="env steps per iteration (--physics)")
    parser.add_argument("--threads", type=int, default=2, help="cores the floor is spread over (--physics)")
    a = parser.parse_args()
    if a.skip >= a.iterations:
        sys.exit("--skip must leave at least one iteration")
    variants = []
    for spec in a.variants:
        name, sep, rest = spec.partition("=")
        if not sep or not name:
            sys.exit(f"variant {spec!r}: expected NAME=ARGS")
        args = shlex.split(rest)
        binary = a.logo
        if args and args[0].startswith("@"):
            binary = args.pop(0)[1:]
        variants.append((name, binary, args))

    per_run = {name: [] for name, _, _ in variants}
    with tempfile.TemporaryDirectory(prefix="logo-bench-") as scratch:
        for round_ in range(a.rounds):
            floor = None
            if a.physics:
                raw = physics_rate(a.logo, a.physics)
                floor = a.samples / raw / a.threads
                print(f"round {round_ + 1}: raw {raw:.0f} env steps/s, floor {floor:.3f} s", file=sys.stderr)
            for name, binary, args in variants:
                out = os.path.join(scratch, f"{name}-{round_}")
                rows = run_once(binary, args, a.iterations, out)
                kept = rows[a.skip :]
                phases = {key: statistics.mean(float(r[key]) for r in kept) for key, _ in PHASES}
                # Wall time between the ends of consecutive iterations (the critic fits
                # run beside the policy steps, so the phases do not add up to it).
                # (From the run's start for the first iteration when nothing is skipped.)
                ends = [0.0] + [float(r["wall_s"]) for r in rows]
                walls = [ends[i + 1] - ends[i] for i in range(a.skip, len(rows))]
                phases["total"] = statistics.mean(walls)
                if floor:
                    phases["ratio"] = phases["total"] / floor
                per_run[name].append(phases)
                print(f"round {round_ + 1} {name}: {phases['total']:.2f} s/iteration", file=sys.stderr)

    keys = [("total", "**wall per iteration**")] + PHASES
    print("| variant | " + " | ".join(label for _, label in keys) + " | vs first |")
    print("|" + " --- |" * (len(keys) + 2))
    first = None
    for name, _, _ in variants:
        med = {key: statistics.median(r[key] for r in per_run[name]) for key, _ in keys}
        first = first or med["total"]
        rounds = " / ".join(f"{r['total']:.2f}" for r in per_run[name])
        cells = [f"**{med['total']:.2f}** ({rounds})"] + [f"{med[k]:.2f}" for k, _ in PHASES]
        line = f"| {name} | " + " | ".join(cells) + f" | {first / med['total']:.2f}× |"
        if a.physics:
            ratios = [r["ratio"] for r in per_run[name]]
            line += f" ÷ physics floor {statistics.median(ratios):.2f} ({' / '.join(f'{x:.2f}' for x in ratios)}) |"
        print(line)


if __name__ == "__main__":
    main()
