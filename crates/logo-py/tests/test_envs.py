"""logo_rl's envs through Gymnasium: the env checker, bit parity with Gymnasium's own
MuJoCo envs, the project's seeded resets, rendering, and errors on bad input."""

import os

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import logo_rl

DENSE = [i for i in logo_rl.env_ids() if not i.startswith("Sparse")]
SPARSE = [i for i in logo_rl.env_ids() if i.startswith("Sparse")]


def test_every_env_of_logo_envs_is_registered_and_passes_the_env_checker():
    assert len(DENSE) == 21 and len(SPARSE) == 8
    for env_id in logo_rl.env_ids():
        env = gym.make(f"logo_rl/{env_id}")
        # Gymnasium's own registered limits.
        limit = {"Reacher": 50, "Pusher": 100}.get(env_id.split("-")[0], 1000)
        assert env.spec.max_episode_steps == limit
        check_env(env.unwrapped, skip_render_check=True)
        env.close()


def play_both(env_id: str, steps: int, rng: np.random.Generator):
    """Gymnasium's env and logo_rl's, from Gymnasium's reset state, with the same float64
    actions; yields each step's pair until either episode ends."""
    ours = gym.make(f"logo_rl/{env_id}")
    theirs = gym.make(env_id.removeprefix("Sparse"))
    theirs.reset(seed=int(rng.integers(1 << 31)))
    ours.reset(seed=0)
    data = theirs.unwrapped.data
    qpos, qvel = data.qpos.copy(), data.qvel.copy()
    ours.unwrapped.set_state(qpos, qvel)
    np.testing.assert_array_equal(ours.unwrapped.state_vector(), theirs.unwrapped.state_vector())
    low, high = theirs.action_space.low, theirs.action_space.high
    for _ in range(steps):
        # A little outside the control range too: both must clamp alike.
        action = rng.uniform(1.2 * low, 1.2 * high).astype(np.float64)
        a = ours.step(action)
        b = theirs.step(action)
        yield a, b
        if a[2] or a[3] or b[2] or b[3]:
            return


@pytest.mark.parametrize("env_id", DENSE)
def test_dense_envs_step_bit_identically_to_gymnasium(env_id):
    rng = np.random.default_rng(7)
    steps = episodes = 0
    # Episodes until 300 steps are compared (random actions drop the pendulum in ~10).
    while steps < 300:
        for (obs, reward, term, trunc, info), (g_obs, g_reward, g_term, g_trunc, _) in play_both(
            env_id, 300, rng
        ):
            np.testing.assert_array_equal(obs, g_obs)
            assert reward == g_reward and info["dense_reward"] == g_reward
            assert (term, trunc) == (g_term, g_trunc)
            steps += 1
        episodes += 1
    assert episodes < 100


def test_a_whole_episode_ends_truncated_at_the_same_step_as_gymnasium():
    # HalfCheetah never terminates: its episodes end by the time limit alone.
    rng = np.random.default_rng(3)
    pairs = list(play_both("HalfCheetah-v4", 1001, rng))
    assert len(pairs) == 1000
    (_, _, term, trunc, _), (_, _, g_term, g_trunc, _) = pairs[-1]
    assert (term, trunc) == (g_term, g_trunc) == (False, True)


@pytest.mark.parametrize("env_id", SPARSE)
def test_sparse_envs_report_gymnasiums_dense_reward_beside_their_own(env_id):
    rng = np.random.default_rng(11)
    paid = []
    for (obs, reward, term, trunc, info), (g_obs, g_reward, g_term, g_trunc, _) in play_both(
        env_id, 1000, rng
    ):
        np.testing.assert_array_equal(obs, g_obs)
        assert info["dense_reward"] == g_reward
        assert (term, trunc) == (g_term, g_trunc)
        paid.append(reward)
    # Sparse: most steps pay nothing.
    assert sum(r == 0.0 for r in paid) > len(paid) // 2


@pytest.mark.parametrize("limit", [50, 1200])
def test_gymnasium_makes_time_limit_ends_the_episodes(limit):
    env = gym.make("logo_rl/HalfCheetah-v4", max_episode_steps=limit)  # never terminates
    env.reset(seed=0)
    for step in range(1, limit + 1):
        *_, terminated, truncated, _ = env.step(np.zeros(6))
        assert not terminated and truncated == (step == limit)


def test_seeded_resets_follow_the_projects_own_stream():
    env = gym.make("logo_rl/Hopper-v4")
    first, _ = env.reset(seed=5)
    again, _ = env.reset(seed=5)
    other, _ = env.reset(seed=6)
    np.testing.assert_array_equal(first, again)
    assert not np.array_equal(first, other)
    # The stream is ChaCha8's, not NumPy's: Gymnasium's env draws other states.
    theirs, _ = gym.make("Hopper-v4").reset(seed=5)
    assert not np.array_equal(first, theirs)
    # The same states as the Rust env of that seed, which `logo train` resets.
    rust = logo_rl._logo_rl.RustEnv("Hopper-v4")
    np.testing.assert_array_equal(rust.reset(5), first)


def test_rgb_array_frames():
    env = gym.make("logo_rl/Hopper-v4", render_mode="rgb_array", width=96, height=64)
    env.reset(seed=0)
    try:
        frame = env.render()
    except logo_rl.LogoError as e:
        # scripts/test.sh installs Mesa's EGL; on CI (LOGO_REQUIRE_VIDEO) it must be there.
        if os.environ.get("LOGO_REQUIRE_VIDEO"):
            raise
        pytest.skip(f"no offscreen OpenGL here: {e}")
    assert frame.shape == (64, 96, 3) and frame.dtype == np.uint8
    assert frame.std() > 0, "a blank frame"
    # Gymnasium's checker, its render check included.
    check_env(gym.make("logo_rl/SparseHopper-v4", render_mode="rgb_array").unwrapped)


def test_bad_input_raises_python_exceptions_naming_it():
    env = gym.make("logo_rl/Hopper-v4").unwrapped
    env.reset(seed=0)
    with pytest.raises(ValueError, match="action of 2 values; Hopper-v4 takes 3"):
        env.step(np.zeros(2))
    with pytest.raises(logo_rl.LogoError, match="not finite"):
        env.step(np.array([0.0, np.nan, 0.0]))
    with pytest.raises(ValueError, match="qpos has 2 values"):
        env.set_state(np.zeros(2), np.zeros(6))
    with pytest.raises(logo_rl.LogoError, match="unknown environment id"):
        logo_rl.LogoEnv("Hopper-v9")
    with pytest.raises(ValueError, match="rgb_array"):
        logo_rl.LogoEnv("Hopper-v4", render_mode="human")
    with pytest.raises(ValueError, match="a Python env is used as itself"):
        logo_rl.LogoEnv("python:mine")
    # The env is still usable after each error.
    obs, *_ = env.step(np.zeros(3))
    assert np.all(np.isfinite(obs))


def test_max_episode_steps_is_the_tasks_none_or_a_number():
    assert logo_rl.LogoEnv("Reacher-v5")._env.max_episode_steps == 50
    assert logo_rl.LogoEnv("Reacher-v5", max_episode_steps=7)._env.max_episode_steps == 7
    with pytest.raises(ValueError, match="expected 'task', None or a number"):
        logo_rl.LogoEnv("Hopper-v4", max_episode_steps="forever")
    venv = logo_rl.LogoVectorEnv("Pusher-v5", num_envs=2, threads=1)
    venv.reset(seed=0)
    for step in range(1, 101):
        *_, truncated, _ = venv.step(np.zeros((2, 7)))
        assert truncated.all() == (step == 100)
