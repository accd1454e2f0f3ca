"""The built wheel in a fresh venv: `pip install` pulls in what it needs from PyPI, and the
envs work there, MuJoCo coming from the mujoco wheel (no set-up step)."""

import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from conftest import ROOT

CHECK = textwrap.dedent(
    """
    import gymnasium as gym, numpy as np
    from gymnasium.utils.env_checker import check_env
    import logo_rl
    env = gym.make("logo_rl/SparseHopper-v4")
    check_env(env.unwrapped, skip_render_check=True)
    ours, theirs = gym.make("logo_rl/Hopper-v4"), gym.make("Hopper-v4")
    theirs.reset(seed=1)
    ours.reset()
    ours.unwrapped.set_state(theirs.unwrapped.data.qpos.copy(), theirs.unwrapped.data.qvel.copy())
    rng = np.random.default_rng(0)
    for _ in range(100):
        a = rng.uniform(-1, 1, 3)
        x, y = ours.step(a), theirs.step(a)
        assert np.array_equal(x[0], y[0]) and x[1:4] == y[1:4], (x, y)
        if x[2]:
            break
    print("ok", logo_rl.__file__)
    """
)


def test_the_wheel_installs_and_runs_in_a_fresh_venv(tmp_path):
    wheels = sorted((ROOT / "target" / "wheels").glob("logo_rl-*.whl"))
    if not wheels:
        pytest.fail("no wheel in target/wheels: ./scripts/setup.sh builds it")
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    python = venv / "bin" / "python"
    pip = subprocess.run(
        [str(python), "-m", "pip", "install", "--quiet", "--disable-pip-version-check", str(wheels[-1])],
        capture_output=True, text=True,
    )
    assert pip.returncode == 0, f"pip install of {wheels[-1].name} failed:\n{pip.stderr}"
    # Away from the checkout, with no variable of the project's set.
    done = subprocess.run(
        [str(python), "-c", CHECK], capture_output=True, text=True, cwd=tmp_path,
        env={"PATH": "/usr/bin:/bin", "HOME": str(Path.home())},
    )
    assert done.returncode == 0, done.stderr
    assert str(venv) in done.stdout
