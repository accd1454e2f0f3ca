"""A user's own Gymnasium env and demonstrations, made ready for the Rust trainer."""

from __future__ import annotations

import json
import os
import re
import warnings
from pathlib import Path
from typing import Any, Callable

import gymnasium as gym
import numpy as np
from gymnasium import spaces
from gymnasium.wrappers import TimeLimit

from ._errors import LogoFileNotFoundError, LogoTypeError, LogoValueError
from ._logo_rl import EXTERNAL_PREFIX as PREFIX  # the ids of envs the caller brings


class _Adapter:
    """What the Rust side calls: float64 arrays in and out, shapes and values checked."""

    def __init__(self, env: gym.Env, name: str, obs_dim: int):
        self.env, self.name, self.obs_dim = env, name, obs_dim

    def _obs(self, obs, where: str) -> np.ndarray:
        array = np.asarray(obs, dtype=np.float64).reshape(-1)
        if array.shape != (self.obs_dim,):
            raise LogoValueError(
                f"{self.name}: {where} returned an observation of shape {np.shape(obs)}, "
                f"expected ({self.obs_dim},)"
            )
        bad = np.flatnonzero(~np.isfinite(array))
        if bad.size:
            raise LogoValueError(
                f"{self.name}: {where} returned an observation with {array[bad[0]]} at index {bad[0]}"
            )
        return np.ascontiguousarray(array)

    def reset(self, seed: int | None):
        result = self.env.reset(seed=None if seed is None else int(seed) % (1 << 63))
        if not (isinstance(result, tuple) and len(result) == 2 and isinstance(result[1], dict)):
            raise _old_api(self.name, f"reset returned {_described(result)}, not (obs, info)")
        obs, info = result
        x = float(info.get("x_position", 0.0))
        if not np.isfinite(x):
            raise LogoValueError(f"{self.name}: reset returned info['x_position'] = {x}")
        return self._obs(obs, "reset"), x

    def step(self, action: np.ndarray):
        try:
            result = self.env.step(action)
        except ValueError as error:
            # A wrapper of Gymnasium's (TimeLimit) unpacks the inner env's step first.
            if "values to unpack (expected 5, got 4)" in str(error):
                raise _old_api(self.name, "step returned 4 values") from error
            raise
        if not (isinstance(result, tuple) and len(result) == 5):
            raise _old_api(self.name, f"step returned {_described(result)}")
        obs, reward, terminated, truncated, info = result
        if np.ndim(reward) != 0:
            raise LogoTypeError(
                f"{self.name}: step returned the reward {reward!r} of shape {np.shape(reward)}; "
                "a reward is one number (return float(reward))"
            )
        reward = float(reward)
        if not np.isfinite(reward):
            raise LogoValueError(f"{self.name}: step returned the reward {reward}")
        dense = float(info.get("dense_reward", reward))
        x = float(info.get("x_position", 0.0))
        for key, value in (("dense_reward", dense), ("x_position", x)):
            if not np.isfinite(value):
                raise LogoValueError(f"{self.name}: step returned info[{key!r}] = {value}")
        success = info.get("is_success", info.get("success"))
        if success is not None:
            if np.size(success) != 1:
                raise LogoValueError(
                    f"{self.name}: step returned info['is_success'] = {success!r}, expected a bool"
                )
            success = bool(np.asarray(success).reshape(-1)[0])
        return self._obs(obs, "step"), reward, bool(terminated), bool(truncated), dense, x, success

    def close(self) -> None:
        self.env.close()


def _described(value) -> str:
    """What an env's reset or step returned, in a few words."""
    if isinstance(value, tuple):
        return f"{len(value)} values"
    return f"{type(value).__name__} {np.shape(value) if hasattr(value, 'shape') else ''}".strip()


def _old_api(name: str, what: str) -> LogoTypeError:
    return LogoTypeError(
        f"{name}: {what}; it looks written for the old gym API. Gymnasium's reset returns "
        "(obs, info) and its step five values, (obs, reward, terminated, truncated, info): "
        "port the env to them, or wrap it with shimmy's GymV21CompatibilityV0"
    )


def _time_limit(env: gym.Env) -> int | None:
    while True:
        if isinstance(env, TimeLimit):
            return env._max_episode_steps
        if not isinstance(env, gym.Wrapper):
            return None
        env = env.env


