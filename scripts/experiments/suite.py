#!/usr/bin/env python3
"""The suite of sparse tasks not in the LOGO paper: each task's demonstrations, success
rule and sample budget, fixed here before any run (docs/findings/new-tasks.md).

    .venv/bin/python scripts/experiments/suite.py demos OUT [TASK ...] [--episodes N]

records each task's demonstrations with its scripted demonstrator into OUT/<task>/demos
(a Minari dataset folder) and prints, over the same number of episodes from the same
initial states, how often the demonstrator, uniform random actions and the zero action
reach the goal and what they earn: a task is sparse enough when random actions do not
find its goal.

    .venv/bin/python scripts/experiments/suite.py run OUT [TASK ...] [--seeds 0..5] [--arms ARMS]

trains, on each task of logo-rl's envs, LOGO with the new-task preset and TRPO (the same
config without its guidance) for the task's budget with `logo sweep` (finished runs are
skipped, interrupted ones resume), and behaviour cloning (`logo bc`, which evaluates its
policy), all from the demonstrations in data/suite/<task>/demos (--arms: only these; a
candidate preset, CANDIDATES below, and the seed's Figure 1 baselines, BASELINES below,
run only when named there). `list` prints the tasks.

    .venv/bin/python scripts/experiments/suite.py report OUT [TASK ...] [--keep DOCS] [--reference ARM]

prints each task's table (the final policies' returns as IQM with 95% bootstrap intervals,
how often each seed's final policy reached the goal, the target against the
demonstrations, P(LOGO > method)) with the check comment scripts/check_results.py reads;
--keep copies the finished runs' files into DOCS/<task>/<method>/seed<N> (metrics,
config, eval.json; BC's policy.eval.json and log) for the results page, and draws LOGO's
and TRPO's training curves into DOCS/<task>.png.
"""

import argparse
import gzip
import json
import os
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np

import logo_rl
from logo_rl.stats import interval, interval_two, iqm, probability_of_improvement
from suite_arms import ARM_NAMES, DEMONSTRATED

ROOT = Path(__file__).resolve().parents[2]
PRESET = ROOT / "configs" / "templates" / "new_task.toml"
LOGO = os.environ.get("LOGO", str(ROOT / "target" / "release" / "logo"))
# The environment every `logo` subprocess runs in: MuJoCo's library from the checkout.
LOGO_ENVIRONMENT = dict(os.environ, LD_LIBRARY_PATH=str(ROOT / "third_party" / "mujoco" / "lib"))

# Reacher's two links (MJCF: the second body 0.1 from the first, the fingertip 0.11
# further), for the demonstrator's inverse kinematics.
REACHER_LINKS = (0.1, 0.11)


def reacher_controller(kp=1.0, kd=0.05):
    """Joint-space PD towards the elbow-up inverse-kinematics solution for the target.
    Observation (Reacher-v5): cos q, sin q, target xy, q̇, fingertip − target xy."""
    l1, l2 = REACHER_LINKS

    def act(obs):
        q = np.arctan2(obs[2:4], obs[0:2])
        tx, ty = obs[4], obs[5]
        cos_elbow = np.clip((tx * tx + ty * ty - l1 * l1 - l2 * l2) / (2 * l1 * l2), -1, 1)
        elbow = np.arccos(cos_elbow)
        shoulder = np.arctan2(ty, tx) - np.arctan2(l2 * np.sin(elbow), l1 + l2 * np.cos(elbow))
        error = np.array([shoulder, elbow]) - q
        error = (error + np.pi) % (2 * np.pi) - np.pi
        return np.clip(kp * error - kd * obs[6:8], -1.0, 1.0)

    return act


def trained(checkpoint):
    """A policy trained here, acting with sampled actions (as its demonstrations were
    recorded)."""
    rng = np.random.default_rng(0)
    policy = []

    def act(obs):
        if not policy:
            policy.append(logo_rl.load(ROOT / checkpoint))
        return policy[0].predict(obs, deterministic=False, rng=rng)

    return act


class FixedCells:
    """PointMaze with its start and goal cells fixed far apart (random ones are often
    next to each other, where random actions find the goal)."""

    RESET, GOAL = (1, 1), (6, 6)

    @staticmethod
    def make():
        import gymnasium as gym

        try:
            import gymnasium_robotics
        except ImportError:
            raise SystemExit("the maze task needs Gymnasium-Robotics, which setup.sh does not "
                             "install: .venv/bin/pip install gymnasium-robotics==1.4.0")
        gym.register_envs(gymnasium_robotics)

        class Fixed(gym.Wrapper):
            def reset(self, *, seed=None, options=None):
                cells = {"reset_cell": np.array(FixedCells.RESET),
                         "goal_cell": np.array(FixedCells.GOAL)}
                return self.env.reset(seed=seed, options=cells)

        return gym.wrappers.FlattenObservation(Fixed(gym.make("PointMaze_Medium-v3")))


def point_maze_medium():
    """PointMaze_Medium-v3 from cell (1, 1) to cell (6, 6), observations flattened."""
    return FixedCells.make()


