"""logo-rl's Rust envs as Gymnasium envs (``gymnasium.make("logo_rl/SparseHopper-v4")``)."""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from ._errors import LogoValueError
from ._logo_rl import RustEnv, time_limit, env_ids

NAMESPACE = "logo_rl"
DEFAULT_SIZE = 480  # Gymnasium's MuJoCo frames
NO_LIMIT = 1 << 62


def rust_limit(max_episode_steps: int | str | None) -> int | None:
    """The env's own time limit as the Rust env takes it: ``"task"`` (the default) for the
    limit Gymnasium registers the task with (1000; Reacher 50, Pusher 100), ``None`` for
    none of its own (``gymnasium.make``'s ``TimeLimit``, whatever ``max_episode_steps`` it
    was given, ends the episodes), or a number of steps."""
    if max_episode_steps == "task":
        return None
    if max_episode_steps is None:
        return NO_LIMIT
    if isinstance(max_episode_steps, str):
        raise LogoValueError(
            f"max_episode_steps={max_episode_steps!r}: expected 'task', None or a number of steps"
        )
    return max_episode_steps


class LogoEnv(gym.Env):
    """One Rust env behind Gymnasium's API.

    It steps as Gymnasium's own MuJoCo env of the same id does, bit for bit: from the same
    state (:meth:`set_state`) and the same float64 actions, the same observations, dense
    rewards, ``terminated`` and ``truncated``. Its reset noise comes from the project's own
    random stream (ChaCha8, seeded by ``reset(seed=...)``), not from NumPy's, so a seed gives
    the initial states a ``logo train`` run with that seed sees, and not those Gymnasium's
    env would draw.

    ``info`` holds ``dense_reward`` (the task's Gymnasium reward, whatever a sparse id pays)
    and ``x_position`` (``qpos[0]`` after the step); Reacher's and Pusher's also
    ``goal_distance`` (fingertip or object to target, in the plane: what the goal kind pays
    on). ``max_episode_steps``: ``"task"`` (Gymnasium's registered limit), ``None`` (none of
    the env's own) or a number of steps.
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 125}

    def __init__(
        self,
        env_id: str,
        max_episode_steps: int | str | None = "task",
        render_mode: str | None = None,
        width: int = DEFAULT_SIZE,
        height: int = DEFAULT_SIZE,
    ):
        if render_mode not in (None, "rgb_array"):
            raise LogoValueError(f"render_mode={render_mode!r}: logo_rl envs render 'rgb_array' only")
        self._env = RustEnv(env_id, rust_limit(max_episode_steps))
        self.last_goal_distance = float("nan")  # the last step's, for the goal kind
        self.env_id = self._env.id
        self.render_mode = render_mode
        self.width, self.height = width, height
        self.metadata = {**self.metadata, "render_fps": int(round(1.0 / self._env.dt))}
        obs_dim = self._env.obs_dim
        self.observation_space = spaces.Box(-np.inf, np.inf, (obs_dim,), np.float64)
        # As Gymnasium's MuJoCo envs: the actuators' control range, float32.
        low = self._env.action_low.astype(np.float32)
        high = self._env.action_high.astype(np.float32)
        self.action_space = spaces.Box(low, high, dtype=np.float32)

    @property
    def dt(self) -> float:
        return self._env.dt

    @property
    def sparse_rule(self) -> str | None:
        """The sparse rule (``distance(2)``, ``delayed``), None for a dense id."""
        return self._env.sparse

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        super().reset(seed=seed)  # NumPy's generator too, and its checks of the seed
        obs = self._env.reset(seed)
        return obs, {}

    def step(self, action):
        action = np.asarray(action, dtype=np.float64).reshape(-1)
        if action.shape != (self._env.act_dim,):
            raise LogoValueError(
                f"action of {action.size} values; {self.env_id} takes {self._env.act_dim}"
            )
        obs, reward, terminated, truncated, dense, x, goal, success = self._env.step(action)
        info = {"dense_reward": dense, "x_position": x}
        if goal is not None:
            info["goal_distance"] = self.last_goal_distance = goal
        if success is not None:
            info["is_success"] = success
        return obs, reward, terminated, truncated, info

    def set_state(self, qpos, qvel) -> None:
        """Overwrites the joint state, as Gymnasium's ``MujocoEnv.set_state``."""
        self._env.set_state(
            np.ascontiguousarray(qpos, dtype=np.float64),
            np.ascontiguousarray(qvel, dtype=np.float64),
        )

    def state_vector(self) -> np.ndarray:
        """``[qpos, qvel]`` now, as Gymnasium's ``MujocoEnv.state_vector``."""
        qpos, qvel = self._env.state()
        return np.concatenate([qpos, qvel])

    def render(self):
        if self.render_mode != "rgb_array":
            return None
        return self._env.render(self.width, self.height)


def register_envs() -> list[str]:
    """Registers ``logo_rl/<id>`` for every id of ``logo envs``; returns the names."""
    names = []
    for env_id in env_ids():
        name = f"{NAMESPACE}/{env_id}"
        if name not in gym.registry:
            gym.register(
                id=name,
                entry_point="logo_rl.envs:LogoEnv",
                kwargs={"env_id": env_id, "max_episode_steps": None},
                max_episode_steps=time_limit(env_id),
            )
        names.append(name)
    return names
