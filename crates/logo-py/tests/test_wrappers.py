"""logo_rl.wrappers.SparseReward on Gymnasium's own Python envs pays as the Rust sparse
kinds do, from the same states and actions."""

import gymnasium as gym
import numpy as np
import pytest

import logo_rl
from logo_rl.wrappers import SparseReward


def compare(python_env, rust_id, rng, episodes, scale=1.0, max_steps=1000):
    """Both envs from the Python env's reset state, the same actions; returns the rewards."""
    rust = logo_rl.LogoEnv(rust_id, max_episode_steps=max_steps)
    paid = []
    for _ in range(episodes):
        python_env.reset(seed=int(rng.integers(1 << 31)))
        data = python_env.unwrapped.data
        qpos, qvel = data.qpos.copy(), data.qvel.copy()
        python_env.set_state(qpos, qvel)
        rust.reset(seed=0)
        rust.set_state(qpos, qvel)
        low, high = python_env.action_space.low, python_env.action_space.high
        while True:
            action = scale * rng.uniform(low, high).astype(np.float64)
            _, r, te, tr, info = python_env.step(action)
            _, rr, rte, rtr, rinfo = rust.step(action)
            assert (r, te, tr) == (rr, rte, rtr)
            assert info["dense_reward"] == rinfo["dense_reward"]
            paid.append(r)
            if te or tr:
                break
    return paid


def test_distance_pays_as_the_rust_kind():
    rng = np.random.default_rng(1)
    env = SparseReward(gym.make("HalfCheetah-v4", max_episode_steps=300), "distance", threshold=0.3)
    paid = compare(env, "HalfCheetah-v4+distance(0.3)", rng, episodes=4, max_steps=300)
    assert 0 < sum(paid) < len(paid), "the threshold was never, or always, passed"


def test_delayed_pays_as_the_rust_kind():
    rng = np.random.default_rng(2)
    env = SparseReward(gym.make("InvertedDoublePendulum-v4"), "delayed")
    paid = compare(env, "SparseInvertedDoublePendulum-v4", rng, episodes=5, scale=0.1)
    assert sum(r != 0 for r in paid) == 5


@pytest.mark.parametrize("env_id, radius", [("Reacher-v5", 0.1), ("Pusher-v5", 0.22)])
def test_goal_pays_as_the_rust_kind(env_id, radius):
    rng = np.random.default_rng(3)
    env = SparseReward(gym.make(env_id), "goal", radius=radius)
    limit = {"Reacher": 50, "Pusher": 100}[env_id.split("-")[0]]
    paid = compare(env, f"{env_id}+goal({radius})", rng, episodes=6, max_steps=limit)
    assert 0 < sum(paid) < len(paid), "the target was never, or always, within the radius"


def test_goal_reads_a_logo_rl_envs_goal_distance():
    # The wrapper over logo_rl's own Reacher pays as the Rust kind does, from its info.
    rng = np.random.default_rng(4)
    ours = SparseReward(gym.make("logo_rl/Reacher-v5"), "goal", radius=0.1)
    rust = logo_rl.LogoEnv("Reacher-v5+goal(0.1)")
    ours.reset(seed=3)
    rust.reset(seed=3)
    paid = []
    for _ in range(50):
        action = rng.uniform(-1, 1, size=2)
        _, r, *_ = ours.step(action)
        _, rr, *_ = rust.step(action)
        assert r == rr
        paid.append(r)
    assert 0 < sum(paid) < len(paid)


def test_bad_kinds_are_errors():
    env = gym.make("Hopper-v4")
    with pytest.raises(ValueError, match="unknown sparse kind 'walk'"):
        SparseReward(env, "walk")
    with pytest.raises(ValueError, match="positive finite radius"):
        SparseReward(gym.make("Reacher-v5"), "goal")
    with pytest.raises(ValueError, match="needs goal_distance="):
        SparseReward(env, "goal", radius=0.1)
    with pytest.raises(ValueError, match="takes no radius"):
        SparseReward(env, "distance", threshold=1, radius=0.1)
    with pytest.raises(ValueError, match="positive finite threshold"):
        SparseReward(env, "distance", threshold=-1)
    with pytest.raises(ValueError, match="takes no threshold"):
        SparseReward(env, "delayed", threshold=2)
    with pytest.raises(ValueError, match="needs position="):
        SparseReward(gym.make("CartPole-v1"), "distance", threshold=1)
