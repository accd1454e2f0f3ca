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