def prepare(env: str | Callable[[], gym.Env]) -> tuple[Callable[[], _Adapter], dict[str, Any]]:
    """The maker of adapted copies of `env` (a Gymnasium id, or a callable returning a new
    env) and the spec the Rust side needs; raises on what the trainer cannot take."""
    if isinstance(env, gym.Env):
        raise LogoTypeError(
            "env= takes a Gymnasium id or a callable returning a new env (the trainer makes "
            "several copies), not an env instance: env=lambda: MyEnv()"
        )
    if isinstance(env, str):
        make, label = (lambda: gym.make(env)), env
    elif callable(env):
        make, label = env, getattr(env, "__name__", type(env).__name__)
        if label == "<lambda>":
            label = "env"
    else:
        raise LogoTypeError(f"env={env!r}: expected a Gymnasium id or a callable returning an env")
    name = PREFIX + re.sub(r"[^A-Za-z0-9_.+()-]", "_", label)
    probe = make()
    try:
        obs_space, act_space = probe.observation_space, probe.action_space
        for what, space in (("observation", obs_space), ("action", act_space)):
            if not isinstance(space, spaces.Box) or len(space.shape) != 1:
                raise LogoTypeError(
                    f"{label}: its {what} space is {space}; logo-rl trains on flat Box "
                    "observation and action spaces"
                )
        steps = _time_limit(probe)
        if steps is None:
            raise LogoValueError(
                f"{label} never ends an episode (no TimeLimit): batches are whole episodes; "
                "wrap it, gymnasium.wrappers.TimeLimit(env, max_episode_steps=1000), or "
                "register it with max_episode_steps"
            )
        low, high = act_space.low.astype(np.float64), act_space.high.astype(np.float64)
        if np.isnan(low).any() or np.isnan(high).any() or (low > high).any():
            raise LogoValueError(f"{label}: its action space's bounds {low}, {high} are not a range")
        flat = np.flatnonzero(low == high)
        if flat.size:
            raise LogoValueError(
                f"{label}: its action space has no width in dimension {flat[0]} (low = high = "
                f"{low[flat[0]]}): a Gaussian policy's actions there would fall outside it; "
                "leave that dimension out of the action space and set it in the env"
            )
        spec = {
            "id": name,
            "obs_dim": int(obs_space.shape[0]),
            "act_dim": int(act_space.shape[0]),
            "action_low": [float(v) for v in low],
            "action_high": [float(v) for v in high],
            "max_episode_steps": int(steps),
            "dt": float(getattr(probe.unwrapped, "dt", 0.0)),
            # For the demonstrations' check (check_demos_env); the Rust side reads only
            # the keys above.
            "spaces": (obs_space, act_space),
            "gym_id": getattr(getattr(probe, "spec", None), "id", None),
            "label": label,
        }
    finally:
        probe.close()
    obs_dim = spec["obs_dim"]
    return (lambda: _Adapter(make(), name, obs_dim)), spec


def _looks_like_a_path(text: str) -> bool:
    """Whether `text`, which names nothing on disk, was meant as a path rather than a
    Minari id (`name`, `namespace/name-v0`): a leading slash, dot or tilde, or a file
    suffix."""
    return text.startswith(("/", ".", "~")) or text.endswith((".npy", ".hdf5")) or "\\" in text


def demos_path(demos: Any, out: Path, obs_dim: int, act_dim: int) -> str:
    """A path the Rust side reads for `demos`: a Minari dataset folder (its path, its local
    id, or the dataset object) as it is, a list of trajectories written as LOGO's `.npy`
    rows ``[observation ‖ action]`` into the run folder."""
    if isinstance(demos, (str, os.PathLike)) and Path(demos).exists():
        return str(Path(demos).resolve())
    if isinstance(demos, os.PathLike) or (isinstance(demos, str) and _looks_like_a_path(demos)):
        raise LogoFileNotFoundError(f"demos={os.fspath(demos)!r}: no such file or folder")
    if isinstance(demos, str) or hasattr(demos, "storage"):
        if isinstance(demos, str):
            # Not a path here: a Minari id, looked up among Minari's local datasets.
            try:
                import minari
            except ImportError:
                raise LogoFileNotFoundError(
                    f"demos={demos!r}: no such file or folder (nor a Minari dataset id: the "
                    "minari package, which would look one up, is not installed)"
                ) from None
            try:
                demos = minari.load_dataset(demos)
            except Exception as error:  # minari's own error names what it looked for
                raise LogoFileNotFoundError(
                    f"demos={demos!r}: no such file or folder, nor a local Minari dataset "
                    f"({error})"
                ) from None
        return str(Path(demos.storage.data_path).resolve().parent)
    if isinstance(demos, (list, tuple)):
        rows = []
        for i, trajectory in enumerate(demos):
            if isinstance(trajectory, dict):
                obs, actions = trajectory.get("observations"), trajectory.get("actions")
            else:
                obs, actions = trajectory
            obs = np.asarray(obs, dtype=np.float64)
            actions = np.asarray(actions, dtype=np.float64).reshape(len(actions), -1)
            if obs.ndim != 2 or obs.shape[1] != obs_dim or actions.shape[1] != act_dim:
                raise LogoValueError(
                    f"demos[{i}]: observations {obs.shape} and actions {actions.shape}; "
                    f"the env's are [steps, {obs_dim}] and [steps, {act_dim}]"
                )
            if len(obs) not in (len(actions), len(actions) + 1):
                raise LogoValueError(
                    f"demos[{i}]: {len(obs)} observations for {len(actions)} actions"
                )
            rows.append(np.concatenate([obs[: len(actions)], actions], axis=1))
        out.mkdir(parents=True, exist_ok=True)
        path = out / "demonstrations.npy"
        np.save(path, np.concatenate(rows) if rows else np.zeros((0, obs_dim + act_dim)))
        return str(path.resolve())
    raise LogoTypeError(
        f"demos={type(demos).__name__}: expected a Minari dataset (a folder, an id, the "
        "dataset), a .npy path, or a list of (observations, actions) trajectories"
    )


