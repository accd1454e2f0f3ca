"""logo_rl.load: a checkpoint's policy acts as `logo eval` does, and its weights are a
torch nn.Sequential's."""

import json

import gymnasium as gym
import numpy as np
import pytest

import logo_rl
from conftest import IDP_CONFIG, run_logo

FINAL_EVALUATION_SEED = 3_000_000  # + 1000 * run seed + episode (crates/logo-cli/src/final_eval.rs)


@pytest.fixture(scope="module")
def trained(tmp_path_factory):
    out = tmp_path_factory.mktemp("policy") / "run"
    return logo_rl.train(IDP_CONFIG, seed=2, iterations=4, out=out, tensorboard=False, progress=False)


def test_predicted_actions_play_logo_evals_episodes(trained, logo_bin):
    doc = json.loads(run_logo(logo_bin, "eval", "--checkpoint", str(trained.checkpoint), "--json"))
    episodes = doc["mean_action"]["episodes"]
    policy = logo_rl.load(trained.checkpoint)
    assert policy.seed == 2 and policy.iteration == 4
    env = gym.make(f"logo_rl/{doc['env']}").unwrapped
    for k, expected in enumerate(episodes):
        obs, _ = env.reset(seed=FINAL_EVALUATION_SEED + 1000 * policy.seed + k)
        ret = dense = 0.0
        length = 0
        while True:
            obs, reward, term, trunc, info = env.step(policy.predict(obs))
            ret += reward
            dense += info["dense_reward"]
            length += 1
            if term or trunc:
                break
        assert length == expected["length"]
        assert ret == pytest.approx(expected["return"], rel=1e-12, abs=1e-12)
        assert dense == pytest.approx(expected["dense_return"], rel=1e-12, abs=1e-12)


def test_state_dict_is_a_torch_sequential_of_the_same_function(trained):
    policy = trained.policy("final")
    state = policy.state_dict()
    assert [k for k in state if k.endswith("weight")] == ["0.weight", "2.weight", "4.weight"]
    assert state["0.weight"].shape == (policy.hidden[0], policy.obs_dim)
    rng = np.random.default_rng(0)
    obs = rng.normal(size=(17, policy.obs_dim))
    h = obs
    for i in (0, 2, 4):
        h = h @ state[f"{i}.weight"].T + state[f"{i}.bias"]
        if i < 4:
            h = np.tanh(h)
    np.testing.assert_allclose(h, policy.predict(obs), rtol=1e-12, atol=1e-12)
    # One observation in, one action out; sampled actions scatter around the mean.
    assert policy.predict(obs[0]).shape == (policy.act_dim,)
    sampled = policy.predict(np.repeat(obs[:1], 500, 0), deterministic=False, rng=rng)
    np.testing.assert_allclose(sampled.std(0), np.exp(policy.log_std), rtol=0.15)


def test_bad_observations_and_checkpoints_raise(trained, tmp_path):
    policy = logo_rl.load(trained.checkpoint)
    with pytest.raises(ValueError, match="observations of 3 values"):
        policy.predict(np.zeros(3))
    bad = np.zeros(policy.obs_dim)
    bad[4] = np.nan
    with pytest.raises(ValueError, match="row 0 has a non-finite value NaN at index 4"):
        policy.predict(bad)
    broken = tmp_path / "broken.safetensors"
    broken.write_bytes(b"not a checkpoint")
    with pytest.raises(logo_rl.LogoError, match="broken.safetensors"):
        logo_rl.load(broken)
