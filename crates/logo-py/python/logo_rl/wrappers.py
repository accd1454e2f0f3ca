"""The sparse kinds of logo-rl for any Gymnasium env, paying as the Rust ones do."""

from __future__ import annotations

import inspect
import math
from typing import Any, Callable

import gymnasium as gym

from ._errors import LogoTypeError, LogoValueError

KINDS = ("distance", "delayed", "goal")
# The bodies whose distance in the plane Gymnasium's tasks with a target are scored on.
GOAL_BODIES = (("fingertip", "target"), ("object", "goal"))


def _mujoco_x(env: gym.Env) -> float:
    return float(env.unwrapped.data.qpos[0])


def _info_goal_distance(env: gym.Env) -> Callable[[gym.Env], float] | None:
    """A logo_rl env of Reacher or Pusher reports its goal distance in ``info``: read from
    the last step's."""
    from .envs import LogoEnv

    task = getattr(env.unwrapped, "env_id", "").split("+")[0].split("-")[0]
    if not isinstance(env.unwrapped, LogoEnv) or task not in ("Reacher", "Pusher"):
        return None
    return lambda env: env.unwrapped.last_goal_distance


def _mujoco_goal_distance(env: gym.Env) -> Callable[[gym.Env], float] | None:
    """Reacher's fingertip-to-target or Pusher's object-to-goal distance in the plane, as
    the Rust envs measure it; None for an env with neither pair of bodies."""
    model = getattr(env.unwrapped, "model", None)
    if model is None:
        return None
    names = {model.body(i).name for i in range(model.nbody)}
    for a, b in GOAL_BODIES:
        if a in names and b in names:

            def distance(env: gym.Env, a=a, b=b) -> float:
                data = env.unwrapped.data
                pa, pb = data.body(a).xpos, data.body(b).xpos
                return math.hypot(pa[0] - pb[0], pa[1] - pb[1])

            return distance
    return None


class SparseReward(gym.Wrapper):
    """Replaces an env's reward by a sparse one; the reward it hides is ``info["dense_reward"]``.

    - ``kind="distance", threshold=d``: +1 on every step where the position has moved more
      than ``d`` from where the episode started, else 0 (LOGO's Hopper, Walker2d,
      HalfCheetah; ``threshold`` 2, 2 and 20 metres).
    - ``kind="delayed"``: 0 on every step but the episode's last (terminated or truncated),
      which pays the episode's whole return (LOGO's InvertedDoublePendulum). Wrap the env
      *outside* its ``TimeLimit`` (as ``gymnasium.make`` returns it), so that the time limit's
      last step pays too.
    - ``kind="goal", radius=r``: +1 on every step where the distance to the target is below
      ``r``, else 0 (Reacher: fingertip to target; Pusher: object to goal; in the plane).

    ``position`` (distance only): a callable of the env giving the position along the axis
    of travel; by default ``qpos[0]`` of a Gymnasium MuJoCo env, as the Rust envs use.
    ``goal_distance`` (goal only): a callable of the env giving its distance to the target;
    by default Reacher's and Pusher's, as the Rust envs measure them.
    """

    def __init__(
        self,
        env: gym.Env,
        kind: str,
        threshold: float | None = None,
        position: Callable[[gym.Env], float] | None = None,
        radius: float | None = None,
        goal_distance: Callable[[gym.Env], float] | None = None,
    ):
        super().__init__(env)
        if kind not in KINDS:
            raise LogoValueError(f"unknown sparse kind {kind!r}; the kinds are {', '.join(KINDS)}")
        if kind == "distance":
            if threshold is None or not (float(threshold) > 0 and float(threshold) < float("inf")):
                raise LogoValueError(
                    f"kind 'distance' needs a positive finite threshold (metres), got {threshold!r}"
                )
            if position is None:
                if not hasattr(env.unwrapped, "data"):
                    raise LogoValueError(
                        "kind 'distance' needs position= for an env that is not a Gymnasium "
                        "MuJoCo env (a callable of the env giving its position)"
                    )
                position = _mujoco_x
        elif threshold is not None:
            raise LogoValueError(f"kind {kind!r} takes no threshold")
        if kind == "goal":
            if radius is None or not (float(radius) > 0 and float(radius) < float("inf")):
                raise LogoValueError(f"kind 'goal' needs a positive finite radius (metres), got {radius!r}")
            goal_distance = goal_distance or _mujoco_goal_distance(env) or _info_goal_distance(env)
            if goal_distance is None:
                raise LogoValueError(
                    "kind 'goal' needs goal_distance= for an env other than Gymnasium's Reacher "
                    "and Pusher (a callable of the env giving its distance to the target)"
                )
        elif radius is not None:
            raise LogoValueError(f"kind {kind!r} takes no radius")
        self.kind, self.threshold, self._position = kind, threshold, position
        self.radius, self._goal_distance = radius, goal_distance
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
            info["is_success"] = bool(moved > self.threshold)
            reward = 1.0 if info["is_success"] else 0.0
        elif self.kind == "goal":
            info["is_success"] = bool(self._goal_distance(self.env) < self.radius)
            reward = 1.0 if info["is_success"] else 0.0
        else:
            self._episode_return += float(dense)
            reward = self._episode_return if (terminated or truncated) else 0.0
        return obs, reward, terminated, truncated, info


class Success(gym.Wrapper):
    """Success as you define it: ``info["is_success"] = predicate(obs, info)`` after every
    step, which the trainer reads as the task's own (``success = "task"``: an episode
    reached the goal if any of its steps did). ``train(..., success=predicate)`` wraps its
    ``env=`` in this; wrap the env yourself to resume such a run or to record with it."""

    def __init__(self, env: gym.Env, predicate: Callable[[Any, dict], Any]):
        super().__init__(env)
        check_predicate(predicate, "predicate")
        self._predicate = predicate

    def step(self, action):
        obs, reward, terminated, truncated, info = self.env.step(action)
        verdict = self._predicate(obs, info)
        try:
            reached = bool(verdict)
        except (TypeError, ValueError) as error:  # e.g. an array of several values
            raise LogoTypeError(
                f"the success predicate returned {verdict!r}, expected a bool"
            ) from error
        return obs, reward, terminated, truncated, {**info, "is_success": reached}


def check_predicate(predicate, keyword: str = "success") -> None:
    """Refuses, before any step, a success predicate that cannot be called as
    ``predicate(obs, info)``."""
    if not callable(predicate):
        raise LogoTypeError(
            f"{keyword}={predicate!r}: expected a callable (obs, info) -> bool"
        )
    try:
        signature = inspect.signature(predicate)
    except (TypeError, ValueError):
        return  # a builtin without a signature: its first call says what is wrong
    try:
        signature.bind(None, None)
    except TypeError:
        name = getattr(predicate, "__name__", type(predicate).__name__)
        raise LogoTypeError(
            f"{keyword}={name}{signature}: the predicate is called after every step as "
            f"{keyword}(obs, info) and must take both, e.g. lambda obs, info: obs[0] > 0.45 "
            "(info is the step's info dict)"
        ) from None


def judged(env, predicate) -> Any:
    """``env`` (a Gymnasium id or a maker) made with a :class:`Success` wrapper of
    ``predicate``, under the same name: what ``success=`` as a callable does."""
    check_predicate(predicate)
    if isinstance(env, str):
        make, name = (lambda: gym.make(env)), env
    elif callable(env) and not isinstance(env, gym.Env):
        make, name = env, getattr(env, "__name__", type(env).__name__)
    else:
        return env  # prepare() says what is wrong with it

    def made():
        return Success(make(), predicate)

    made.__name__ = name
    return made
