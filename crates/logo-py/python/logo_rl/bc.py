"""``logo_rl.bc``: behaviour cloning (``logo bc``) from Python, in this process."""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Sequence

from ._errors import LogoTypeError, LogoValueError
from . import _logo_rl
from .custom import check_demos_env, demos_path, prepare
from .policy import Policy
from .wrappers import judged


@dataclass(frozen=True)
class Cloned:
    """What :func:`bc` did: the checkpoint, the fit and the evaluation of its policy."""

    path: Path
    """The checkpoint (``logo eval``, ``init_policy`` and :func:`logo_rl.load` read it)."""
    pairs: int
    loss_before: float
    """−mean log π(a|s) over the demonstrations, at the initialisation..."""
    loss_after: float
    """...and after the fit."""
    evaluation: dict[str, Any]
    """The mean action over fresh episodes, as sent and clipped (``eval.json``'s layout)."""
    evaluation_path: Path
    """Where the evaluation is kept: beside the checkpoint (``policy.eval.json``)."""

    @property
    def policy(self) -> Policy:
        return Policy(self.path)

    @property
    def success_rate(self) -> float | None:
        """The share of evaluation episodes that reached the goal (None where the task
        defines no success)."""
        return self.evaluation["mean_action"]["summary"]["success_rate"]


def bc(
    demos: Any,
    *,
    env: str | Callable[[], Any],
    out: str | os.PathLike | None = None,
    seed: int = 0,
    epochs: int = 100,
    minibatch: int = 64,
    learning_rate: float = 1e-3,
    learn_std: bool = True,
    hidden: Sequence[int] = (128, 128),
    episodes: int = 20,
    success: str | Callable[[Any, dict], bool] = "task",
    engine: str | None = None,
    backend: str | None = None,
    dtype: str | None = None,
    allow_other_env: bool = False,
) -> Cloned:
    """Fits a policy to ``demos`` by maximum likelihood, as ``logo bc`` does, scores its mean
    action on ``episodes`` fresh episodes of ``env``, and writes it to ``out`` (default
    ``runs/bc-<env>-seed<seed>/policy.safetensors``).

    ``env``: one of logo-rl's ids (:func:`logo_rl.env_ids`), a Gymnasium id, or a callable
    returning a new env. ``demos``: as :func:`logo_rl.train` takes them (a Minari dataset,
    its folder or id, a ``.npy`` of ``[observation ‖ action]`` rows, or a list of
    ``(observations, actions)`` trajectories). ``epochs``, ``minibatch``,
    ``learning_rate``, ``learn_std``: as ``[init]``'s keys (docs/config.md). ``success``:
    which evaluation episodes reached the goal, as :func:`logo_rl.train` takes it
    (``"task"``, ``"terminated"``, ``"none"``, or a callable ``(obs, info) -> bool``
    judging each step of ``env``). The evaluation is also written beside the checkpoint
    (``policy.safetensors`` → ``policy.eval.json``, a run's ``eval.json`` layout).
    Demonstrations recorded in another env than a Python ``env`` are refused unless
    ``allow_other_env=True``, as :func:`logo_rl.train` refuses them.
    """
    for name, value in (("epochs", epochs), ("minibatch", minibatch), ("episodes", episodes)):
        if not isinstance(value, int) or isinstance(value, bool):
            raise LogoTypeError(f"{name}={value!r}: expected an integer")
        if value < 1:
            raise LogoValueError(f"{name}={value}: expected at least 1")
    hidden = list(hidden)
    if not all(isinstance(h, int) and not isinstance(h, bool) for h in hidden):
        raise LogoTypeError(f"hidden={hidden!r}: expected a sequence of integers")
    if callable(success):
        if isinstance(env, str) and env in _logo_rl.env_ids():
            raise LogoValueError(
                "success= as a callable judges the steps of a Gymnasium env; logo-rl's own "
                f"env {env!r} takes success = \"task\", \"terminated\" or \"none\""
            )
        env, success = judged(env, success), "task"
    elif not isinstance(success, str):
        raise LogoTypeError(f"success={success!r}: expected a string or a callable")
    elif success not in ("task", "terminated", "none"):
        raise LogoValueError(f"success={success!r}: expected task, terminated or none, or a "
                         "callable (obs, info) -> bool")
    python_env = None
    if isinstance(env, str) and env in _logo_rl.env_ids():
        env_id = env
        rust_env = _logo_rl.RustEnv(env)
        obs_dim, act_dim = rust_env.obs_dim, rust_env.act_dim
    else:
        python_env = prepare(env)
        spec = python_env[1]
        env_id, obs_dim, act_dim = spec["id"], spec["obs_dim"], spec["act_dim"]
    if out is None:
        out = Path("runs") / f"bc-{env_id.replace('/', '_')}-seed{seed}" / "policy.safetensors"
    out = Path(out)
    where = demos_path(demos, out.parent, obs_dim, act_dim)
    if python_env is not None:
        check_demos_env(where, python_env[1], allow_other_env)
    path, report = _logo_rl.bc(
        env_id=env_id,
        demos=where,
        out=os.fspath(out),
        seed=seed,
        epochs=epochs,
        minibatch=minibatch,
        learning_rate=float(learning_rate),
        learn_std=bool(learn_std),
        hidden=hidden,
        episodes=episodes,
        success=success,
        engine=engine,
        backend=backend,
        dtype=dtype,
        env=python_env,
    )
    report = json.loads(report)
    fit = report["report"]
    return Cloned(
        path=Path(path),
        pairs=fit["pairs"],
        loss_before=fit["loss_before"],
        loss_after=fit["loss_after"],
        evaluation=report["evaluation"],
        evaluation_path=Path(report["evaluation_file"]),
    )
