"""The presets inside the package: run from a folder with no repository files, plain
TRPO as guidance=None."""

import csv
import tomllib

import pytest

import logo_rl


@pytest.fixture
def elsewhere(tmp_path, monkeypatch):
    """A working folder outside the repository, and a fresh cache for the presets."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("LOGO_RL_PRESETS", str(tmp_path / "presets"))
    return tmp_path


def rows(run):
    """metrics.csv's rows without the timings."""
    with open(run.path / "metrics.csv", newline="") as f:
        return [{k: v for k, v in r.items() if k != "wall_s" and not k.startswith("t_")}
                for r in csv.DictReader(f)]


def short(**kw):
    return dict(iterations=1, samples_per_iter=500, eval_steps=100, progress=False,
                tensorboard=False, **kw)


def test_presets_are_listed_with_what_they_are():
    listed = logo_rl.presets()
    for name in ("new-task", "logo/hopper", "trpo/inverted_double_pendulum", "logo-fast/walker2d"):
        assert listed.get(name), name


def test_a_paper_preset_runs_with_its_own_demonstrations_outside_the_repository(elsewhere):
    run = logo_rl.train("logo/inverted_double_pendulum", out=elsewhere / "run", **short())
    config = tomllib.loads((run.path / "config.toml").read_text())
    demos = config["guidance"]["demos"]
    assert demos.startswith(str(elsewhere / "presets")), demos
    assert len(rows(run)) == 1


def test_the_new_task_preset_takes_the_users_env_and_demonstrations(elsewhere):
    task = "MountainCarContinuous-v0"
    demos = logo_rl.record(task, lambda obs: [1.0 if obs[1] >= 0 else -1.0], 2, elsewhere / "demos")
    run = logo_rl.train("new-task", env=task, demos=demos, success="terminated",
                        out=elsewhere / "run", **short(eval_episodes=1))
    config = tomllib.loads((run.path / "config.toml").read_text())
    assert config["guidance"]["discriminator_steps"] == 10
    assert config["guidance"]["demos"] == str(elsewhere / "demos")


def test_a_name_that_is_no_preset_says_which_are(elsewhere):
    with pytest.raises(ValueError, match="is not a preset.*new-task"):
        logo_rl.train("new_task", **short())


def test_guidance_none_is_plain_trpo(elsewhere):
    trpo = logo_rl.train("trpo/inverted_double_pendulum", out=elsewhere / "trpo", seed=2, **short())
    plain = logo_rl.train("logo/inverted_double_pendulum", guidance=None, out=elsewhere / "plain",
                          seed=2, **short())
    assert "guidance" not in tomllib.loads((plain.path / "config.toml").read_text())
    # The LOGO config without its guidance is the TRPO config: the same numbers.
    assert rows(plain) == rows(trpo)
    with pytest.raises(ValueError, match="guidance=None"):
        logo_rl.train("logo/inverted_double_pendulum", guidance=None, env="Pendulum-v1",
                      demos="x", **short())


def test_the_table_of_methods_is_the_packages_list():
    """The package's presets and logo_rl.compare's methods come from the one table of
    methods (crates/logo-algo/src/methods.rs): LOGO from the clone is among both."""
    import importlib

    listed = logo_rl._logo_rl.methods()
    names = [name for name, *_ in listed]
    assert names[0] == "logo" and "bc" in names and len(names) == len(set(names))
    compare = importlib.import_module("logo_rl.compare")
    assert compare.METHODS == tuple(n for n, _, _, comparable in listed if comparable)
    assert "bc-logo" in compare.METHODS and "bc" not in compare.METHODS
    presets = logo_rl.presets()
    for name, *_ in listed:
        if name != "bc":
            assert f"{name}/hopper" in presets, name