def maze_controller(kp=10.0, kd=1.0):
    """Towards the next cell centre of the shortest grid route to the goal (breadth-first
    over the maze map), then to the goal itself; a PD law on the point's position."""
    from collections import deque

    env = point_maze_medium()
    maze = env.unwrapped.maze
    grid = np.array(maze.maze_map)

    def cell(xy):
        return tuple(int(v) for v in maze.cell_xy_to_rowcol(np.asarray(xy)))

    def route(start, goal):
        before, queue = {start: None}, deque([start])
        while queue:
            here = queue.popleft()
            for dr, dc in ((1, 0), (-1, 0), (0, 1), (0, -1)):
                there = (here[0] + dr, here[1] + dc)
                if grid[there] == 0 and there not in before:
                    before[there] = here
                    queue.append(there)
        path = [goal]
        while before.get(path[-1]) is not None:
            path.append(before[path[-1]])
        return path[::-1]

    def act(obs):
        # Flattened in key order: achieved_goal, desired_goal, observation (x, y, ẋ, ẏ).
        position, goal, velocity = obs[4:6], obs[2:4], obs[6:8]
        path = route(cell(position), cell(goal))
        target = goal if len(path) <= 2 else maze.cell_rowcol_to_xy(np.array(path[1]))
        return np.clip(kp * (target - position) - kd * velocity, -1.0, 1.0)

    return act


def mountain_car_controller(obs):
    """Push the way the car moves (every episode reaches the flag)."""
    return [1.0 if obs[1] >= 0 else -1.0]


def degraded(make_controller, gain, sigma, seed=0):
    """A worse demonstrator made from a scripted one: its action scaled by GAIN, plus
    Gaussian noise of standard deviation SIGMA, clipped to [-1, 1] (every suite task's
    action range). The gain makes the demonstrations sub-optimal in what a clone can learn
    (their mean action is the scaled-down controller's), the noise spreads the outcomes
    between episodes. A maker: each call starts the noise's generator anew
    (SEED), so that the demonstrator's play that `demos` prints and the recording draw the
    same noise on the same episodes."""

    def make():
        controller, rng = make_controller(), np.random.default_rng(seed)

        def act(obs):
            clean = gain * np.asarray(controller(obs), dtype=np.float64)
            return np.clip(clean + sigma * rng.standard_normal(clean.shape), -1.0, 1.0)

        return act

    return make


def logo_env(env_id, limit):
    """The maker of a logo-rl env under Gymnasium's TimeLimit (what recording expects),
    named after the env id, which the recorded dataset then names as its env."""
    import gymnasium as gym

    def make():
        return gym.wrappers.TimeLimit(logo_rl.LogoEnv(env_id, max_episode_steps=None), limit)

    make.__name__ = env_id
    return make


# Each task: the env (a logo-rl id, made sparse by its kind, or a Gymnasium env: `python`,
# trained through logo_rl), the success rule a run counts with, the sample budget per run,
# the demonstrator and the number of demonstration episodes.
TASKS = {
    "reacher-goal": dict(
        kind="manipulation goal",
        env=logo_env("Reacher-v5+goal(0.02)", 50),
        env_id="Reacher-v5+goal(0.02)",
        success="task",
        budget=1_000_000,
        demonstrator=reacher_controller(),
        episodes=20,
        legend="lower-right",  # the curves rise early: the lower right stays free
    ),
    # Sparse locomotion: the Ant study's task and demonstrations (docs/findings/new-tasks.md:
    # a behaviour policy trained here on the dense reward, 20 episodes with sampled actions,
    # made by scripts/experiments/new_task.sh).
    "ant-distance": dict(
        kind="sparse locomotion",
        env=logo_env("Ant-v4+distance(5)", 1000),
        env_id="Ant-v4+distance(5)",
        success="task",
        budget=2_000_000,
        demonstrator=trained("docs/results/new-task/ant/behaviour/checkpoint.safetensors"),
        dataset="data/suite/ant-distance/demos",
        episodes=20,
    ),
    # A delayed reward: Hopper's dense return paid once, on the episode's last step. The
    # demonstrations are data/behaviour/hopper-trpo (a dense-reward TRPO policy stopped
    # at the LOGO demonstrations' return, data/README.md). The task defines no goal, so no
    # success rate: the runs are read by their return against the demonstrations'.
    "hopper-delayed": dict(
        kind="delayed reward",
        env=logo_env("Hopper-v4+delayed", 1000),
        env_id="Hopper-v4+delayed",
        success="none",
        budget=2_000_000,
        demonstrator=trained("models/hopper_behaviour_trpo.safetensors"),
        dataset="data/behaviour/hopper-trpo",
        episodes=20,
    ),
    # Navigation in a maze: Gymnasium-Robotics' PointMaze (its sparse reward: 1 on every
    # step within 0.45 of the goal; info["success"]). Needs `.venv/bin/pip install
    # gymnasium-robotics==1.4.0` (it installs beside Gymnasium 1.4.0).
    "maze": dict(
        kind="navigation in a maze",
        env=point_maze_medium,
        python=True,
        env_id="PointMaze_Medium-v3, cells (1, 1) to (6, 6)",
        success="task",
        budget=1_000_000,
        demonstrator=None,  # made on first use: it reads the maze's map
        episodes=20,
        legend="lower-right",  # the rise by 300k is at the upper left; TRPO's 0 shows left of it
    ),
    "mountain-car": dict(
        kind="goal with an action cost",
        env="MountainCarContinuous-v0",
        python=True,
        env_id="MountainCarContinuous-v0",
        success="terminated",
        budget=200_000,
        demonstrator=mountain_car_controller,
        episodes=15,
        legend="lower-right",
    ),
}


