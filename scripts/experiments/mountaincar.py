#!/usr/bin/env python3
"""Why LOGO let go of the demonstrations on a new task: MountainCarContinuous-v0.

A task not in the LOGO paper with a goal (the flag, +100, ending the episode) and an
action cost (0.1·a² per step), 15 demonstrations of a scripted controller (push the way
the car moves: every episode reaches the flag in about 106 steps, return 89.4), 40
iterations of 5,000 samples, as the report that opened the study ran it. Each arm
changes the preset or the old template in one or more settings; every run's folder
keeps metrics.csv, config.toml and eval.json (the final and best policies over 20
fresh episodes; MountainCar ends an episode only at the flag, so an episode that
terminated reached it).

    .venv/bin/python scripts/experiments/mountaincar.py OUT ARM [ARM ...] --seeds 0-4

Finished runs (with eval.json) are skipped. `--list` prints the arms. The tables of
docs/findings/new-tasks.md come from docs/results/new-task-mcc/, made by this script
(`scripts/check_results.py` recomputes them).
"""

import argparse
import sys
from pathlib import Path

import gymnasium as gym
import numpy as np

import logo_rl

ROOT = Path(__file__).resolve().parents[2]
PRESET = ROOT / "configs" / "templates" / "new_task.toml"
TASK = "MountainCarContinuous-v0"
LOW, HIGH = np.array([-1.2, -0.07]), np.array([0.6, 0.07])

# The template before the study (commit 98dab0d): δ_0 0.2, δ_k decaying by α = 0.9 on
# the return, one discriminator step, no normalisation, no KL check, 2,048 evaluation
# steps. Laid over the preset as it is now, so every setting the preset has changed since
# is spelled out (the kept runs' config.toml files hold what each arm ran).
OLD = dict(
    normalise_observations=False, success="terminated", eval_episodes=1,
    improvement={"kl_limit": 1e300},
    guidance={"delta0": 0.2, "alpha": 0.9, "decay_on": "return", "discriminator_steps": 1},
)


def old(**changes):
    """The old template with `changes` laid over it (a dict value merges key by key;
    guidance=None: no guidance step)."""
    out = {k: (dict(v) if isinstance(v, dict) else v) for k, v in OLD.items()}
    for key, value in changes.items():
        if isinstance(value, dict):
            out.setdefault(key, {}).update(value)
        else:
            out[key] = value
    return out


ARMS = {
    # The old template, then each candidate alone.
    "template": old(),
    "kl-limit": old(improvement={"kl_limit": 1.5}),
    "no-decay": old(guidance={"alpha": 1.0}),
    "log-std-1": old(log_std_init=-1.0),
    "clip-actions": old(clip_actions=True),
    "disc-lr-3e-3": old(guidance={"discriminator_lr": 3e-3}),
    "scaled": old(scaled=True),
    "normalised": old(normalise_observations=True),
    "delta0-0.01": old(guidance={"delta0": 0.01}),
    "disc-10": old(guidance={"discriminator_steps": 10}),
    # Candidates together.
    "scaled-delta0-0.01": old(scaled=True, guidance={"delta0": 0.01}),
    "scaled-delta0-0.05": old(scaled=True, guidance={"delta0": 0.05}),
    "scaled-disc-10": old(scaled=True, guidance={"discriminator_steps": 10}),
    "disc-10-delta0-0.01": old(guidance={"discriminator_steps": 10, "delta0": 0.01}),
    "scaled-disc-10-delta0-0.01": old(scaled=True, guidance={"discriminator_steps": 10, "delta0": 0.01}),
    "scaled-disc-50-delta0-0.01": old(scaled=True, guidance={"discriminator_steps": 50, "delta0": 0.01}),
    "normalised-disc-10-delta0-0.01": old(
        normalise_observations=True, guidance={"discriminator_steps": 10, "delta0": 0.01}
    ),
    "normalised-disc-10-delta0-0.01-kl-limit": old(
        normalise_observations=True, eval_episodes=10, improvement={"kl_limit": 1.5},
        guidance={"discriminator_steps": 10, "delta0": 0.01},
    ),
    # The preset as it was then (decaying δ_k on success; it holds δ_k since), and TRPO
    # with the old and the preset's settings (no [guidance]).
    "preset": dict(success="terminated", guidance={"alpha": 0.9, "decay_on": "success"}),
    "trpo": old(guidance=None),
    "trpo-preset": dict(success="terminated", guidance=None),
}


def pump(obs):
    """The scripted demonstrator: push the way the car moves."""
    return np.array([1.0 if obs[1] >= 0 else -1.0])


def scaled_env():
    """A wrapper a user would write: observations scaled to [-1, 1] by their bounds."""
    env = gym.make(TASK)
    space = gym.spaces.Box(-1.0, 1.0, (2,), np.float64)
    return gym.wrappers.TransformObservation(env, lambda o: 2 * (o - LOW) / (HIGH - LOW) - 1, space)


def demos(out: Path, scaled: bool) -> Path:
    path = out / ("demos-scaled" if scaled else "demos")
    if not path.exists():
        # The controller reads the sign of the velocity, which scaling keeps.
        logo_rl.record(scaled_env if scaled else TASK, pump, 15, path, seed=0)
    return path


def train(out: Path, arm: str, seed: int) -> None:
    run_dir = out / arm / f"seed{seed}"
    if (run_dir / "eval.json").is_file():
        return
    settings = dict(ARMS[arm])
    scaled = settings.pop("scaled", False)
    guidance = settings.pop("guidance", {})
    common = dict(
        env=scaled_env if scaled else TASK, out=run_dir, seed=seed, iterations=40,
        samples_per_iter=5000, progress=False, tensorboard=False,
    )
    if guidance is None:  # plain TRPO: the preset's settings without its [guidance]
        config = {k: v for k, v in _preset_table().items() if k != "guidance"}
        config["env"] = "SparseHopper-v4"  # replaced by env=
        logo_rl.train(config, **common, **settings)
    else:
        logo_rl.train(PRESET, demos=demos(out, scaled), guidance=guidance, **common, **settings)
    reached = sum(e["terminated"] for e in logo_rl.Run(run_dir).eval["policies"]["final"]["mean_action"]["episodes"])
    print(f"{arm} seed {seed}: the final policy reached the flag in {reached} of 20 episodes", flush=True)


def _preset_table() -> dict:
    try:
        import tomllib
    except ModuleNotFoundError:  # Python 3.10
        import tomli as tomllib
    return tomllib.loads(PRESET.read_text())


def seeds(text: str) -> list[int]:
    lo, _, hi = text.partition("-")
    return list(range(int(lo), int(hi or lo) + 1))


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("out", type=Path, nargs="?")
    p.add_argument("arms", nargs="*")
    p.add_argument("--seeds", type=seeds, default=seeds("0-4"))
    p.add_argument("--list", action="store_true")
    args = p.parse_args()
    if args.list or args.out is None:
        for name, settings in ARMS.items():
            print(f"{name}: {settings}")
        return
    unknown = [a for a in args.arms if a not in ARMS]
    if unknown or not args.arms:
        sys.exit(f"arms {unknown or '(none)'}: expected some of {', '.join(ARMS)}")
    for arm in args.arms:
        for seed in args.seeds:
            train(args.out, arm, seed)


if __name__ == "__main__":
    main()