def _recorded_space(text) -> dict | None:
    """A Box space as Minari's metadata serialises it, or None."""
    try:
        space = json.loads(text) if isinstance(text, str) else text
    except ValueError:
        return None
    if not isinstance(space, dict) or space.get("type") != "Box":
        return None
    return space


def _same_box(recorded: dict, space: spaces.Box) -> bool:
    low, high = np.asarray(space.low, np.float64).reshape(-1), np.asarray(space.high, np.float64).reshape(-1)
    theirs_low = np.asarray(recorded.get("low", []), np.float64).reshape(-1)
    theirs_high = np.asarray(recorded.get("high", []), np.float64).reshape(-1)
    if list(recorded.get("shape", [])) != list(space.shape) or theirs_low.shape != low.shape:
        return False
    # float32 bounds written as float64 (and back): equal to float32's precision.
    close = lambda a, b: np.allclose(a, b, rtol=1e-6, atol=0.0, equal_nan=False)  # noqa: E731
    return bool(close(theirs_low, low) and close(theirs_high, high))


def _described_box(recorded: dict) -> str:
    return (f"Box(low={recorded.get('low')}, high={recorded.get('high')}, "
            f"shape={tuple(recorded.get('shape', ()))})")


def check_demos_env(where: str, spec: dict, allow_other_env: bool) -> None:
    """Refuses demonstrations recorded in another env than ``spec``'s: a Minari dataset's
    recorded observation and action spaces (shapes and bounds) must be the env's, and so
    must its Gymnasium id where both name one. ``allow_other_env`` trains anyway. A
    ``.npy`` or list of trajectories names no env: said once, with a warning."""
    observation_space, action_space = spec["spaces"]
    metadata_path = Path(where) / "data" / "metadata.json"
    if not metadata_path.is_file():
        warnings.warn(
            f"demos {where}: nothing in them says which env they were recorded in (a .npy "
            "or a list of trajectories); only their sizes are checked against the env",
            stacklevel=3,
        )
        return
    metadata = json.loads(metadata_path.read_text())
    differences = []
    for what, key, space in (("observation", "observation_space", observation_space),
                             ("action", "action_space", action_space)):
        recorded = _recorded_space(metadata.get(key))
        if recorded is not None and not _same_box(recorded, space):
            differences.append(f"{what} space {_described_box(recorded)}, the env's {space}")
    recorded_id = None
    env_spec = metadata.get("env_spec")
    if isinstance(env_spec, str):
        try:
            recorded_id = json.loads(env_spec).get("id")
        except (ValueError, AttributeError):
            recorded_id = None
    logo_id = metadata.get("logo_env_id")
    if recorded_id is None and isinstance(logo_id, str) and logo_id in gym.registry:
        recorded_id = logo_id  # a Gymnasium id that logo_rl.record was given
    if recorded_id is not None and spec.get("gym_id") and recorded_id != spec["gym_id"]:
        differences.append(f"Gymnasium id {recorded_id}, the env's {spec['gym_id']}")
    if differences and not allow_other_env:
        raise LogoValueError(
            f"demos {where} were recorded in another env than env={spec['label']}: "
            + "; ".join(differences)
            + ". Record them in this env, or pass allow_other_env=True to train on them anyway"
        )
