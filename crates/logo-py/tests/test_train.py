"""logo_rl.train runs `logo train`'s job in this process: the same metrics, a dict config,
overrides, Ctrl-C with an exact resume, and errors as Python exceptions."""

import os
import re
import signal
import subprocess
import sys
import textwrap
import tomllib

import numpy as np
import pytest

import logo_rl
from conftest import IDP_CONFIG, ROOT, metrics_without_timings, run_logo

ITERATIONS = 6


@pytest.fixture(scope="module")
def cli_run(tmp_path_factory, logo_bin):
    out = tmp_path_factory.mktemp("cli") / "run"
    run_logo(
        logo_bin, "train", "--config", str(IDP_CONFIG), "--seed", "3",
        "--iterations", str(ITERATIONS), "--out", str(out), "--no-tensorboard",
    )
    return out


def test_train_writes_the_metrics_of_logo_train(cli_run, tmp_path):
    lines = []
    # NumPy integers and paths are taken as TOML values.
    run = logo_rl.train(
        IDP_CONFIG, seed=np.int64(3), iterations=ITERATIONS, out=tmp_path / "py",
        tensorboard=False, progress=lines.append,
    )
    assert metrics_without_timings(run.path) == metrics_without_timings(cli_run)
    assert sum(line.startswith("[") for line in lines) == ITERATIONS
    assert run.eval is not None and set(run.eval["policies"]) <= {"final", "best"}
    metrics = run.metrics
    assert len(metrics["iteration"]) == ITERATIONS


def test_a_dict_config_trains_as_its_file(cli_run, tmp_path):
    config = tomllib.loads(IDP_CONFIG.read_text())
    # Relative paths of a dict are the working directory's.
    config["guidance"]["demos"] = str(IDP_CONFIG.parent / config["guidance"]["demos"])
    config.update(seed=3, iterations=ITERATIONS)
    run = logo_rl.train(config, out=tmp_path / "dict", tensorboard=False, progress=False)
    assert metrics_without_timings(run.path) == metrics_without_timings(cli_run)


def test_overrides_change_the_config_and_tables_merge(tmp_path):
    run = logo_rl.train(
        IDP_CONFIG, seed=1, iterations=2, samples_per_iter=1000,
        guidance={"delta0": 0.05}, out=tmp_path / "o", tensorboard=False, progress=False,
    )
    saved = tomllib.loads(run.config_path.read_text())
    assert saved["samples_per_iter"] == 1000 and saved["guidance"]["delta0"] == 0.05
    # The rest of the guidance table is the file's.
    assert saved["guidance"]["demos"].endswith("inverted_double_pendulum")
    assert len(metrics_without_timings(run.path)) == 2


# Trains until Ctrl-C, then exits 130. With "self" it sends itself SIGINT from its progress
# callback at iteration 2; with "outside" the signal comes from the test, as a terminal's.
INTERRUPTIBLE = textwrap.dedent(
    """
    import os, signal, sys
    import logo_rl
    def say(line):
        print(line, flush=True)
        if line.startswith("[   2/"):
            os.kill(os.getpid(), signal.SIGINT)
    progress = say if sys.argv[4] == "self" else True
    try:
        logo_rl.train(sys.argv[1], seed=3, iterations=int(sys.argv[3]), out=sys.argv[2],
                      tensorboard=False, progress=progress)
    except KeyboardInterrupt:
        print("KeyboardInterrupt", flush=True)
        sys.exit(130)
    """
)


def test_ctrl_c_keeps_a_checkpoint_that_resumes_exactly(cli_run, tmp_path):
    out = tmp_path / "interrupted"
    done = subprocess.run(
        [sys.executable, "-c", INTERRUPTIBLE, str(IDP_CONFIG), str(out), str(ITERATIONS), "self"],
        capture_output=True, text=True, cwd=ROOT, timeout=600,
    )
    assert done.returncode == 130, done.stdout + done.stderr
    assert "stopped after iteration 2" in done.stderr
    assert len(metrics_without_timings(out)) == 2
    assert (out / "checkpoint.safetensors").is_file()
    run = logo_rl.train(resume=out, progress=False)
    assert metrics_without_timings(run.path) == metrics_without_timings(cli_run)


def test_ctrl_c_while_rust_computes_stops_after_the_iteration(cli_run, tmp_path):
    # SIGINT from outside, as a terminal's Ctrl-C: Python sees it when the trainer asks
    # between iterations (the GIL is released while Rust computes).
    out = tmp_path / "sigint"
    child = subprocess.Popen(
        [sys.executable, "-u", "-c", INTERRUPTIBLE, str(IDP_CONFIG), str(out), str(ITERATIONS),
         "outside"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT,
    )
    for line in child.stdout:
        if line.startswith("[   2/"):
            child.send_signal(signal.SIGINT)
            break
    stdout, stderr = child.communicate(timeout=600)
    assert child.returncode == 130, stdout + stderr
    stopped = re.search(r"stopped after iteration (\d+)", stderr)
    assert stopped, stderr
    kept = int(stopped.group(1))
    assert 2 <= kept < ITERATIONS
    assert len(metrics_without_timings(out)) == kept
    run = logo_rl.train(resume=out, progress=False)
    assert metrics_without_timings(run.path) == metrics_without_timings(cli_run)


def test_bad_input_is_a_python_exception(tmp_path):
    with pytest.raises(logo_rl.LogoError, match="samples_per_iter"):
        logo_rl.train(IDP_CONFIG, samples_per_iter=0, out=tmp_path / "a", progress=False)
    with pytest.raises(logo_rl.LogoError, match="unknown field `no_such_key`"):
        logo_rl.train(IDP_CONFIG, no_such_key=1, out=tmp_path / "b", progress=False)
    with pytest.raises(logo_rl.LogoError, match="nothing.toml"):
        logo_rl.train(tmp_path / "nothing.toml", progress=False)
    with pytest.raises(ValueError, match="dtype=\"f16\": expected one of f64, f32"):
        logo_rl.train(IDP_CONFIG, dtype="f16", out=tmp_path / "c", progress=False)
    with pytest.raises(ValueError, match="drop config"):
        logo_rl.train(IDP_CONFIG, resume=tmp_path / "c")
    with pytest.raises(logo_rl.LogoError, match="resume="):
        logo_rl.train(resume=tmp_path / "no-run", progress=False)
    with pytest.raises(TypeError, match="not a TOML value"):
        logo_rl.train(IDP_CONFIG, seed=object(), out=tmp_path / "d", progress=False)
    assert not (tmp_path / "a").exists() and not (tmp_path / "b").exists()
