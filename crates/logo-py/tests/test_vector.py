"""LogoVectorEnv: Gymnasium's VectorEnv API over the Rust VecEnv, copy for copy the single
envs it is made of."""

import gymnasium as gym
import numpy as np
import pytest

import logo_rl
from logo_rl.vector import LogoVectorEnv


def test_each_copy_steps_as_a_single_env_with_same_step_autoreset():
    n, steps = 3, 400
    venv = LogoVectorEnv("SparseHopper-v4", n, threads=2)
    singles = [gym.make("logo_rl/SparseHopper-v4").unwrapped for _ in range(n)]
    obs, _ = venv.reset(seed=10)
    for i, env in enumerate(singles):
        np.testing.assert_array_equal(env.reset(seed=10 + i)[0], obs[i])
    rng = np.random.default_rng(0)
    ended = 0
    for _ in range(steps):
        actions = rng.uniform(-1, 1, (n, 3))
        obs, reward, term, trunc, info = venv.step(actions)
        for i, env in enumerate(singles):
            o, r, te, tr, inf = env.step(actions[i])
            assert (r, te, tr) == (reward[i], term[i], trunc[i])
            assert inf["dense_reward"] == info["dense_reward"][i]
            if te or tr:
                ended += 1
                assert info["_final_obs"][i] and info["final_info"]["_dense_reward"][i]
                np.testing.assert_array_equal(info["final_obs"][i], o)
                assert info["final_info"]["dense_reward"][i] == inf["dense_reward"]
                o, _ = env.reset()  # the copy went on from its own stream, as this one does
            np.testing.assert_array_equal(obs[i], o)
    assert ended > 3, "no episode ended: autoreset untested"


def test_spaces_and_errors():
    venv = LogoVectorEnv("Walker2d-v4", 4, threads=1)
    assert venv.observation_space.shape == (4, 17) and venv.action_space.shape == (4, 6)
    obs, _ = venv.reset(seed=0)
    assert obs.shape == (4, 17)
    with pytest.raises(ValueError, match=r"actions of shape \[4, 5\]"):
        venv.step(np.zeros((4, 5)))
    bad = np.zeros((4, 6))
    bad[2, 1] = np.inf
    with pytest.raises(logo_rl.LogoError, match="not finite"):
        venv.step(bad)
    with pytest.raises(logo_rl.LogoError, match="at least one copy"):
        LogoVectorEnv("Walker2d-v4", 0, threads=1)
    with pytest.raises(ValueError, match="a Python env is used as itself"):
        LogoVectorEnv("python:mine", 2, threads=1)
