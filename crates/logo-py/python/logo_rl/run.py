"""``logo_rl.train``: ``logo train`` from Python, in this process."""

from __future__ import annotations

import csv
import json
import os
from pathlib import Path
from typing import Any, Callable, Mapping

import numpy as np

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib

from ._errors import LogoFileNotFoundError, LogoTypeError, LogoValueError
from . import _logo_rl
from .custom import PREFIX, check_demos_env, demos_path, prepare
from .policy import Policy
from .presets import preset_path
from .wrappers import judged


class Run:
    """A run folder: what ``logo train`` writes, read back."""

    def __init__(self, path: str | os.PathLike):
        self.path = Path(path)
        if not (self.path / "metrics.csv").is_file():
            raise LogoFileNotFoundError(f"{self.path}: no metrics.csv (not a logo-rl run folder)")

    def __repr__(self) -> str:
        return f"Run({str(self.path)!r})"

    checkpoint = property(lambda self: self.path / "checkpoint.safetensors")
    best = property(
        lambda self: self.path / "best.safetensors",
        doc="The policy of the latest iteration whose evaluation reached the highest return.",
    )
    config_path = property(lambda self: self.path / "config.toml")

    @property
    def metrics(self):
        """``metrics.csv``'s columns: a pandas DataFrame where pandas is installed, else a
        dict of NumPy arrays (numbers as float64, others as strings)."""
        try:
            import pandas
        except ImportError:
            pandas = None
        if pandas is not None:
            return pandas.read_csv(self.path / "metrics.csv")
        with open(self.path / "metrics.csv", newline="") as f:
            rows = list(csv.DictReader(f))
        columns = {}
        for key in rows[0].keys() if rows else []:
            values = [row[key] for row in rows]
            try:
                columns[key] = np.array([float(v) for v in values])
            except ValueError:
                columns[key] = np.array(values)
        return columns

    @property
    def eval(self) -> dict[str, Any] | None:
        """``eval.json``: the final and the best policy over fresh episodes (None until the
        run has ended)."""
        path = self.path / "eval.json"
        return json.loads(path.read_text()) if path.is_file() else None

    def policy(self, which: str = "final") -> Policy:
        """The run's ``final`` (checkpoint) or ``best`` policy."""
        files = {"final": self.checkpoint, "best": self.best}
        if which not in files:
            raise LogoValueError(f"which={which!r}: expected 'final' or 'best'")
        return Policy(files[which])


def train(
    config: str | os.PathLike | Mapping[str, Any] | None = None,
    *,
    env: str | Callable[[], Any] | None = None,
    demos: Any = None,
    out: str | os.PathLike | None = None,
    resume: str | os.PathLike | None = None,
    iterations: int | None = None,
    engine: str | None = None,
    backend: str | None = None,
    dtype: str | None = None,
    tensorboard: bool = True,
    progress: bool | Callable[[str], None] = True,
    allow_other_env: bool = False,
    **overrides: Any,
) -> Run:
    """Trains as ``logo train --config CONFIG`` does and returns the :class:`Run`.

    ``config``: a preset's name (``"new-task"``, ``"logo/hopper"``: :func:`logo_rl.presets`
    lists them; no repository needed), a TOML file, or a dict of the same keys (its
    relative paths are taken from the working directory); every key: docs/config.md. ``overrides`` replace the config's keys
    (``seed=3``, ``samples_per_iter=2000``); a dict value is laid over the config's table
    of that name key by key (``guidance={"delta0": 0.1}``); ``guidance=None`` takes LOGO's
    guidance out, leaving the improvement step alone (plain TRPO from a LOGO config). ``resume``: continue the run
    in that folder instead (``iterations`` may extend it). ``engine``, ``backend``,
    ``dtype``: as ``logo train``'s flags. ``progress``: print each iteration's line
    (True), stay quiet (False) or hand each line to a callable.

    ``env``: train on a Gymnasium env of your own instead of the config's: its id, or a
    callable returning a new one (flat Box spaces, a time limit). The Rust sampler steps
    it, holding the GIL only around its ``reset`` and ``step``; the run optimises and
    evaluates its own reward, and reports ``info["dense_reward"]`` beside it where a
    wrapper (:class:`logo_rl.SparseReward`) made it sparse. ``demos``: the demonstrations,
    a Minari dataset (its folder, its local id, or the dataset), a ``.npy`` of LOGO's
    ``[observation ‖ action]`` rows, or a list of ``(observations, actions)``
    trajectories (written into the run folder); None keeps the config's. A Minari
    dataset's recorded spaces (and Gymnasium id, where both sides have one) must be the
    env's: demonstrations of another env are refused, unless ``allow_other_env=True``.

    ``success``: which episodes reached the goal, counted in ``eval.json`` and read by
    ``[guidance] decay_on = "success"``. ``"task"`` (the env's ``info["is_success"]``, or
    a sparse kind's goal), ``"terminated"`` (a task that stops at its goal), ``"none"``,
    or a callable ``(obs, info) -> bool`` judging each step of ``env=`` (it wraps the env
    in :class:`logo_rl.Success`; an episode reached the goal if any step did).

    Ctrl-C stops the run after the iteration in progress; the run folder then holds that
    iteration's checkpoint (``train(resume=run.path)`` goes on, exactly as the run would
    have, for logo-rl's envs; a Python env's own state is not saved, so its copies start
    new episodes there) and KeyboardInterrupt is raised. An exception of a Python env
    stops the run the same way and is raised again, with its traceback.
    """
    if progress is True:
        say = lambda line: print(line, flush=True)  # noqa: E731
    elif progress is False:
        say = lambda line: None  # noqa: E731
    elif callable(progress):
        say = progress
    else:
        raise LogoTypeError(f"progress={progress!r}: expected True, False or a callable")
    common = dict(say=say, engine=engine, backend=backend, dtype=dtype, tensorboard=tensorboard)
    python_env = None
    predicate = overrides.get("success")
    if callable(predicate):
        # A predicate of the caller's judges a Python env's steps: the env is wrapped and
        # the run reads its is_success as the task's.
        if env is None:
            raise LogoValueError(
                "success= as a callable judges the steps of env=: give env= too (a config's "
                "own env takes success = \"task\", \"terminated\" or \"none\")"
            )
        del overrides["success"]
        env = judged(env, predicate)
        if resume is None:
            overrides["success"] = "task"
    if resume is not None:
        if config is not None or overrides or demos is not None:
            raise LogoValueError(
                "resume continues a run with its own config: drop config, demos and overrides"
            )
        if env is not None:
            saved = _saved_env_id(Path(resume))
            if saved is None:
                raise LogoValueError(
                    f"{resume} is not a run on a Python env: resume it without env= "
                    "(its env is one of logo-rl's, named in its config.toml)"
                )
            python_env = _python_env(env, saved)
        path = _logo_rl.train(
            resume=os.fspath(resume), iterations=iterations, env=python_env, **common
        )
        return Run(path)
    if config is None:
        raise LogoValueError("train needs a config (a preset, a TOML file or a dict) or resume=")
    if isinstance(config, str) and not os.path.exists(config):
        if not config.endswith(".toml"):
            config = preset_path(config)  # raises, listing the presets, if it is none
    if "guidance" in overrides and overrides["guidance"] is None and demos is not None:
        raise LogoValueError("demos= with guidance=None: without guidance no demonstrations are used")
    table = _absolute_paths(dict(overrides))
    if iterations is not None:
        table["iterations"] = iterations
    path_arg = None
    if isinstance(config, Mapping):
        table = _lay_over(dict(config), table)
    else:
        path_arg = os.fspath(config)
    if env is not None:
        python_env = _python_env(env, None)
        spec = python_env[1]
        table["env"] = table["eval_env"] = spec["id"]
        # A Python env may raise at any step: every whole iteration keeps its checkpoint,
        # unless the config or the call says otherwise.
        if "checkpoint_every" not in table and (
            path_arg is None or "checkpoint_every" not in _config_keys(path_arg)
        ):
            table["checkpoint_every"] = 1
        if demos is not None:
            run_dir = Path(out) if out is not None else _run_dir_for(config, table)
            where = demos_path(demos, run_dir, spec["obs_dim"], spec["act_dim"])
            check_demos_env(where, spec, allow_other_env)
            table = _lay_over(table, {"guidance": {"demos": where}})
    elif demos is not None:
        raise LogoValueError("demos= goes with env= (a config's own env has its demos in the config)")
    path = _logo_rl.train(
        config=path_arg,
        table_json=json.dumps(table, default=_plain),
        base=os.getcwd(),
        out=None if out is None else os.fspath(out),
        env=python_env,
        **common,
    )
    return Run(path)


