"""logo_rl.train on a Gymnasium env of the user's own (Python), with the user's own
demonstrations: a small env defined here trains end to end, resumes, and each kind of bad
input is a Python exception, the env's own one propagating."""

import gymnasium as gym
import numpy as np
import pytest
from gymnasium import spaces

import logo_rl
from conftest import IDP_CONFIG, ROOT, metrics_without_timings

GOAL = 1.0


class PointMass(gym.Env):
    """A unit mass on a line, pushed by a force in [-1, 1]; dense reward: minus the
    distance to the goal at x = 1."""

    def __init__(self, raise_after=None, nan_after=None):
        self.observation_space = spaces.Box(-np.inf, np.inf, (2,), np.float64)
        self.action_space = spaces.Box(-1.0, 1.0, (1,), np.float32)
        self.raise_after, self.nan_after, self.steps = raise_after, nan_after, 0

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.x, self.v = self.np_random.uniform(-0.1, 0.1), 0.0
        return np.array([self.x, self.v]), {"x_position": self.x}

    def step(self, action):
        self.steps += 1
        if self.raise_after is not None and self.steps > self.raise_after:
            raise RuntimeError(f"the robot's driver failed at step {self.steps}")
        force = float(np.clip(action[0], -1, 1))
        self.v += 0.05 * force
        self.x += 0.05 * self.v
        obs = np.array([self.x, self.v])
        if self.nan_after is not None and self.steps > self.nan_after:
            obs[1] = np.nan
        return obs, -abs(self.x - GOAL), False, False, {"x_position": self.x}


def sparse_point(**kwargs):
    env = gym.wrappers.TimeLimit(PointMass(**kwargs), max_episode_steps=100)
    return logo_rl.SparseReward(env, "distance", threshold=0.5, position=lambda e: e.unwrapped.x)


def controller_demos(episodes=5):
    """A proportional-derivative controller's trajectories: the user's own demonstrations."""
    trajectories = []
    for seed in range(episodes):
        env = sparse_point()
        obs, _ = env.reset(seed=seed)
        observations, actions = [obs], []
        for _ in range(100):
            action = np.clip([2.0 * (GOAL - obs[0]) - 3.0 * obs[1]], -1, 1)
            obs, *_ = env.step(action)
            observations.append(obs)
            actions.append(action)
        trajectories.append((np.array(observations), np.array(actions)))
    return trajectories


SMALL = dict(samples_per_iter=1000, eval_steps=200, tensorboard=False, progress=False)


def test_a_custom_env_trains_end_to_end_and_resumes(tmp_path):
    out = tmp_path / "point"
    template = ROOT / "configs" / "templates" / "new_task.toml"
    run = logo_rl.train(
        template, env=sparse_point, demos=controller_demos(), seed=0, iterations=2, out=out, **SMALL
    )
    rows = metrics_without_timings(run.path)
    assert len(rows) == 2
    # The run optimises the sparse reward and reports the dense one it hides.
    assert any(r["train_sparse_return"] != r["train_dense_return"] for r in rows)
    assert float(rows[-1]["train_dense_return"]) < 0  # minus a distance, every step
    assert (out / "demonstrations.npy").is_file() and run.eval is not None
    policy = logo_rl.load(run.checkpoint)
    assert policy.env_id == "python:sparse_point"
    assert policy.predict(np.zeros(2)).shape == (1,)
    resumed = logo_rl.train(resume=out, env=sparse_point, iterations=3, progress=False)
    assert len(metrics_without_timings(resumed.path)) == 3
    assert metrics_without_timings(resumed.path)[:2] == rows


def test_the_envs_own_exception_propagates_and_whole_iterations_are_kept(tmp_path):
    out = tmp_path / "raises"
    with pytest.raises(RuntimeError, match="driver failed at step") as raised:
        logo_rl.train(
            IDP_CONFIG, env=lambda: sparse_point(raise_after=2500), demos=controller_demos(),
            seed=0, iterations=5, num_envs=1, threads=1, out=out, **SMALL,
        )
    assert any(frame.name == "step" for frame in raised.traceback), "the env's frame is kept"
    # Iteration 1 is whole (the pipelined schedule collected batch 2 in it too, and batch
    # 3 raised in iteration 2): its checkpoint is there.
    rows = metrics_without_timings(out)
    assert len(rows) == 1 and (out / "checkpoint.safetensors").is_file()


def test_bad_envs_and_demos_are_python_exceptions(tmp_path):
    train = lambda **kw: logo_rl.train(IDP_CONFIG, seed=0, iterations=1, out=tmp_path / "x", **SMALL, **kw)  # noqa: E731
    with pytest.raises(TypeError, match="not an env instance"):
        train(env=sparse_point())
    with pytest.raises(TypeError, match="action space is Discrete"):
        train(env=lambda: gym.make("CartPole-v1"))
    with pytest.raises(ValueError, match="never ends an episode"):
        train(env=PointMass)
    with pytest.raises(ValueError, match=r"observation with nan at index 1"):
        train(env=lambda: sparse_point(nan_after=10), demos=controller_demos())
    with pytest.raises(ValueError, match=r"demos\[0\]: observations \(3, 5\)"):
        train(env=sparse_point, demos=[(np.zeros((3, 5)), np.zeros((2, 1)))])
    # The config's own demonstrations (IDP's: 11 + 1 dims) do not fit a 2 + 1 env.
    with pytest.raises(logo_rl.LogoError, match=r"dims \(11, 1\), expected the env's \(2, 1\)"):
        train(env=sparse_point)
    with pytest.raises(ValueError, match="demos= goes with env="):
        train(demos=controller_demos())
    # A run of logo-rl's own env resumes without env=.
    rust_run = logo_rl.train(IDP_CONFIG, seed=0, iterations=1, out=tmp_path / "rust", **SMALL)
    with pytest.raises(ValueError, match="not a run on a Python env"):
        logo_rl.train(resume=rust_run.path, env=sparse_point, progress=False)


def test_a_controllers_demonstrations_recorded_into_minari_train(tmp_path):
    import minari

    controller = lambda obs: np.clip([2.0 * (GOAL - obs[0]) - 3.0 * obs[1]], -1, 1)  # noqa: E731
    path = logo_rl.record(sparse_point, controller, episodes=4, path=tmp_path / "pd")
    dataset = minari.MinariDataset(path / "data")  # Python's minari reads it
    assert dataset.total_episodes == 4 and dataset.total_steps == 400
    run = logo_rl.train(
        IDP_CONFIG, env=sparse_point, demos=path, seed=1, iterations=1, out=tmp_path / "run", **SMALL
    )
    assert str(path) in run.config_path.read_text()
    # A trained policy records too (sampled actions, as LOGO's demonstrations).
    again = logo_rl.record(sparse_point, run.policy(), episodes=2, path=tmp_path / "logo")
    assert minari.MinariDataset(again / "data").total_episodes == 2
