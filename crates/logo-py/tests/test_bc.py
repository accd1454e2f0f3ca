"""logo_rl.bc: behaviour cloning from Python, on logo-rl's envs and on a Gymnasium env of
the user's own, and a BC-TRPO preset."""

import json

import numpy as np
import pytest

import logo_rl
from conftest import ROOT

IDP = "SparseInvertedDoublePendulum-v4"


@pytest.fixture
def idp_demos():
    return ROOT / "data/logo/inverted_double_pendulum"


def test_bc_on_a_logo_env_writes_a_policy_that_load_reads(tmp_path, idp_demos):
    cloned = logo_rl.bc(idp_demos, env=IDP, out=tmp_path / "bc.safetensors", epochs=5,
                        hidden=(16, 16), episodes=2)
    assert cloned.path.is_file()
    assert cloned.pairs == 183
    assert cloned.loss_after < cloned.loss_before
    assert cloned.success_rate is None  # the delayed reward defines no goal
    policy = cloned.policy
    assert policy.algorithm == "bc" and policy.hidden == [16, 16]
    action = policy.predict(np.zeros(policy.obs_dim))
    assert action.shape == (policy.act_dim,)
    # The same call twice: the same policy.
    again = logo_rl.bc(idp_demos, env=IDP, out=tmp_path / "again.safetensors", epochs=5,
                       hidden=(16, 16), episodes=2)
    np.testing.assert_array_equal(again.policy.log_std, policy.log_std)


def test_bc_on_a_gymnasium_env_of_ones_own(tmp_path):
    # Pendulum's demonstrations from a proportional controller, as trajectories.
    import gymnasium as gym

    env = gym.make("Pendulum-v1")
    trajectories = []
    for seed in range(3):
        obs, _ = env.reset(seed=seed)
        observations, actions = [], []
        for _ in range(50):
            action = np.clip([-2.0 * obs[2]], -2.0, 2.0)
            observations.append(obs)
            actions.append(action)
            obs, *_ = env.step(action)
        trajectories.append((np.array(observations), np.array(actions)))
    cloned = logo_rl.bc(trajectories, env="Pendulum-v1", out=tmp_path / "p.safetensors",
                        epochs=20, hidden=(8,), episodes=1)
    assert cloned.pairs == 150
    assert cloned.loss_after < cloned.loss_before
    assert cloned.evaluation["mean_action"]["summary"]["length"] == 200
    # Pendulum reports no success of its own, and never terminates.
    assert cloned.success_rate is None
    kept = json.loads(cloned.evaluation_path.read_text())
    assert cloned.evaluation_path == tmp_path / "p.eval.json"
    assert kept["policies"]["final"]["mean_action"] == cloned.evaluation["mean_action"]
    terminated = logo_rl.bc(trajectories, env="Pendulum-v1", out=tmp_path / "t.safetensors",
                            epochs=20, hidden=(8,), episodes=2, success="terminated")
    assert terminated.success_rate == 0.0
    # A predicate of one's own: upright (cos θ > 0.9) at some step; recorded per episode.
    upright = logo_rl.bc(trajectories, env="Pendulum-v1", out=tmp_path / "u.safetensors",
                         epochs=20, hidden=(8,), episodes=2,
                         success=lambda obs, info: bool(obs[0] > 0.9))
    never = logo_rl.bc(trajectories, env="Pendulum-v1", out=tmp_path / "n.safetensors",
                       epochs=20, hidden=(8,), episodes=2, success=lambda obs, info: False)
    assert never.success_rate == 0.0
    assert upright.success_rate is not None
    assert [e["reached"] for e in never.evaluation["mean_action"]["episodes"]] == [False, False]


def test_bad_bc_arguments_are_python_errors(tmp_path, idp_demos):
    with pytest.raises(ValueError, match="epochs=0"):
        logo_rl.bc(idp_demos, env=IDP, epochs=0)
    with pytest.raises(TypeError, match="hidden"):
        logo_rl.bc(idp_demos, env=IDP, hidden=("16",))
    with pytest.raises(ValueError, match="success=.*expected task, terminated or none"):
        logo_rl.bc(idp_demos, env=IDP, success="always", out=tmp_path / "s.safetensors")
    with pytest.raises(ValueError, match="logo-rl's own env"):
        logo_rl.bc(idp_demos, env=IDP, success=lambda obs, info: True)
    with pytest.raises(FileNotFoundError, match="no_such"):
        logo_rl.bc(tmp_path / "no_such", env=IDP)
    with pytest.raises(logo_rl.LogoError, match="act"):
        # Hopper's demonstrations do not fit IDP.
        logo_rl.bc(idp_demos.parent / "hopper", env=IDP, out=tmp_path / "x.safetensors")


def test_the_bc_trpo_preset_clones_then_trains(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("LOGO_RL_PRESETS", str(tmp_path / "presets"))
    assert "bc-trpo/hopper" in logo_rl.presets()
    lines = []
    run = logo_rl.train("bc-trpo/inverted_double_pendulum", out=tmp_path / "run", iterations=1,
                        samples_per_iter=500, eval_steps=100, progress=lines.append,
                        tensorboard=False, init={"epochs": 2})
    assert any("started from behaviour cloning on 183 pairs" in line for line in lines), lines
    assert (run.path / "bc.json").is_file()
