"""Demonstrations into Minari: a trained policy's or a controller of the user's own."""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable

import numpy as np

from ._errors import LogoValueError
from ._logo_rl import read_dataset as _read_dataset
from ._logo_rl import write_dataset
from .custom import PREFIX, prepare
from .policy import Policy
from .wrappers import judged


@dataclass(frozen=True)
class Recording:
    """What :func:`record` wrote: the dataset folder (``train(demos=...)`` takes this object
    as it takes the path; ``recording / "data"`` is Minari's folder) and its episodes."""

    path: Path
    episodes: int
    steps: int
    returns: np.ndarray  # each episode's return, in the env's own reward
    success_rate: float | None  # the share reaching the goal (info["is_success"]); None without one

    def __fspath__(self) -> str:
        return os.fspath(self.path)

    def __truediv__(self, other) -> Path:
        return self.path / other

    def __str__(self) -> str:
        return str(self.path)


def record(
    env: str | Callable[[], Any],
    act: Policy | Callable[[np.ndarray], Any],
    episodes: int,
    path: str | os.PathLike,
    *,
    dataset_id: str | None = None,
    seed: int = 0,
    deterministic: bool = False,
    success: str | Callable[[Any, dict], bool] = "task",
) -> Recording:
    """Plays ``episodes`` episodes of ``env`` (a Gymnasium id or a callable returning a new
    env) with ``act`` and writes them as a Minari dataset folder at ``path``
    (``path/data/main_data.hdf5`` and ``metadata.json``, as Minari lays out a dataset;
    ``minari.MinariDataset(path / "data")`` reads it, and so does logo-rl without
    minari); returns a :class:`Recording` (the path, the episodes, steps, returns and the
    success rate where the env reports ``info["is_success"]``), which
    :func:`logo_rl.train` takes as ``demos=``. The dataset's metadata holds the same
    summary, and the spaces as the env declares them.

    ``act``: a :class:`logo_rl.Policy` (sampled actions, as LOGO's demonstrations were
    recorded, unless ``deterministic``) or any callable from an observation to an action
    (a controller of your own). Episode k starts from ``reset(seed=seed + k)``. The
    rewards stored are the env's own (a sparse env's sparse ones).

    ``success``: which episodes reached the goal, as :func:`logo_rl.train` takes it:
    ``"task"`` (any step's ``info["is_success"]``), ``"terminated"`` (the episode ended
    there), ``"none"``, or a callable ``(obs, info) -> bool`` judging each step.
    """
    if episodes < 1:
        raise LogoValueError(f"episodes={episodes}: at least 1")
    if callable(success):
        env = judged(env, success)  # checks the predicate's arguments first
        success = "task"
    elif success not in ("task", "terminated", "none"):
        raise LogoValueError(
            f"success={success!r}: expected 'task', 'terminated', 'none' or a callable "
            "(obs, info) -> bool"
        )
    make, spec = prepare(env)  # the same checks as training: Box spaces, a time limit
    adapter = make()
    rng = np.random.default_rng(seed)
    if isinstance(act, Policy):
        policy = act
        act = lambda obs: policy.predict(obs, deterministic=deterministic, rng=rng)  # noqa: E731
    played, reached = [], []
    observation_space, action_space = adapter.env.observation_space, adapter.env.action_space
    try:
        for k in range(episodes):
            obs, _ = adapter.reset(seed + k)
            observations, actions, rewards, terminations, truncations = [obs], [], [], [], []
            episode_reached = None
            while True:
                action = np.asarray(act(obs), dtype=np.float64).reshape(-1)
                if action.shape != (spec["act_dim"],):
                    raise LogoValueError(
                        f"episode {k}, step {len(actions)}: the controller returned "
                        f"{action.size} action values; the action space "
                        f"({action_space}) has {spec['act_dim']}"
                    )
                obs, reward, terminated, truncated, _, _, reached_here = adapter.step(action)
                if success == "terminated":
                    reached_here = bool(terminated)
                if reached_here is not None and success != "none":
                    episode_reached = bool(episode_reached) or reached_here
                observations.append(obs)
                actions.append(action)
                rewards.append(reward)
                terminations.append(terminated)
                truncations.append(truncated)
                if terminated or truncated:
                    break
            played.append((
                np.array(observations), np.array(actions), np.array(rewards),
                terminations, truncations,
            ))
            reached.append(episode_reached)
    finally:
        adapter.close()
    returns = np.array([float(np.sum(episode[2])) for episode in played])
    known = [r for r in reached if r is not None]
    success_rate = sum(known) / len(known) if known else None
    path = Path(path)
    summary = {
        "return_mean": float(returns.mean()),
        "return_std": float(returns.std(ddof=1)) if len(returns) > 1 else 0.0,
        "return_min": float(returns.min()),
        "return_max": float(returns.max()),
        "success_rate": success_rate,
    }
    write_dataset(
        path, played,
        dataset_id=dataset_id or f"logo_rl/{path.name}-v0",
        # The env's own name (a Gymnasium id where one was given): what a config of
        # logo-rl's envs compares with the dataset's env.
        env_id=spec["id"].removeprefix(PREFIX),
        observation_space=_box(observation_space), action_space=_box(action_space),
        summary_json=json.dumps(summary),
    )
    steps = sum(len(episode[1]) for episode in played)
    return Recording(path, len(played), steps, returns, success_rate)


def _box(space) -> tuple[list[float], list[float], str]:
    """A Box space's bounds and dtype, as the env declares them."""
    return (
        [float(v) for v in np.asarray(space.low, dtype=np.float64).reshape(-1)],
        [float(v) for v in np.asarray(space.high, dtype=np.float64).reshape(-1)],
        str(np.dtype(space.dtype)),
    )


@dataclass(frozen=True)
class Dataset:
    """A Minari dataset folder as logo-rl reads it (no ``minari`` package needed)."""

    episodes: list[dict[str, Any]]  # observations, actions, rewards, terminations, truncations
    metadata: dict[str, Any]  # metadata.json; a recording's summary under "logo_recording"

    @property
    def total_episodes(self) -> int:
        return len(self.episodes)

    @property
    def total_steps(self) -> int:
        return sum(len(e["actions"]) for e in self.episodes)


def read_dataset(path: str | os.PathLike) -> Dataset:
    """Reads a Minari dataset folder (one :func:`record` wrote, or ``data/logo/hopper``)
    as the trainer does; a folder that does not exist raises FileNotFoundError."""
    episodes, metadata = _read_dataset(Path(path))
    keys = ("observations", "actions", "rewards", "terminations", "truncations")
    return Dataset([dict(zip(keys, e)) for e in episodes], json.loads(metadata))