# Degraded demonstrations (the issue of going beyond sub-optimal demonstrations): the same
# task, env, success rule and budget, demonstrated by the task's scripted controller made
# worse by `degraded` so that it reaches the goal in 30-60% of its episodes; the gain and
# noise were chosen on the episodes `demos` prints (seed 0) before any run, and fixed.
# TRPO uses no demonstrations: a degraded task's table reads TRPO's runs of its base task.
DEGRADED = {
    "reacher-goal-degraded": ("reacher-goal", lambda: reacher_controller(), 0.5, 1.0),
    "mountain-car-degraded": ("mountain-car", lambda: mountain_car_controller, 0.1, 1.0),
    "maze-degraded": ("maze", lambda: maze_controller(), 0.2, 1.0),
}
for _name, (_base, _controller, _gain, _sigma) in DEGRADED.items():
    TASKS[_name] = dict(TASKS[_base], base=_base, demonstrator=None,
                        make_demonstrator=degraded(_controller, _gain, _sigma),
                        degradation=(_gain, _sigma))
    TASKS[_name].pop("dataset", None)


def demonstrator_of(task):
    """A task's demonstrator, made anew where it has a maker (a degraded one's noise starts
    again) or on first use (the maze's reads its map)."""
    if "make_demonstrator" in task:
        return task["make_demonstrator"]()
    return task["demonstrator"] or maze_controller()


def make_env(env):
    """A task's env: its maker called, or its Gymnasium id made."""
    import gymnasium as gym

    return env() if callable(env) else gym.make(env)


def seed_range(seeds: str) -> range:
    """`0..5` as logo sweep reads it: seeds 0 to 4."""
    first, last = (int(x) for x in seeds.split(".."))
    return range(first, last)


def play(env, act, episodes, seed, success):
    """Returns, steps and whether each episode reached the goal by the task's success rule
    ("task": any step's info["is_success"]; "terminated": the episode ended there;
    "none": no goal, None)."""
    out = []
    for k in range(episodes):
        obs, _ = env.reset(seed=seed + k)
        total, steps, reached, done = 0.0, 0, False, False
        while not done:
            obs, reward, terminated, truncated, info = env.step(np.asarray(act(obs)))
            total += float(reward)
            steps += 1
            goal = info.get("is_success", info.get("success", False))
            reached |= bool(goal if success == "task" else terminated)
            done = terminated or truncated
        out.append((total, steps, None if success == "none" else reached))
    return out


def describe(name, results):
    returns = np.array([r for r, _, _ in results])
    earned = f"return {returns.mean():.2f} ± {returns.std(ddof=1):.2f}"
    if results[0][2] is None:
        return f"  {name:<13} {earned} over {len(results)} episodes (the task has no goal)"
    reached = sum(ok for _, _, ok in results)
    return f"  {name:<13} reached the goal in {reached} of {len(results)} episodes; {earned}"


def demos(out: Path, names, episodes, seed):
    for name in names:
        task = TASKS[name]
        n = episodes or task["episodes"]
        rng = np.random.default_rng(seed)
        env = make_env(task["env"])
        space = env.action_space
        random_act = lambda obs: rng.uniform(space.low, space.high)  # noqa: E731
        zero_act = lambda obs: np.zeros(space.shape)  # noqa: E731
        print(f"{name} ({task['kind']}): {task['env_id']}, success = {task['success']!r}, "
              f"budget {task['budget']:,} samples")
        if "degradation" in task:
            gain, sigma = task["degradation"]
            print(f"  demonstrator: {task['base']}'s, its action × {gain} plus N(0, {sigma}²) "
                  "noise, clipped to [-1, 1]")
        for who, act in [("demonstrator", demonstrator_of(task)), ("random", random_act),
                         ("zero", zero_act)]:
            print(describe(who, play(env, act, n, seed, task["success"])))
        path = out / name / "demos"
        if "dataset" in task:
            # Made by another study (the Ant study's, now in data/suite/ant-distance/demos).
            path.parent.mkdir(parents=True, exist_ok=True)
            if not path.exists():
                path.symlink_to(os.path.relpath(ROOT / task["dataset"], path.parent))
            print(f"  demonstrations: {task['dataset']} (linked from {path})")
            continue
        recording = logo_rl.record(task["env"], demonstrator_of(task), n, path, seed=seed)
        print(f"  recorded {recording.episodes} episodes, {recording.steps} steps into {path}")


def toml_value(value):
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    return repr(value)


def replace_line(text: str, line: str, new: str) -> str:
    """TEXT with its one line LINE replaced by NEW; an error where LINE is not there once
    (a template edited under the suite must not change a task's config silently)."""
    lines = text.split("\n")
    if lines.count(line) != 1:
        raise SystemExit(f"{PRESET}: expected the line {line!r} once, found it "
                         f"{lines.count(line)} times")
    return "\n".join(new if x == line else x for x in lines)


# The guidance keys a kept run must share with the preset, and the defaults of those a
# config may leave out (docs/config.md).
GUIDANCE_KEYS = ("delta0", "alpha", "warmup", "decay_on", "decay_from", "grow_back",
                 "discriminator_steps")
GUIDANCE_DEFAULTS = {"decay_on": "return", "discriminator_steps": 1, "grow_back": False}

