"""What a user gets wrong, said in Python's words: the recording's summary and reading it
back without minari, a missing demonstrations path, a reward that is not a number, a bad
keyword argument, a run folder already in use."""

import json

import gymnasium as gym
import numpy as np
import pytest

import logo_rl

TASK = "MountainCarContinuous-v0"


def pump(obs):
    return [1.0 if obs[1] >= 0 else -1.0]


def short(**kw):
    return dict(iterations=1, samples_per_iter=500, eval_steps=100, progress=False,
                tensorboard=False, **kw)


def test_record_returns_a_summary_and_logo_rl_reads_the_dataset_back(tmp_path):
    class Flag(gym.Wrapper):
        def step(self, action):
            obs, reward, terminated, truncated, info = self.env.step(action)
            return obs, reward, terminated, truncated, {**info, "is_success": bool(terminated)}

    rec = logo_rl.record(lambda: Flag(gym.make(TASK)), pump, 3, tmp_path / "demos")
    assert rec.episodes == 3 and rec.success_rate == 1.0
    data = logo_rl.read_dataset(rec)
    assert data.total_episodes == 3 and data.total_steps == rec.steps
    for episode, ret in zip(data.episodes, rec.returns):
        assert episode["observations"].shape == (len(episode["actions"]) + 1, 2)
        assert float(np.sum(episode["rewards"])) == pytest.approx(ret)
    meta = json.loads((tmp_path / "demos" / "data" / "metadata.json").read_text())
    assert meta["logo_recording"]["success_rate"] == 1.0
    assert meta["logo_recording"]["return_mean"] == pytest.approx(float(np.mean(rec.returns)))
    # The spaces as the env declares them: MountainCar's are float32 and bounded.
    space = json.loads(meta["observation_space"])
    assert space["dtype"] == "float32" and space["high"][1] == pytest.approx(0.07)
    # Without a goal the env reports, there is no success rate.
    plain = logo_rl.record(TASK, pump, 1, tmp_path / "plain")
    assert plain.success_rate is None
    with pytest.raises(FileNotFoundError, match="no-such-folder"):
        logo_rl.read_dataset(tmp_path / "no-such-folder")


def test_a_missing_demonstrations_path_is_a_file_not_found_error(tmp_path):
    for missing in (str(tmp_path / "nowhere"), "./nowhere", "nowhere-at-all"):
        with pytest.raises(FileNotFoundError, match="nowhere"):
            logo_rl.train("new-task", env=TASK, demos=missing, **short())


def test_a_reward_that_is_not_a_number_says_so(tmp_path):
    class ArrayReward(gym.Wrapper):
        def step(self, action):
            obs, reward, terminated, truncated, info = self.env.step(action)
            return obs, np.array([reward]), terminated, truncated, info

    with pytest.raises(TypeError, match="a reward is one number"):
        logo_rl.record(lambda: ArrayReward(gym.make(TASK)), pump, 1, tmp_path / "d")


def test_a_bad_keyword_argument_is_named_not_the_preset(tmp_path):
    with pytest.raises(logo_rl.LogoError, match="keyword arguments.*samples_per_iter"):
        logo_rl.train("trpo/inverted_double_pendulum", out=tmp_path / "r",
                      **{**short(), "samples_per_iter": "many"})


def test_errors_from_python_name_keyword_arguments_not_flags(tmp_path):
    logo_rl.train("trpo/inverted_double_pendulum", out=tmp_path / "run", **short())
    with pytest.raises(logo_rl.LogoError) as raised:
        logo_rl.train("trpo/inverted_double_pendulum", out=tmp_path / "run", **short())
    message = str(raised.value)
    assert "resume=" in message and "out=" in message, message
    assert "--resume" not in message and "--out" not in message, message


