"""Trained policies in Python: ``logo_rl.load(checkpoint)``."""

from __future__ import annotations

import os

import numpy as np

from ._errors import LogoValueError
from ._logo_rl import Policy as _RustPolicy


class Policy:
    """A checkpoint's Gaussian policy: a tanh MLP for the mean, a state-independent σ.

    :meth:`predict` acts as ``logo eval`` does (the same host kernels, float64), so its
    deterministic actions are ``logo eval``'s. :meth:`state_dict` gives the weights in the
    layout of a torch ``nn.Sequential(Linear, Tanh, ..., Linear)`` of the same sizes.
    """

    def __init__(self, checkpoint: str | os.PathLike):
        if os.path.isdir(checkpoint):
            raise LogoValueError(_folder_message(os.fspath(checkpoint)))
        self._policy = _RustPolicy(os.fspath(checkpoint))

    def __repr__(self) -> str:
        sizes = [self.obs_dim, *self.hidden, self.act_dim]
        return (
            f"Policy({self.env_id}, {self.algorithm}, iteration {self.iteration}, "
            f"mean net {'-'.join(map(str, sizes))}, from {self.path})"
        )

    path = property(lambda self: self._policy.path, doc="The checkpoint file.")
    env_id = property(lambda self: self._policy.env_id, doc="The env it was trained on.")
    obs_dim = property(lambda self: self._policy.obs_dim)
    act_dim = property(lambda self: self._policy.act_dim)
    iteration = property(lambda self: self._policy.iteration, doc="Iterations trained.")
    algorithm = property(lambda self: self._policy.algorithm)
    seed = property(lambda self: self._policy.seed, doc="The training run's seed.")

    @property
    def hidden(self) -> list[int]:
        """The hidden layers' sizes."""
        return [w.shape[0] for w, _ in self._policy.layers()[:-1]]

    @property
    def log_std(self) -> np.ndarray:
        return self._policy.log_std

    @property
    def observation_norm(self) -> dict[str, np.ndarray] | None:
        """``{"mean": ..., "var": ...}`` where the run standardised observations
        (``normalise_observations``): the mean net sees ``clip((obs - mean) / sqrt(var +
        1e-8), -10, 10)``, which :meth:`predict` applies. None otherwise."""
        norm = self._policy.observation_norm
        return None if norm is None else {"mean": norm[0], "var": norm[1]}

    def predict(
        self,
        obs,
        deterministic: bool = True,
        rng: np.random.Generator | None = None,
    ) -> np.ndarray:
        """Actions for ``obs`` (one observation, or a batch ``[rows, obs_dim]``).

        ``deterministic``: the mean action μ(s); else μ(s) + σ·ε with ε ~ N(0, I) from
        ``rng`` (a fresh ``np.random.default_rng()`` when None). Unclipped, as the trainer
        samples them: MuJoCo clamps each action to the control range.
        """
        obs = np.asarray(obs, dtype=np.float64)
        single = obs.ndim == 1
        batch = np.ascontiguousarray(obs.reshape(1, -1) if single else obs)
        if batch.ndim != 2:
            raise LogoValueError(f"observations of shape {obs.shape}: expected [obs_dim] or [rows, obs_dim]")
        actions = self._policy.mean(batch)
        if not deterministic:
            rng = np.random.default_rng() if rng is None else rng
            actions = actions + np.exp(self.log_std) * rng.standard_normal(actions.shape)
        return actions[0] if single else actions

    def state_dict(self) -> dict[str, np.ndarray]:
        """``{"0.weight": [out, in], "0.bias": ..., "2.weight": ..., "log_std": ...}``: the
        keys and layouts of ``torch.nn.Sequential(Linear, Tanh, Linear, Tanh, Linear)``
        (indices 0, 2, 4: the Tanh layers hold no weights), plus ``log_std``, and
        ``observation_mean`` / ``observation_var`` where the policy standardises its
        observations (:attr:`observation_norm`)."""
        state = {}
        for i, (weight, bias) in enumerate(self._policy.layers()):
            state[f"{2 * i}.weight"] = weight
            state[f"{2 * i}.bias"] = bias
        state["log_std"] = self.log_std
        if self.observation_norm is not None:
            # Not torch weights: the standardisation the Sequential's input goes through.
            state["observation_mean"] = self.observation_norm["mean"]
            state["observation_var"] = self.observation_norm["var"]
        return state


# What each policy file of a run or a clone's folder is.
POLICY_FILES = {
    "checkpoint.safetensors": "the final policy",
    "best.safetensors": "the policy whose evaluation earned the most",
    "policy.safetensors": "a behaviour clone (logo_rl.bc)",
}


def _folder_message(folder: str) -> str:
    """What to load from a folder given in place of a policy file."""
    held = sorted(name for name in os.listdir(folder) if name.endswith(".safetensors"))
    if not held:
        return (f"{folder} is a folder with no policy file (*.safetensors) in it: load() "
                "takes a checkpoint file, e.g. runs/<run>/best.safetensors")
    listed = ", ".join(f"{name} ({POLICY_FILES.get(name, 'a policy file')})" for name in held)
    return (f"{folder} is a folder: load() takes one of its policy files, "
            f"{os.path.join(folder, held[0])}; it holds {listed}")


def load(checkpoint: str | os.PathLike) -> Policy:
    """Opens the policy of a checkpoint (``checkpoint.safetensors``, ``best.safetensors``)."""
    return Policy(checkpoint)
