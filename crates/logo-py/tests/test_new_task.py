"""The new-task preset (configs/templates/new_task.toml) on a held-out Gymnasium task,
MountainCarContinuous-v0: a goal, an action cost, and scripted demonstrations."""

import csv
from pathlib import Path

import numpy as np
import pytest

import logo_rl

ROOT = Path(__file__).resolve().parents[3]
PRESET = ROOT / "configs" / "templates" / "new_task.toml"
TASK = "MountainCarContinuous-v0"


def pump(obs):
    """Push the way the car moves: every episode reaches the flag."""
    return np.array([1.0 if obs[1] >= 0 else -1.0])


@pytest.fixture(scope="module")
def demos(tmp_path_factory):
    return logo_rl.record(TASK, pump, 5, tmp_path_factory.mktemp("mcc") / "demos")


def rows(run):
    with open(run.path / "metrics.csv", newline="") as f:
        return list(csv.DictReader(f))


def overshoots(run, limit):
    """The accepted steps whose measured KL exceeds `limit` times their bound."""
    out = []
    for r in rows(run):
        bound = 0.01  # the preset's max_kl
        if r["update_stop"] == "accepted" and float(r["kl"]) > limit * bound:
            out.append(("improvement", r["iteration"], r["kl"]))
        if r["guidance_stop"] == "accepted" and float(r["guidance_kl"]) > limit * float(r["delta_k"]):
            out.append(("guidance", r["iteration"], r["guidance_kl"], r["delta_k"]))
    return out


def test_no_accepted_step_of_the_preset_exceeds_its_kl_limit(tmp_path, demos):
    train = lambda name, **kw: logo_rl.train(  # noqa: E731
        PRESET, env=TASK, demos=demos, success="terminated", iterations=6,
        samples_per_iter=3000, seed=1, out=tmp_path / name, progress=False,
        tensorboard=False, **kw,
    )
    preset = train("preset")
    assert len(rows(preset)) == 6
    assert overshoots(preset, 1.5) == []
    # The same scenario with the check off and LOGO's δ_0 = 0.2 overshoots: the test
    # above would see a preset without its limit.
    unlimited = train("unlimited", guidance={"delta0": 0.2}, improvement={"kl_limit": 1e9})
    assert overshoots(unlimited, 1.5) != []


def test_success_is_the_tasks_and_none_where_it_defines_none(tmp_path, demos):
    common = dict(env=TASK, demos=demos, iterations=1, samples_per_iter=1000, seed=0,
                  progress=False, tensorboard=False, eval_episodes=1)
    # MountainCar reports no is_success: with the task's rule there is none to report (the
    # preset holds δ_k, so no decay reads it).
    run = logo_rl.train(PRESET, out=tmp_path / "plain", **common)
    summary = run.eval["policies"]["final"]["mean_action"]["summary"]
    assert summary["reached"] is None and summary["success_rate"] is None
    assert np.isnan(float(rows(run)[0]["eval_success"]))
    # Decaying δ_k on success there has nothing to read: refused, naming the remedy for a
    # task with no goal at all, δ_k held.
    with pytest.raises(logo_rl.LogoError, match="the task defines no success") as refused:
        logo_rl.train(PRESET, out=tmp_path / "decaying", **common,
                      guidance={"alpha": 0.9, "decay_on": "success"})
    assert 'guidance.decay_on = "return" with guidance.alpha = 1.0' in str(refused.value)
    # A task that stops at its goal: an episode that ends by termination reached it.
    run = logo_rl.train(PRESET, out=tmp_path / "terminated", success="terminated", **common)
    summary = run.eval["policies"]["final"]["mean_action"]["summary"]
    k, n = summary["reached"]
    assert n == 20 and summary["success_rate"] == k / n


def left_of_the_valley(obs, info):
    return obs[0] < -0.55


def test_a_python_envs_is_success_is_honoured(tmp_path, demos):
    import gymnasium as gym

    class LeftOfTheValley(gym.Wrapper):
        """Success: the car is ever left of the valley's floor."""

        def step(self, action):
            obs, reward, terminated, truncated, info = self.env.step(action)
            return obs, reward, terminated, truncated, {**info, "is_success": left_of_the_valley(obs, info)}

    make = lambda: LeftOfTheValley(gym.make(TASK))  # noqa: E731
    run = logo_rl.train(
        PRESET, env=make, demos=demos, iterations=1, samples_per_iter=1000, seed=0,
        eval_episodes=1, progress=False, tensorboard=False, out=tmp_path / "run",
    )
    reached = run.eval["policies"]["final"]["mean_action"]["summary"]["reached"]
    # The same 20 episodes replayed here: an episode succeeds if any step reported it.
    policy, env, hits = run.policy("final"), make(), 0
    for k in range(20):
        obs, _ = env.reset(seed=3_000_000 + k)
        while True:
            obs, _, terminated, truncated, info = env.step(policy.predict(obs))
            if info["is_success"]:
                hits += 1
                break
            if terminated or truncated:
                break
    assert reached == [hits, 20]
    assert 0 < hits < 20, "the rule must see both outcomes to be tested"
    # The same rule given as a predicate: the same run, the same count.
    judged = logo_rl.train(
        PRESET, env=TASK, demos=demos, iterations=1, samples_per_iter=1000, seed=0,
        eval_episodes=1, progress=False, tensorboard=False, out=tmp_path / "predicate",
        success=left_of_the_valley,
    )
    assert judged.eval["policies"]["final"]["mean_action"]["summary"]["reached"] == reached


def test_a_success_predicate_needs_a_python_env_and_a_bool():
    with pytest.raises(ValueError, match="give env= too"):
        logo_rl.train(PRESET, success=left_of_the_valley, progress=False)
    import gymnasium as gym

    env = logo_rl.Success(gym.make(TASK), lambda obs, info: obs)
    env.reset(seed=0)
    with pytest.raises(TypeError, match="expected a bool"):
        env.step(np.array([0.0]))