# Candidates for the preset: arms that are its LOGO config with these guidance keys
# changed, run beside it to decide what the preset should be. `logo-waiting`: δ_k shrinks
# only at iterations where at least 0.9 of the batch's (sampled) episodes reached the goal;
# `logo-eval-waiting`: only after evaluations (the mean action) with at least 0.9 of their
# episodes at the goal; `logo-eval-following`: so, and after the others it grows back by
# 1/α, up to δ_0.
CANDIDATES = {
    "logo-waiting": {"alpha": 0.9, "decay_on": "success", "decay_from": 0.9},
    "logo-eval-waiting": {"alpha": 0.9, "decay_on": "evaluation", "decay_from": 0.9},
    "logo-eval-following": {"alpha": 0.9, "decay_on": "evaluation", "decay_from": 0.9,
                            "grow_back": True},
    # `logo-letting-go`: δ_k held until an evaluation's share at the goal reaches the
    # demonstrations' own (DEMONSTRATED), then shrinking by 0.9 after each such one.
    "logo-letting-go": {"alpha": 0.9, "decay_on": "evaluation",
                        "decay_from": "demonstrations"},
}


def candidate_keys(arm: str, name: str, required: bool = True) -> dict | None:
    """CANDIDATES[ARM] for task NAME: a level of "demonstrations" is the share of the
    task's demonstration episodes that reached the goal. A task without a goal has none:
    an error where REQUIRED, else None (the arm is not made for it)."""
    keys = dict(CANDIDATES[arm])
    if keys.get("decay_from") == "demonstrations":
        reached = DEMONSTRATED[name]["reached"]
        if reached is None:
            if not required:
                return None
            raise SystemExit(f"{arm}: {name} has no goal, so its demonstrations have no "
                             "success share to let the guidance go at")
        keys["decay_from"] = reached[0] / reached[1]
    return keys


# Arms that start from the demonstrations' clone: the named arm's config with `[init] kind =
# "bc"` (behaviour cloning on the guidance's demonstrations before the first iteration),
# nothing else changed. `bc-logo`: the new-task preset from the clone, the first probe of
# LOGO that keeps the clone (run only when named by --arms).
CLONE_STARTED = {"bc-logo": "logo", "bc-logo-letting-go": "logo-letting-go"}


# The seed's Figure 1 baselines (docs/algorithms.md), each the task's LOGO config made into
# that method by its own keys, as `logo compare` makes them (logo_rl's configure: GAIL and
# POfD keep the discriminator without the guidance step, BC-TRPO and DAPG clone the
# demonstrations first), run only when named by --arms.
BASELINES = ("gail", "pofd", "bc-trpo", "dapg")


def baseline_config(folder: Path, method: str, logo: Path, table: dict | None = None) -> Path:
    """FOLDER/configs/METHOD.toml: the LOGO config LOGO (with TABLE laid over it) made into
    METHOD."""
    from logo_rl import _logo_rl

    text = _logo_rl.configure(name=method, config=str(logo), table_json=json.dumps(table or {}),
                              base=str(ROOT))
    path = folder / "configs" / f"{method}.toml"
    path.parent.mkdir(parents=True, exist_ok=True)
    write_if_changed(path, f"# {method}, made from {logo.name} as `logo compare` makes it "
                     "(scripts/experiments/suite.py BASELINES)\n" + text)
    return path


def refuse_other_runs(arm: Path, config: dict, then: str = "to run the new config"):
    """Stops where a kept run of ARM was made with other guidance settings than CONFIG's:
    `logo sweep` would count it done (or resume it with its own config) under the new one,
    and a report would keep both under one name (THEN: what moving ARM aside allows).
    What δ_k's decay reads does not matter where neither decays (α = 1)."""
    wanted = {**GUIDANCE_DEFAULTS, **config.get("guidance", {})}
    for run_config in sorted(arm.glob("seed*/config.toml")):
        kept = {**GUIDANCE_DEFAULTS, **tomllib.loads(run_config.read_text()).get("guidance", {})}
        held = kept.get("alpha") == wanted.get("alpha") == 1.0
        for key in GUIDANCE_KEYS:
            if key == "decay_on" and held:
                continue
            if kept.get(key) != wanted.get(key):
                raise SystemExit(
                    f"{run_config}: guidance.{key} = {kept.get(key)!r}, the suite's config "
                    f"now says {wanted.get(key)!r}; move {arm} aside {then}")


def write_if_changed(path: Path, text: str):
    """PATH holds TEXT, written whole (another copy of the suite may be starting a run from
    it) and only where it differs."""
    if path.is_file() and path.read_text() == text:
        return
    partial = path.with_name(f".{path.name}.{os.getpid()}.partial")
    partial.write_text(text)
    os.replace(partial, path)


