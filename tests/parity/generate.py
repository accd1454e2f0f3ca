#!/usr/bin/env python3
"""Records Gymnasium 1.4.0 + MuJoCo 3.17.0 trajectories: the oracle for logo-envs.

For every env id, from given initial qpos/qvel (LOGO's four tasks: the model's with
noise drawn here; the other seven: the task's own reset) and under given action
sequences (uniform-random in the control range, and saturating beyond it so MuJoCo
clamps), it records observations, dense rewards, sparse rewards (LOGO's rule for its four
tasks, the episode lump for the others; a low distance threshold; the goal kind for
Reacher and Pusher), x positions and the termination/truncation flags, until the episode
ends or for at most 1000 steps (fewer for the wide observations of MAX_STEPS).

The sparse rewards come from LogoSparse below, written from docs/reference.md
independently of the Rust code. The Rust test crates/logo-envs/tests/parity.rs replays
the same initial states and actions and compares.

  generate.py OUT_DIR            write fixtures
  generate.py --check DIR        regenerate in memory and compare with DIR (exit 1 on drift)

Layout: OUT_DIR/<id>.json (manifest) and OUT_DIR/<id>.f64 (little-endian float64; each
trajectory's arrays concatenated in the manifest's order at its offset).
"""
import json
import math
import sys
from pathlib import Path

import gymnasium as gym
import numpy as np

LOGO_IDS = [
    "Hopper-v4", "Hopper-v5", "Walker2d-v4", "Walker2d-v5",
    "HalfCheetah-v4", "HalfCheetah-v5",
    "InvertedDoublePendulum-v4", "InvertedDoublePendulum-v5",
]
# The other seven tasks (Pusher only -v5: Gymnasium 1.4.0 refuses Pusher-v4 under MuJoCo 3).
OTHER_IDS = [
    "Ant-v4", "Ant-v5", "Humanoid-v4", "Humanoid-v5",
    "HumanoidStandup-v4", "HumanoidStandup-v5", "InvertedPendulum-v4", "InvertedPendulum-v5",
    "Pusher-v5", "Reacher-v4", "Reacher-v5", "Swimmer-v4", "Swimmer-v5",
]
ENV_IDS = LOGO_IDS + OTHER_IDS
# LOGO's sparse rules (docs/reference.md): distance threshold, or None = episode lump. The
# tasks LOGO did not use have no LOGO rule; their "sparse_reward" is the episode lump.
SPARSE_THRESHOLD = {"Hopper": 2.0, "Walker2d": 2.0, "HalfCheetah": 20.0, "InvertedDoublePendulum": None}
# The tasks with a target, and the bodies whose distance in the plane the goal kind pays on.
GOAL_BODIES = {"Reacher": ("fingertip", "target"), "Pusher": ("object", "goal")}
# Steps recorded at most, where 1000 steps of a wide observation would bloat the fixtures
# (truncation is covered by the tasks recorded to 1000).
MAX_STEPS = {"Ant": 300, "Humanoid": 300, "HumanoidStandup": 60}
# Per trajectory: the name, the noise scale of the initial state, the action generator.
TRAJECTORIES = ["random", "saturating", "gentle"]
ARRAYS = ["actions", "obs", "reward", "sparse_reward", "sparse_reward_low",
          "x_position", "terminated", "truncated"]


class LogoSparse:
    """+1 on every step with x - x_init > threshold; or the dense return paid at episode end."""

    def __init__(self, threshold):
        self.threshold = threshold

    def start(self, x_init):
        self.x_init = x_init
        self.acc = 0.0

    def reward(self, dense, x, done):
        if self.threshold is not None:
            return 1.0 if x - self.x_init > self.threshold else 0.0
        self.acc += dense
        return self.acc if done else 0.0


