"""N copies of a logo_rl env behind Gymnasium's VectorEnv API, stepped on Rust threads."""

from __future__ import annotations

import os
from typing import Any

import numpy as np
from gymnasium import spaces
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from ._errors import LogoValueError
from ._logo_rl import RustVecEnv
from .envs import rust_limit


class LogoVectorEnv(VectorEnv):
    """``num_envs`` copies of one env of ``logo envs``, stepped together on ``threads``
    Rust threads with the GIL released (logo-rl's own ``VecEnv``, the trainer's).

    Autoreset is Gymnasium's ``SAME_STEP`` mode: a copy whose episode ends is reset within
    the same ``step``; its last observation is in ``info["final_obs"]`` (where
    ``info["_final_obs"]``). ``info`` also holds ``dense_reward`` and ``x_position`` per
    copy. ``reset(seed=s)`` seeds copy i with ``s + i``, from the project's own stream.
    ``max_episode_steps``: as ``LogoEnv``'s (``"task"``: Gymnasium's registered limit).
    """

    metadata = {"autoreset_mode": AutoresetMode.SAME_STEP}

    def __init__(
        self,
        env_id: str,
        num_envs: int,
        threads: int | None = None,
        max_episode_steps: int | str | None = "task",
    ):
        threads = min(num_envs, os.cpu_count() or 1) if threads is None else threads
        self._venv = RustVecEnv(env_id, num_envs, threads, 0, rust_limit(max_episode_steps))
        one = self._venv
        self.env_id = one.id
        self.num_envs = num_envs
        self.threads = threads
        self.single_observation_space = spaces.Box(-np.inf, np.inf, (one.obs_dim,), np.float64)
        self.single_action_space = spaces.Box(
            one.action_low.astype(np.float32), one.action_high.astype(np.float32), dtype=np.float32
        )
        self.observation_space = batch_space(self.single_observation_space, num_envs)
        self.action_space = batch_space(self.single_action_space, num_envs)

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        if seed is not None:
            self._np_random, self._np_random_seed = np.random.default_rng(seed), seed
            if seed < 0:
                raise LogoValueError(f"seed={seed}: a seed is a non-negative integer")
        return self._venv.reset(seed), {}

    def step(self, actions):
        actions = np.ascontiguousarray(actions, dtype=np.float64)
        obs, reward, terminated, truncated, dense, x, final_obs = self._venv.step(
            actions.reshape(self.num_envs, -1)
        )
        every = np.ones(self.num_envs, dtype=bool)
        info: dict[str, Any] = {
            "dense_reward": dense, "_dense_reward": every, "x_position": x, "_x_position": every,
        }
        ended = terminated | truncated
        if ended.any():
            # As Gymnasium's same-step mode: the ended episodes' last observation and the
            # info of their last step, each with its mask.
            finals = np.full(self.num_envs, None, dtype=object)
            for i in np.flatnonzero(ended):
                finals[i] = final_obs[i]
            info["final_obs"], info["_final_obs"] = finals, ended
            info["final_info"] = {
                "dense_reward": dense, "_dense_reward": ended, "x_position": x, "_x_position": ended,
            }
            info["_final_info"] = ended
        return obs, reward, terminated, truncated, info