def configs(out: Path, name: str) -> list[Path]:
    """The task's LOGO (new-task preset), TRPO, candidate and baseline configs, written
    under out/configs."""
    task = TASKS[name]
    preset = tomllib.loads(PRESET.read_text())
    iterations = task["budget"] // preset["samples_per_iter"]
    demos = ROOT / "data" / "suite" / name / "demos"
    if not demos.is_dir():
        raise SystemExit(f"{demos}: no demonstrations (run `suite.py demos data/suite {name}`)")
    header = (f"# The suite's {name} ({task['kind']}): configs/templates/new_task.toml with the "
              f"task's env, demonstrations, success rule and budget (scripts/experiments/suite.py).\n")
    settings = {"env": task["env_id"], "success": task["success"], "iterations": iterations}
    top = "".join(f"{k} = {toml_value(v)}\n" for k, v in settings.items())
    text = PRESET.read_text()
    kept = [line for line in text.splitlines()
            if not line.split("=")[0].strip() in ("env", "success", "iterations")]
    body = replace_line("\n".join(kept), 'demos = "../../data/logo/hopper"',
                        f"demos = {toml_value(str(demos))}")
    folder = out / "configs"
    folder.mkdir(parents=True, exist_ok=True)
    logo = folder / "logo.toml"
    write_if_changed(logo, header + top + body + "\n")
    # TRPO: the same config without its [guidance] table (nor the guidance's comments).
    cut = body.index("[guidance]")
    trpo = folder / "trpo.toml"
    write_if_changed(trpo, header + top + body[:cut].rstrip() + "\n")
    made = [arm for arm in CANDIDATES if candidate_keys(arm, name, required=False)]
    for arm in made:
        keys = candidate_keys(arm, name)
        write_if_changed(folder / f"{arm}.toml", header + top + candidate(body, arm, keys) + "\n")
    made += [arm for arm, source in CLONE_STARTED.items() if source in ("logo", *made)]
    for arm, source in [(a, s) for a, s in CLONE_STARTED.items() if a in made]:
        text = (folder / f"{source}.toml").read_text()
        if "\n[init]" in text:
            raise SystemExit(f"{folder / source}.toml has an [init] table already: {arm} would "
                             "not be that config from the clone alone")
        write_if_changed(folder / f"{arm}.toml",
                         text + f"\n# {arm}: {source}'s config from the demonstrations' clone "
                         "(scripts/experiments/suite.py CLONE_STARTED)\n[init]\nkind = \"bc\"\n")
    baselines = [baseline_config(out, method, logo) for method in BASELINES]
    return [logo, trpo] + [folder / f"{arm}.toml" for arm in made] + baselines


def candidate(body: str, arm: str, keys: dict) -> str:
    """The preset's config BODY with the candidate's guidance KEYS in place: each one
    replacing the preset's line of that key, or added at the end of [guidance]."""
    lines = body.split("\n")
    start = lines.index("[guidance]")
    end = next((i for i in range(start + 1, len(lines)) if lines[i].startswith("[")), len(lines))
    added = []
    for key, value in keys.items():
        line = f"{key} = {toml_value(value)}"
        at = [i for i in range(start, end) if lines[i].split("=")[0].strip() == key]
        if at:
            lines[at[0]] = line
        else:
            added.append(line)
    lines[end:end] = [f"# The candidate {arm} (scripts/experiments/suite.py CANDIDATES):"] + added
    return "\n".join(lines)


# The methods each task is run with: their folders under OUT/<task>/runs and their names.
ARMS = ("logo", "trpo", "bc")
# What a task's table shows, where kept: those, LOGO's runs made with an earlier preset
# that let δ_k decay (logo-decayed), and the candidates (ARM_NAMES' order).
REPORTED = tuple(ARM_NAMES)


def run(out: Path, names, seeds: str, iterations: int | None = None, arms=ARMS):
    for name in names:
        task = TASKS[name]
        folder = out / name
        if "base" in task and "trpo" in arms:
            # TRPO uses no demonstrations: its runs of the base task are the degraded task's.
            print(f"[suite] {name}: TRPO's runs are {task['base']}'s (no demonstrations)")
            arms = tuple(a for a in arms if a != "trpo")
        if task.get("python"):
            run_python(folder, name, seeds, iterations, arms)
            continue
        written = configs(folder, name)
        for config in written:
            if config.stem in ("logo", *CANDIDATES, *CLONE_STARTED) and config.stem in arms:
                refuse_other_runs(folder / "runs" / config.stem, tomllib.loads(config.read_text()))
        logo = written[0]
        for config in written:
            todo = unfinished(folder / "runs" / config.stem, seeds) if config.stem in arms else []
            if not todo:
                continue
            sweep = [LOGO, "sweep", str(config), "--seeds", ",".join(map(str, todo)),
                     "--jobs", "1", "--threads", "1", "--out", str(folder / "runs")]
            if iterations is not None:  # a shorter run than the budget (a smoke test)
                sweep += ["--iterations", str(iterations)]
            subprocess.run(sweep, check=True, env=LOGO_ENVIRONMENT)
        for seed in unfinished(folder / "runs" / "bc", seeds) if "bc" in arms else ():
            bc = folder / "runs" / "bc" / f"seed{seed}"
            if (bc / "policy.safetensors").is_file():
                continue
            bc.mkdir(parents=True, exist_ok=True)
            with open(bc / "bc.txt", "w") as log:
                subprocess.run([LOGO, "bc", "--config", str(logo), "--seed", str(seed),
                                "--out", str(bc / "policy.safetensors")],
                               check=True, env=LOGO_ENVIRONMENT, stdout=log)


def unfinished(arm: Path, seeds: str) -> list[int]:
    """The seeds of ARM (a method's runs) with no final evaluation yet. A run kept from
    docs/results has no checkpoint, by which `logo sweep` would count it done."""
    return [s for s in seed_range(seeds) if final_policy(arm / f"seed{s}") is None]