def actions_for(kind, rng, low, high, steps):
    if kind == "random":
        return rng.uniform(low, high, size=(steps, low.size))
    if kind == "gentle":  # small actions: the long-lived episodes, with contacts
        return 0.1 * rng.uniform(low, high, size=(steps, low.size))
    # Saturating: +-1.5x the range (MuJoCo clamps; the control cost sees the raw value),
    # the sign of each actuator flipping every 7 + i steps.
    t = np.arange(steps)[:, None]
    period = 7 + np.arange(low.size)[None, :]
    sign = np.where((t // period) % 2 == 0, 1.0, -1.0)
    return 1.5 * np.where(sign > 0, high, low) * np.abs(sign)


def record(env_id, kind, seed):
    env = gym.make(env_id)
    env.reset(seed=seed)
    base = env.unwrapped
    rng = np.random.default_rng(seed)
    task = env_id.split("-")[0]
    if env_id in LOGO_IDS:
        scale = 0.1 if env_id.startswith(("HalfCheetah", "InvertedDoublePendulum")) else 0.005
        qpos0 = base.init_qpos + rng.uniform(-scale, scale, size=base.model.nq)
        qvel0 = base.init_qvel + rng.uniform(-scale, scale, size=base.model.nv)
        base.set_state(qpos0, qvel0)
    else:
        # The task's own reset (Reacher's target and Pusher's object placed as it does).
        qpos0, qvel0 = base.data.qpos.copy(), base.data.qvel.copy()
    low, high = base.model.actuator_ctrlrange.T.astype(np.float64)
    actions = actions_for(kind, rng, low, high, MAX_STEPS.get(task, 1000))
    sparse = LogoSparse(SPARSE_THRESHOLD.get(task))
    sparse.start(float(base.data.qpos[0]))

    goal = GOAL_BODIES.get(task)
    out = {k: [] for k in ARRAYS}
    goal_distances = []
    out["obs"].append(base._get_obs().copy())
    x_init = float(base.data.qpos[0])
    for a in actions:
        obs, reward, terminated, truncated, _ = env.step(a.copy())
        x = float(base.data.qpos[0])
        out["actions"].append(a)
        out["obs"].append(obs.copy())
        out["reward"].append(float(reward))
        out["sparse_reward"].append(sparse.reward(float(reward), x, terminated or truncated))
        out["sparse_reward_low"].append(x)  # replaced below, once the threshold is known
        out["x_position"].append(x)
        if goal:
            a, b = (base.data.body(name).xpos for name in goal)
            goal_distances.append(math.hypot(a[0] - b[0], a[1] - b[1]))
        out["terminated"].append(float(terminated))
        out["truncated"].append(float(truncated))
        if terminated or truncated:
            break
    env.close()
    # A second, low distance threshold that this trajectory does cross (a quarter of its
    # farthest advance), so the +1 branch of the rule is exercised.
    xs = np.asarray(out["x_position"])
    low_threshold = max(float(np.max(xs - x_init)) / 4.0, 1e-4)
    low = LogoSparse(low_threshold)
    low.start(x_init)
    out["sparse_reward_low"] = [low.reward(0.0, x, False) for x in xs]
    meta = {"name": kind, "seed": seed, "steps": len(out["reward"]),
            "qpos0": qpos0.tolist(), "qvel0": qvel0.tolist(),
            "low_threshold": low_threshold}
    if goal:
        # The goal kind (+1 while the distance is below a radius) at a radius halfway
        # between two of this trajectory's distances near their median, so both branches
        # occur and no distance lies on the boundary.
        distinct = sorted(set(goal_distances))
        k = len(distinct) // 2
        radius = (distinct[k - 1] + distinct[k]) / 2
        meta["goal_radius"] = radius
        out["sparse_reward_goal"] = [1.0 if d < radius else 0.0 for d in goal_distances]
    return meta, {k: np.asarray(v, dtype="<f8") for k, v in out.items()}


def build(env_id):
    trajectories, blobs, offset = [], [], 0
    for i, kind in enumerate(TRAJECTORIES):
        meta, arrays = record(env_id, kind, seed=1000 + i)
        meta["arrays"] = {}
        for k in arrays:  # ARRAYS, then the goal kind's column where the task has one
            meta["arrays"][k] = {"offset": offset, "shape": list(arrays[k].shape)}
            offset += arrays[k].size
            blobs.append(arrays[k].ravel())
        trajectories.append(meta)
    manifest = {
        "env_id": env_id,
        "sparse_threshold": SPARSE_THRESHOLD.get(env_id.split("-")[0]),
        "logo_sparse": env_id in LOGO_IDS,
        "generator": f"gymnasium {gym.__version__}, numpy {np.__version__}",
        "trajectories": trajectories,
    }
    return manifest, np.concatenate(blobs).astype("<f8")


def main(argv):
    if len(argv) == 3 and argv[1] == "--check":
        ref_dir, drift = Path(argv[2]), []
        for env_id in ENV_IDS:
            manifest, data = build(env_id)
            ref = json.loads((ref_dir / f"{env_id}.json").read_text())
            ref_data = np.fromfile(ref_dir / f"{env_id}.f64", dtype="<f8")
            steps = [t["steps"] for t in manifest["trajectories"]]
            ref_steps = [t["steps"] for t in ref["trajectories"]]
            if steps != ref_steps or data.shape != ref_data.shape:
                drift.append(f"{env_id}: episode lengths {steps} vs committed {ref_steps}")
            elif not np.allclose(data, ref_data, rtol=0, atol=1e-12):
                worst = np.max(np.abs(data - ref_data))
                drift.append(f"{env_id}: values drifted from the committed fixture (max |diff| {worst:.3g})")
        for d in drift:
            print(f"parity fixtures: DRIFT {d}", file=sys.stderr)
        print(f"parity fixtures: {len(ENV_IDS) - len(drift)} of {len(ENV_IDS)} env ids match the Gymnasium oracle")
        return 1 if drift else 0
    if len(argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    out = Path(argv[1])
    out.mkdir(parents=True, exist_ok=True)
    for env_id in ENV_IDS:
        manifest, data = build(env_id)
        (out / f"{env_id}.json").write_text(json.dumps(manifest, indent=1) + "\n")
        data.tofile(out / f"{env_id}.f64")
        print(env_id, [t["steps"] for t in manifest["trajectories"]])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
