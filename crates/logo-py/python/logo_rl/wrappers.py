"""The sparse kinds of logo-rl for any Gymnasium env, paying as the Rust ones do."""

from __future__ import annotations

from typing import Any, Callable

import gymnasium as gym

KINDS = ("distance", "delayed")


def _mujoco_x(env: gym.Env) -> float:
    return float(env.unwrapped.data.qpos[0])


class SparseReward(gym.Wrapper):
    """Replaces an env's reward by a sparse one; the reward it hides is ``info["dense_reward"]``.

    - ``kind="distance", threshold=d``: +1 on every step where the position has moved more
      than ``d`` from where the episode started, else 0 (LOGO's Hopper, Walker2d,
      HalfCheetah; ``threshold`` 2, 2 and 20 metres).
    - ``kind="delayed"``: 0 on every step but the episode's last (terminated or truncated),
      which pays the episode's whole return (LOGO's InvertedDoublePendulum). Wrap the env
      *outside* its ``TimeLimit`` (as ``gymnasium.make`` returns it), so that the time limit's
      last step pays too.

    ``position`` (distance only): a callable of the env giving the position along the axis
    of travel; by default ``qpos[0]`` of a Gymnasium MuJoCo env, as the Rust envs use.
    """

    def __init__(
        self,
        env: gym.Env,
        kind: str,
        threshold: float | None = None,
        position: Callable[[gym.Env], float] | None = None,
    ):
        super().__init__(env)
        if kind not in KINDS:
            raise ValueError(f"unknown sparse kind {kind!r}; the kinds are {', '.join(KINDS)}")
        if kind == "distance":
            if threshold is None or not (float(threshold) > 0 and float(threshold) < float("inf")):
                raise ValueError(
                    f"kind 'distance' needs a positive finite threshold (metres), got {threshold!r}"
                )
            if position is None:
                if not hasattr(env.unwrapped, "data"):
                    raise ValueError(
                        "kind 'distance' needs position= for an env that is not a Gymnasium "
                        "MuJoCo env (a callable of the env giving its position)"
                    )
                position = _mujoco_x
        elif threshold is not None:
            raise ValueError("kind 'delayed' takes no threshold")
        self.kind, self.threshold, self._position = kind, threshold, position
        self._start = 0.0
        self._episode_return = 0.0

    def _start_episode(self) -> None:
        self._start = self._position(self.env) if self.kind == "distance" else 0.0
        self._episode_return = 0.0

    def reset(self, **kwargs: Any):
        obs, info = self.env.reset(**kwargs)
        self._start_episode()
        return obs, info

    def set_state(self, qpos, qvel) -> None:
        """The env's ``set_state``; the state set is the episode's start, as in Rust."""
        self.env.unwrapped.set_state(qpos, qvel)
        self._start_episode()

    def step(self, action):
        obs, dense, terminated, truncated, info = self.env.step(action)
        info = {**info, "dense_reward": float(dense)}
        if self.kind == "distance":
            moved = self._position(self.env) - self._start
            reward = 1.0 if moved > self.threshold else 0.0
        else:
            self._episode_return += float(dense)
            reward = self._episode_return if (terminated or truncated) else 0.0
        return obs, reward, terminated, truncated, info