def _python_env(env, saved_id: str | None) -> tuple[Callable, dict[str, Any]]:
    make, spec = prepare(env)
    if saved_id is not None:
        spec["id"] = saved_id
    return make, spec


def _plain(value: Any) -> Any:
    """What json.dumps cannot write by itself: paths, NumPy scalars and arrays."""
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    if isinstance(value, (np.generic, np.ndarray)):
        return value.tolist()
    raise LogoTypeError(f"config value {value!r} of type {type(value).__name__}: not a TOML value")


PATH_KEYS = {
    ("init_policy",),
    ("init", "demos"),
    ("guidance", "demos"),
    ("guidance", "behaviour_policy"),
}


def _absolute_paths(table: dict) -> dict:
    """Paths given as overrides are the caller's, from the working directory (a config
    file's own paths are from its folder)."""
    for keys in PATH_KEYS:
        holder = table
        for key in keys[:-1]:
            holder = holder.get(key) if isinstance(holder.get(key), dict) else None
            if holder is None:
                break
        if holder is not None and isinstance(holder.get(keys[-1]), (str, os.PathLike)):
            holder[keys[-1]] = os.path.abspath(holder[keys[-1]])
    return table


def _saved_env_id(run: Path) -> str | None:
    try:
        saved = tomllib.loads((run / "config.toml").read_text())
    except (OSError, tomllib.TOMLDecodeError):
        return None  # the resume itself says what is wrong with the folder
    env = saved.get("env")
    env = env.get("id") if isinstance(env, dict) else env
    return env if isinstance(env, str) and env.startswith(PREFIX) else None


def _run_dir_for(config, table: Mapping[str, Any]) -> Path:
    """`logo train`'s default folder, runs/<config name>-seed<seed>."""
    if isinstance(config, Mapping):
        path, seed = None, table.get("seed", config.get("seed", 0))
    else:
        path = os.fspath(config)
        seed = table.get("seed", _config_keys(path).get("seed", 0))
    return Path(_logo_rl.run_dir_for(path, int(seed)))


def _config_keys(path: str) -> dict:
    """A config file's keys, read by the Rust side as ``logo train`` reads it: a file
    that is not there or not TOML raises the same LogoError, naming the file and the
    line, as the same file gives without ``env=``."""
    return json.loads(_logo_rl.config_keys(path))


def _lay_over(under: dict, top: Mapping) -> dict:
    for key, value in top.items():
        if isinstance(value, Mapping) and isinstance(under.get(key), Mapping):
            under[key] = _lay_over(dict(under[key]), value)
        else:
            under[key] = value
    return under
