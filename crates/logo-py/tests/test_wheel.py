"""The distribution wheel (scripts/wheel.sh) as a user elsewhere gets it: a manylinux tag
that auditwheel stands behind, no path of the machine that built it, and in a fresh venv
away from the checkout `pip install` pulls in what it needs from PyPI and the envs and
`train("new-task", ...)` work there, MuJoCo coming from the mujoco wheel."""

import json
import os
import subprocess
import sys
import textwrap
import zipfile
from pathlib import Path

import pytest
from elftools.elf.dynamic import DynamicSection
from elftools.elf.elffile import ELFFile

from conftest import ROOT

TAG = "manylinux_2_35_x86_64"
# Loaded from the mujoco wheel, which the package depends on (pyproject.toml).
MUJOCO = "libmujoco.so.3.17.0"


@pytest.fixture(scope="module")
def wheel() -> Path:
    wheels = sorted((ROOT / "dist").glob("logo_rl-*.whl"))
    if not wheels:
        pytest.fail("no wheel in dist/: ./scripts/wheel.sh builds it")
    return wheels[-1]


@pytest.fixture(scope="module")
def extension(wheel, tmp_path_factory) -> Path:
    """The wheel's compiled module, unpacked."""
    out = tmp_path_factory.mktemp("unpacked")
    with zipfile.ZipFile(wheel) as z:
        (name,) = [n for n in z.namelist() if n.endswith(".so")]
        z.extract(name, out)
    return out / name


def test_auditwheel_finds_the_wheel_manylinux_2_35(wheel):
    assert wheel.name.endswith(f"-cp310-abi3-{TAG}.whl"), wheel.name
    shown = subprocess.run(
        [str(ROOT / ".venv" / "bin" / "auditwheel"), "show", "--json", str(wheel)],
        capture_output=True, text=True,
    )
    assert shown.returncode == 0, shown.stderr
    report = json.loads(shown.stdout)
    # The symbol versions it uses from the system (glibc, libgcc, libm) allow manylinux_2_35,
    # and no library outside the policy is linked: auditwheel's verdict is the tag itself.
    assert report["sym_tag"] == TAG, report["sym_tag"]
    assert report["external_libs"] == {}, report["external_libs"]
    assert report["overall_tag"] == TAG, report["overall_tag"]


def test_the_extension_keeps_no_path_of_the_build_machine(extension):
    data = extension.read_bytes()
    here = {
        "the checkout": str(ROOT),
        "the target folder": str((ROOT / os.environ.get("CARGO_TARGET_DIR", "target")).resolve()),
        "cargo's home": str(Path(os.environ.get("CARGO_HOME", Path.home() / ".cargo")).resolve()),
    }
    for what, path in here.items():
        found = path.encode() in data
        assert not found, f"{extension.name} holds {what}, {path}"
    # `strings` would see the same: the needles are printable and longer than 4 bytes.
    with extension.open("rb") as f:
        dynamic = next(s for s in ELFFile(f).iter_sections() if isinstance(s, DynamicSection))
        paths = [t.runpath for t in dynamic.iter_tags("DT_RUNPATH")]
        paths += [t.rpath for t in dynamic.iter_tags("DT_RPATH")]
        needed = [t.needed for t in dynamic.iter_tags("DT_NEEDED")]
    # MuJoCo is not linked by name or found by path: logo_rl/__init__.py loads the mujoco
    # wheel's copy before the extension (the fresh-venv test below shows that it works).
    assert paths == [], paths
    assert MUJOCO not in needed, needed


USE = textwrap.dedent(
    """
    import sys
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
    # A user's own task: demonstrations recorded here, LOGO's new-task preset on them.
    task = "MountainCarContinuous-v0"
    demos = logo_rl.record(task, lambda obs: [1.0 if obs[1] >= 0 else -1.0], 2, "demos")
    run = logo_rl.train("new-task", env=task, demos=demos, success="terminated", out="run",
                        iterations=1, samples_per_iter=500, eval_steps=100, eval_episodes=1,
                        progress=False, tensorboard=False)
    assert (run.path / "metrics.csv").is_file()
    assert (run.path / "checkpoint.safetensors").is_file()
    print("ok", logo_rl.__file__)
    """
)


def test_the_wheel_installs_and_trains_in_a_fresh_venv(wheel, tmp_path):
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    python = venv / "bin" / "python"
    pip = subprocess.run(
        [str(python), "-m", "pip", "install", "--quiet", "--disable-pip-version-check", str(wheel)],
        capture_output=True, text=True,
    )
    assert pip.returncode == 0, f"pip install of {wheel.name} failed:\n{pip.stderr}"
    # Away from the checkout, with no variable of the project's set.
    done = subprocess.run(
        [str(python), "-c", USE], capture_output=True, text=True, cwd=tmp_path,
        env={"PATH": "/usr/bin:/bin", "HOME": str(Path.home())},
    )
    assert done.returncode == 0, done.stderr
    assert str(venv) in done.stdout