def test_errors_are_typed_python_exceptions_under_logo_error(tmp_path):
    """Each kind of mistake is the exception Python code raises for it, and a LogoError."""
    empty, damaged = tmp_path / "empty", tmp_path / "damaged"
    empty.mkdir()
    damaged.mkdir()
    (damaged / "checkpoint.safetensors").write_bytes(b"not a checkpoint")
    cases = [
        # A config file that is not there.
        (FileNotFoundError, logo_rl.LogoFileNotFoundError, "nothing.toml",
         lambda: logo_rl.train(tmp_path / "nothing.toml", progress=False)),
        # A value of the wrong type for its key.
        (TypeError, logo_rl.LogoTypeError, "invalid type",
         lambda: logo_rl.train("trpo/inverted_double_pendulum", out=tmp_path / "a",
                               **{**short(), "samples_per_iter": "many"})),
        # A value out of its range, and a key that does not exist.
        (ValueError, logo_rl.LogoValueError, "gamma",
         lambda: logo_rl.train("trpo/inverted_double_pendulum", out=tmp_path / "b",
                               **{**short(), "gamma": 2.0})),
        (ValueError, logo_rl.LogoValueError, "no_such_key",
         lambda: logo_rl.train("trpo/inverted_double_pendulum", out=tmp_path / "c",
                               **{**short(), "no_such_key": 1})),
        # A checkpoint that is not there, and an env id that does not exist.
        (FileNotFoundError, logo_rl.LogoFileNotFoundError, "missing.safetensors",
         lambda: logo_rl.load(tmp_path / "missing.safetensors")),
        (ValueError, logo_rl.LogoValueError, "unknown environment id",
         lambda: logo_rl.LogoEnv("Hopper-v9")),
        # The trainer's own: a run folder with nothing to resume is a missing file; a
        # checkpoint that is not one is a bad value.
        (FileNotFoundError, logo_rl.LogoFileNotFoundError, "no such checkpoint",
         lambda: logo_rl.train(resume=empty, progress=False)),
        (ValueError, logo_rl.LogoValueError, "not a safetensors file",
         lambda: logo_rl.train(resume=damaged, progress=False)),
        # The same damaged file read as a policy is the same kind of mistake.
        (ValueError, logo_rl.LogoValueError, "not a safetensors file",
         lambda: logo_rl.load(damaged / "checkpoint.safetensors")),
    ]
    for python_kind, logo_kind, words, call in cases:
        with pytest.raises(python_kind, match=words) as raised:
            call()
        assert isinstance(raised.value, logo_rl.LogoError), (words, type(raised.value))
        assert type(raised.value) is logo_kind, (words, type(raised.value))
    assert not any((tmp_path / name).exists() for name in "abc")


# Mistakes answered before any work is done, in the user's words: each of these failed
# late or unclearly before (the issue of a robot's task from Python).


class _OldGymReset(gym.Env):
    """An env on the old gym API: reset returns the observation alone, step four values."""

    observation_space = gym.spaces.Box(-1.0, 1.0, (2,), np.float64)
    action_space = gym.spaces.Box(-1.0, 1.0, (1,), np.float64)

    def __init__(self, new_reset=False):
        self.new_reset = new_reset

    def reset(self, *, seed=None, options=None):
        obs = np.zeros(2)
        return (obs, {}) if self.new_reset else obs

    def step(self, action):
        return np.zeros(2), 0.0, False, {}


def _limited(env, steps=20):
    def make():
        return gym.wrappers.TimeLimit(env(), steps)
    return make


def test_a_one_argument_success_predicate_is_refused_before_any_iteration(tmp_path):
    for call in (
        lambda: logo_rl.train("new-task", env=TASK, demos=None, success=lambda obs: obs[0] > 0.45,
                              out=tmp_path / "run", **short()),
        lambda: logo_rl.bc(tmp_path / "nowhere", env=TASK, success=lambda obs: True),
        lambda: logo_rl.record(TASK, pump, 1, tmp_path / "d", success=lambda obs: True),
    ):
        with pytest.raises(logo_rl.LogoTypeError, match=r"success=.*\(obs, info\)") as raised:
            call()
        assert isinstance(raised.value, TypeError)
    assert not (tmp_path / "run").exists() and not (tmp_path / "d").exists()


def test_an_env_on_the_old_gym_api_is_named_at_its_first_reset_and_step(tmp_path):
    with pytest.raises(logo_rl.LogoTypeError, match=r"reset returned .*\(obs, info\)"):
        logo_rl.record(_limited(_OldGymReset), pump, 1, tmp_path / "a")
    with pytest.raises(logo_rl.LogoTypeError, match=r"step returned 4 values.*five values"):
        logo_rl.record(_limited(lambda: _OldGymReset(new_reset=True)), pump, 1, tmp_path / "b")
    with pytest.raises(logo_rl.LogoTypeError, match=r"old gym API"):
        logo_rl.train("trpo/inverted_double_pendulum", env=_limited(_OldGymReset),
                      out=tmp_path / "c", **short())


def test_a_config_given_with_env_is_read_as_without_it(tmp_path):
    broken = tmp_path / "broken.toml"
    broken.write_text("samples_per_iter = 500\n[guidance\ndelta0 = 0.1\n")
    for path, kind, words in (
        (broken, logo_rl.LogoValueError, "broken.toml"),
        (tmp_path / "missing.toml", logo_rl.LogoFileNotFoundError, "missing.toml"),
    ):
        messages = []
        for env in (None, TASK):
            with pytest.raises(kind, match=words) as raised:
                logo_rl.train(path, env=env, progress=False)
            messages.append(str(raised.value))
        assert messages[0] == messages[1], messages