def _logo_rl_preset() -> dict:
    """The new-task preset as the installed logo_rl carries it (built into the package)."""
    from logo_rl.presets import preset_path

    return tomllib.loads(preset_path("new-task").read_text())


def run_python(folder: Path, name: str, seeds: str, iterations: int | None, arms=ARMS):
    """A Gymnasium env's task through logo_rl.train and logo_rl.bc (the Rust sampler steps
    the Python env), with the same arms and the new-task preset."""
    task = TASKS[name]
    preset = tomllib.loads(PRESET.read_text())
    if ({"logo", "trpo", *CANDIDATES, *CLONE_STARTED, *BASELINES} & set(arms)
            and _logo_rl_preset() != preset):
        raise SystemExit(f"logo_rl's new-task preset is not {PRESET} as it is now (the package "
                         "was built before the file changed): build it again, scripts/setup.sh")
    for arm in [a for a in ("logo", *CLONE_STARTED) if a in arms]:
        if CLONE_STARTED.get(arm, "logo") == "logo":
            refuse_other_runs(folder / "runs" / arm, preset)
    for arm in [a for a in CLONE_STARTED if a in arms] + sorted(CANDIDATES.keys() & set(arms)):
        source = CLONE_STARTED.get(arm, arm)
        if source in CANDIDATES:
            guidance = {**preset["guidance"], **candidate_keys(source, name)}
            refuse_other_runs(folder / "runs" / arm, {**preset, "guidance": guidance})
    demos = ROOT / "data" / "suite" / name / "demos"
    n = iterations or task["budget"] // preset["samples_per_iter"]
    # Each arm's config and keys for logo_rl.train: the preset with the arm's own keys, or
    # (a baseline) the preset made into that method.
    starts = {}
    for arm in [a for a in ("logo", *CANDIDATES, *CLONE_STARTED, "trpo") if a in arms]:
        arm_keys = {"guidance": None} if arm == "trpo" else {"demos": demos}
        source = CLONE_STARTED.get(arm, arm)
        if source in CANDIDATES:
            arm_keys["guidance"] = candidate_keys(source, name)
        if arm in CLONE_STARTED:
            arm_keys["init"] = {"kind": "bc"}
        starts[arm] = ("new-task", dict(iterations=n, success=task["success"], **arm_keys))
    for method in [m for m in BASELINES if m in arms]:
        starts[method] = (baseline_config(folder, method, PRESET, {
            "success": task["success"], "iterations": n, "guidance": {"demos": str(demos)}}), {})
    for seed in seed_range(seeds):
        for arm, (config, arm_keys) in starts.items():
            run_dir = folder / "runs" / arm / f"seed{seed}"
            if (run_dir / "eval.json").is_file():
                continue
            print(f"[suite] {name} {arm}/seed{seed}", flush=True)
            if (run_dir / "checkpoint.safetensors").is_file():
                logo_rl.train(resume=run_dir, env=task["env"], progress=False)
                continue
            logo_rl.train(config, env=task["env"], out=run_dir, seed=seed, progress=False,
                          **arm_keys)
        bc = folder / "runs" / "bc" / f"seed{seed}"
        if "bc" in arms and final_policy(bc) is None and not (bc / "policy.safetensors").is_file():
            cloned = logo_rl.bc(demos, env=task["env"], seed=seed, success=task["success"],
                                out=bc / "policy.safetensors")
            kept = {"pairs": cloned.pairs, "loss_before": cloned.loss_before,
                    "loss_after": cloned.loss_after, "evaluation": cloned.evaluation}
            (bc / "bc.json").write_text(json.dumps(kept, indent=1) + "\n")


def final_policy(folder: Path) -> dict | None:
    """A finished seed's final policy as its evaluation file holds it (a run's eval.json,
    BC's policy.eval.json), or None while it runs."""
    for name in ("eval.json", "policy.eval.json", "eval.json.gz", "policy.eval.json.gz"):
        path = folder / name
        if path.is_file():
            text = gzip.decompress(path.read_bytes()) if name.endswith(".gz") else path.read_text()
            return json.loads(text)["policies"]["final"]
    return None


def bc_evaluation(folder: Path):
    """BC's policy.eval.json where a `logo bc` older than it left only the checkpoint:
    `logo eval --json` plays the same episodes (the checkpoint's seed, 20 fresh initial
    states, its success rule) and its report is kept in `logo bc`'s layout."""
    checkpoint = folder / "policy.safetensors"
    if (folder / "policy.eval.json").is_file() or not checkpoint.is_file():
        return
    if (folder / "bc.json").is_file():
        # A Python env's BC (logo_rl.bc), which `logo eval` cannot make: logo_rl.bc writes
        # the file itself since it judges by the task's success rule.
        raise SystemExit(f"{folder}: BC made before logo_rl.bc kept its evaluation (and "
                         "judged it by the task's rule): delete the folder and run again")
    played = json.loads(subprocess.run(
        [LOGO, "eval", "--checkpoint", str(checkpoint), "--json"],
        check=True, env=LOGO_ENVIRONMENT, capture_output=True, text=True).stdout)
    final = {"checkpoint": checkpoint.name, "iteration": 0,
             "mean_action": played["mean_action"], "clipped": played["clipped"]}
    doc = {"env": played["env"], "seed": int(folder.name[4:]),
           "episodes": len(played["mean_action"]["episodes"]),
           "initial_states": "fresh: as `logo eval --json` (the checkpoint's seed)",
           "policies": {"final": final}}
    (folder / "policy.eval.json").write_text(json.dumps(doc, indent=2) + "\n")


