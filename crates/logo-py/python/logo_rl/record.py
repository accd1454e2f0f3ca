"""Demonstrations into Minari: a trained policy's or a controller of the user's own."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Callable

import numpy as np

from ._logo_rl import write_dataset
from .custom import PREFIX, prepare
from .policy import Policy


def record(
    env: str | Callable[[], Any],
    act: Policy | Callable[[np.ndarray], Any],
    episodes: int,
    path: str | os.PathLike,
    *,
    dataset_id: str | None = None,
    seed: int = 0,
    deterministic: bool = False,
) -> Path:
    """Plays ``episodes`` episodes of ``env`` (a Gymnasium id or a callable returning a new
    env) with ``act`` and writes them as a Minari dataset folder at ``path``
    (``path/data/main_data.hdf5`` and ``metadata.json``, as Minari lays out a dataset;
    ``minari.MinariDataset(path / "data")`` reads it); returns ``path``, which
    :func:`logo_rl.train` takes as ``demos=``.

    ``act``: a :class:`logo_rl.Policy` (sampled actions, as LOGO's demonstrations were
    recorded, unless ``deterministic``) or any callable from an observation to an action
    (a controller of your own). Episode k starts from ``reset(seed=seed + k)``. The
    rewards stored are the env's own (a sparse env's sparse ones).
    """
    if episodes < 1:
        raise ValueError(f"episodes={episodes}: at least 1")
    make, spec = prepare(env)  # the same checks as training: Box spaces, a time limit
    adapter = make()
    rng = np.random.default_rng(seed)
    if isinstance(act, Policy):
        policy = act
        act = lambda obs: policy.predict(obs, deterministic=deterministic, rng=rng)  # noqa: E731
    played = []
    try:
        for k in range(episodes):
            obs, _ = adapter.reset(seed + k)
            observations, actions, rewards, terminations, truncations = [obs], [], [], [], []
            while True:
                action = np.asarray(act(obs), dtype=np.float64).reshape(-1)
                obs, reward, terminated, truncated, _, _, _ = adapter.step(action)
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
    finally:
        adapter.close()
    path = Path(path)
    write_dataset(
        path, played,
        dataset_id=dataset_id or f"logo_rl/{path.name}-v0",
        # The env's own name (a Gymnasium id where one was given): what a config of
        # logo-rl's envs compares with the dataset's env.
        env_id=spec["id"].removeprefix(PREFIX),
        action_low=spec["action_low"], action_high=spec["action_high"],
    )
    return path