def test_a_controllers_action_of_the_wrong_size_is_refused_at_its_first_step(tmp_path):
    played = []

    def three(obs):
        played.append(obs)
        return [0.0, 0.0, 0.0]

    with pytest.raises(logo_rl.LogoValueError,
                       match=r"episode 0, step 0: the controller returned 3 .* has 1"):
        logo_rl.record(TASK, three, 5, tmp_path / "d")
    assert len(played) == 1


def test_an_action_space_without_width_is_refused(tmp_path):
    class Pinned(gym.Wrapper):
        def __init__(self, env):
            super().__init__(env)
            self.action_space = gym.spaces.Box(np.array([0.5]), np.array([0.5]), dtype=np.float64)

    with pytest.raises(logo_rl.LogoValueError, match="no width in dimension 0"):
        logo_rl.train("new-task", env=lambda: Pinned(gym.make(TASK)), guidance=None,
                      out=tmp_path / "r", **short())


def test_load_of_a_folder_lists_the_policy_files_it_holds(tmp_path):
    run = logo_rl.train("trpo/inverted_double_pendulum", out=tmp_path / "run", **short())
    with pytest.raises(logo_rl.LogoValueError,
                       match=r"is a folder.*best\.safetensors.*checkpoint\.safetensors"):
        logo_rl.load(run.path)
    with pytest.raises(logo_rl.LogoValueError, match="no policy file"):
        logo_rl.load(tmp_path)


def test_record_takes_the_success_predicate_train_takes(tmp_path):
    at_flag = lambda obs, info: obs[0] >= 0.45  # noqa: E731
    rec = logo_rl.record(TASK, pump, 2, tmp_path / "a", success=at_flag)
    assert rec.success_rate == 1.0
    rec = logo_rl.record(TASK, pump, 2, tmp_path / "b", success="terminated")
    assert rec.success_rate == 1.0
    rec = logo_rl.record(TASK, lambda obs: [0.0], 1, tmp_path / "c", success="terminated")
    assert rec.success_rate == 0.0
    with pytest.raises(logo_rl.LogoValueError, match="success='sometimes'"):
        logo_rl.record(TASK, pump, 1, tmp_path / "e", success="sometimes")


def test_errors_raised_in_rust_are_the_packages_own(tmp_path):
    run = logo_rl.train("trpo/inverted_double_pendulum", out=tmp_path / "run", **short())
    policy = logo_rl.load(run.checkpoint)
    with pytest.raises(logo_rl.LogoValueError) as raised:
        policy.predict(np.zeros(3))
    assert isinstance(raised.value, ValueError)
    with pytest.raises(logo_rl.LogoValueError):
        logo_rl.LogoEnv("InvertedDoublePendulum-v4").set_state(np.zeros(2), np.zeros(2))


def test_demonstrations_of_another_env_are_refused_naming_both(tmp_path):
    demos = logo_rl.record(TASK, pump, 2, tmp_path / "demos")

    class Wider(gym.Wrapper):
        """MountainCar's sizes, other observation bounds: another env."""

        def __init__(self, env):
            super().__init__(env)
            self.observation_space = gym.spaces.Box(-2.0, 2.0, (2,), np.float32)

    other = lambda: Wider(gym.make(TASK))  # noqa: E731
    for call in (
        lambda **kw: logo_rl.train("new-task", env=other, demos=demos, out=tmp_path / "r",
                                   **short(), **kw),
        lambda **kw: logo_rl.bc(demos, env=other, epochs=1, episodes=1,
                                out=tmp_path / "bc" / "p.safetensors", **kw),
    ):
        with pytest.raises(logo_rl.LogoValueError,
                           match=r"another env.*observation space Box\(low=\[-1\.2.*allow_other_env=True"):
            call()
        call(allow_other_env=True)  # trains anyway
    # A Gymnasium id recorded, another one in env= (same sizes and bounds).
    gym.register("logo_test/MountainCarAgain-v0",
                 entry_point="gymnasium.envs.classic_control:Continuous_MountainCarEnv",
                 max_episode_steps=999)
    with pytest.raises(logo_rl.LogoValueError, match="Gymnasium id MountainCarContinuous-v0"):
        logo_rl.train("new-task", env="logo_test/MountainCarAgain-v0", demos=demos,
                      out=tmp_path / "r2", **short())
    # Trajectories name no env: said once, with a warning.
    rows = [(np.zeros((5, 2)), np.zeros((5, 1)))]
    with pytest.warns(UserWarning, match="nothing in them says which env"):
        logo_rl.train("new-task", env=TASK, demos=rows, out=tmp_path / "r3", **short())