def task_table(out: Path, name: str, keep: Path | None, reference: str = "logo") -> str:
    """One task's table and its check comment, whose groups name the folders --keep
    copies to (relative to docs/results/; docs/results/suite without --keep). An arm with
    no finished run under OUT is read from --keep, where an earlier report copied it (its
    runs since deleted from OUT), so a report of new arms keeps the old ones in the table.
    REFERENCE: the arm every other is compared with, in the first row ("LOGO" in the
    header's P and difference columns)."""
    runs = out / name / "runs"
    kept_task = keep / name if keep is not None else None
    seeds: dict[str, list[tuple[int, dict]]] = {}
    finished = lambda arm: any(  # noqa: E731 (a BC seed is finished once its checkpoint is)
        final_policy(f) or (f / "policy.safetensors").is_file() for f in (runs / arm).glob("seed*"))
    source = {a: runs / a if kept_task is None or finished(a) else kept_task / a for a in REPORTED}
    if "base" in TASKS[name]:
        # TRPO uses no demonstrations: the base task's runs, as kept (or under OUT).
        base = TASKS[name]["base"]
        kept_base = keep / base / "trpo" if keep is not None else None
        source["trpo"] = kept_base if kept_base is not None and kept_base.is_dir() \
            else out / base / "runs" / "trpo"
    arms = [a for a in REPORTED if a in ARMS or source[a].is_dir()]
    if reference not in arms:
        raise SystemExit(f"{name}: no runs of the reference arm {reference}")
    arms = [reference] + [a for a in arms if a != reference]
    for arm in arms:
        copying = (kept_task is not None and source[arm] != kept_task / arm
                   and not (arm == "trpo" and "base" in TASKS[name]))
        if copying and (kept_task / arm).is_dir():
            # Seeds of another config must not join the kept ones under one name.
            first = next(source[arm].glob("seed*/config.toml"), None)
            if first is not None:
                refuse_other_runs(kept_task / arm, tomllib.loads(first.read_text()),
                                  then=f"to keep {source[arm]}'s runs in its place")
        found = []
        for folder in sorted(source[arm].glob("seed*"), key=lambda p: int(p.name[4:])):
            if arm == "bc":
                bc_evaluation(folder)
            policy = final_policy(folder)
            if policy is not None:
                found.append((int(folder.name[4:]), policy))
                if copying:
                    keep_seed(folder, kept_task / arm / folder.name)
        seeds[arm] = found
    demo = DEMONSTRATED[name]
    goal = demo["reached"] is not None
    returns = {a: [p["mean_action"]["summary"]["return"] for _, p in seeds[a]] for a in arms}
    if goal:
        k, n = demo["reached"]
        target = f"seeds at ≥ the demonstrations' {k}/{n}"
    else:
        target = f"seeds at ≥ the demonstrations' return {demo['return']:.1f}"
    header = ["method", "seeds", "final return: IQM [95% CI]",
              "reached the goal, final policy per seed" if goal else "reached the goal",
              target, "P(LOGO > method) [95% CI]", "IQM difference LOGO − method [95% CI]"]
    rows = []
    for arm in arms:
        x = returns[arm]
        if not x:
            rows.append([ARM_NAMES[arm], "0"] + ["—"] * (len(header) - 2))
            continue
        cells = [ARM_NAMES[arm], str(len(x)), estimate(iqm(x), interval(x, iqm), 1)]
        if goal:
            counts = [p["mean_action"]["summary"]["reached"] for _, p in seeds[arm]]
            cells.append(", ".join(str(c[0]) for c in counts) + f" of {counts[0][1]}")
            rate = demo["reached"][0] / demo["reached"][1]
            met = sum(c[0] / c[1] >= rate for c in counts)
        else:
            cells.append("— (no goal)")
            met = sum(v >= demo["return"] for v in x)
        cells.append(f"{met} of {len(x)}")
        y = returns[reference]
        if arm == reference or not y:
            cells += ["—", "—"]
        else:
            difference = lambda a, b: iqm(a) - iqm(b)  # noqa: E731
            cells.append(estimate(probability_of_improvement(y, x),
                                  interval_two(y, x, probability_of_improvement), 2))
            cells.append(estimate(difference(y, x), interval_two(y, x, difference), 1))
        rows.append(cells)
    docs = ROOT / "docs" / "results"
    kept = keep.resolve() if keep is not None else docs / "suite"
    base = kept.relative_to(docs) if kept.is_relative_to(docs) else kept
    groups = ";".join(f"{base}/{TASKS[name].get('base', name) if arm == 'trpo' else name}/{arm}"
                      for arm in arms)
    demos_option = (f"demos={demo['reached'][0]}/{demo['reached'][1]}" if goal
                    else f"demos_return={demo['return']}")
    lines = [f"<!-- check suite rows={groups} {demos_option} -->",
             "| " + " | ".join(header) + " |", "|" + " --- |" * len(header)]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(lines)


def number(x: float, digits: int) -> str:
    """x with a typographic minus, as the results pages print numbers."""
    return f"{x:.{digits}f}".replace("-", "−")


def estimate(point: float, interval: tuple[float, float], digits: int) -> str:
    """"POINT [LO, HI]"."""
    lo, hi = interval
    return f"{number(point, digits)} [{number(lo, digits)}, {number(hi, digits)}]"


def keep_seed(source: Path, dest: Path):
    """A finished seed's files for the results page: no checkpoints."""
    dest.mkdir(parents=True, exist_ok=True)
    for name in ("metrics.csv", "metrics.csv.gz", "config.toml", "eval.json", "eval.json.gz",
                 "policy.eval.json", "bc.txt", "bc.json"):
        if (source / name).is_file():
            shutil.copy2(source / name, dest / name)


def learning_figure(keep: Path, name: str):
    """The training curves, IQM over seeds with 95% bands, of the share of sampled
    episodes at the goal (the return where the task has none): LOGO's presets and
    candidates beside TRPO as KEEP/<task>.png, and LOGO's preset and TRPO beside the
    Figure 1 baselines as KEEP/<task>-baselines.png (where any is kept); data as .csv."""
    task = TASKS[name]
    metric, what = (("train_sparse_return", "sampled episodes' return")
                    if task["success"] == "none" else
                    ("train_success", "share of sampled episodes at the goal"))
    # (figure, its arms, the arms one of which must be kept for it to be drawn)
    main_arms = ("logo", "logo-decayed", *CANDIDATES, *CLONE_STARTED, "trpo")
    figures = [(name, main_arms, main_arms),
               (f"{name}-baselines", ("logo", "trpo", *BASELINES), BASELINES)]
    legend = ["--legend", task["legend"]] if "legend" in task else []
    # TRPO uses no demonstrations: a degraded task's is its base task's.
    folder = {arm: keep / name / arm for arm in ARM_NAMES}
    if "base" in task:
        folder["trpo"] = keep / task["base"] / "trpo"
    for figure, candidates, needed in figures:
        arms = [arm for arm in candidates if folder[arm].is_dir()]
        if not set(arms) & set(needed):
            continue
        labels = [f"--label={arm}={ARM_NAMES[arm]}" for arm in arms]
        subprocess.run([LOGO, "plot", *(str(folder[arm]) for arm in arms),
                        "--metric", metric, "--stat", "iqm", "--band", "ci", "--smooth", "5",
                        *labels, *legend, "--title", f"{name}: {what} (IQM, 95% band)",
                        "--out", str(keep / f"{figure}.png")],
                       check=True, env=LOGO_ENVIRONMENT, stdout=subprocess.DEVNULL)


def report(out: Path, names, keep: Path | None, reference: str = "logo"):
    for name in names:
        task = TASKS[name]
        print(f"### {name}: {task['kind']}, {task['env_id']}, {task['budget']:,} samples\n")
        print(task_table(out, name, keep, reference) + "\n")
        if keep is not None:
            learning_figure(keep, name)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    d = sub.add_parser("demos", help="record each task's demonstrations")
    d.add_argument("out", type=Path)
    d.add_argument("tasks", nargs="*", default=list(TASKS))
    d.add_argument("--episodes", type=int, default=None)
    d.add_argument("--seed", type=int, default=0)
    r = sub.add_parser("run", help="LOGO, TRPO and BC on each task")
    r.add_argument("out", type=Path)
    r.add_argument("tasks", nargs="*", default=list(TASKS))
    r.add_argument("--seeds", default="0..5")
    r.add_argument("--iterations", type=int, default=None,
                   help="fewer iterations than the budget's (a smoke test)")
    r.add_argument("--arms", default=",".join(ARMS),
                   help="the methods to run, of " + ", ".join(
                       ARMS + tuple(CANDIDATES) + tuple(CLONE_STARTED) + BASELINES) +
                   " (a changed preset needs only logo run again; a candidate preset and the "
                   "baselines are run only when named)")
    p = sub.add_parser("report", help="each task's table of final policies")
    p.add_argument("out", type=Path)
    p.add_argument("tasks", nargs="*", default=list(TASKS))
    p.add_argument("--keep", type=Path, default=None,
                   help="copy the finished runs' files into KEEP/<task>/<method>/seed<N>")
    p.add_argument("--reference", default="logo", choices=REPORTED,
                   help="the arm in the first row, which every other is compared with")
    sub.add_parser("list", help="the tasks")
    args = parser.parse_args(argv)
    if args.command == "list":
        for name, task in TASKS.items():
            print(f"{name}: {task['kind']}, {task['env_id']}, success={task['success']!r}, "
                  f"budget {task['budget']:,}")
        return 0
    unknown = [t for t in args.tasks if t not in TASKS]
    if unknown:
        parser.error(f"unknown task(s) {', '.join(unknown)}; the tasks: {', '.join(TASKS)}")
    if args.command == "run":
        arms = tuple(a.strip() for a in args.arms.split(","))
        known = ARMS + tuple(CANDIDATES) + tuple(CLONE_STARTED) + BASELINES
        if not arms or any(a not in known for a in arms):
            parser.error(f"--arms {args.arms!r}: expected some of {', '.join(known)}, "
                         "separated by commas")
        run(args.out, args.tasks, args.seeds, args.iterations, arms)
    elif args.command == "report":
        report(args.out, args.tasks, args.keep, args.reference)
    else:
        demos(args.out, args.tasks, args.episodes, args.seed)
    return 0


if __name__ == "__main__":
    sys.exit(main())
