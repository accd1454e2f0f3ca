"""Estimates over a few seeds, as :func:`logo_rl.compare` and the suite report them: the
interquartile mean (IQM), a 95% percentile-bootstrap interval, and the probability of
improvement P(X > Y) (ties count one half), each as rliable defines it for one task."""

from __future__ import annotations

import math
from typing import Callable, Sequence

import numpy as np


def iqm(values: Sequence[float]) -> float:
    """The mean of the middle half (scipy's trim_mean at 25%, as rliable's IQM)."""
    v = np.sort(np.asarray(values, dtype=float))
    cut = int(math.floor(0.25 * len(v)))
    return float(v[cut:len(v) - cut].mean())


def probability_of_improvement(x: Sequence[float], y: Sequence[float]) -> float:
    """P(X > Y) + P(X = Y) / 2 over all pairs of a value of x and one of y."""
    a, b = np.asarray(x, dtype=float)[:, None], np.asarray(y, dtype=float)[None, :]
    return float(np.mean((a > b) + 0.5 * (a == b)))


def interval(values: Sequence[float], stat: Callable = iqm, reps: int = 20_000,
             rng: np.random.Generator | None = None) -> tuple[float, float]:
    """The 95% percentile-bootstrap interval of ``stat`` over resamples of the seeds."""
    rng = rng if rng is not None else np.random.default_rng(0)
    x = np.asarray(values, dtype=float)
    draws = [stat(rng.choice(x, len(x))) for _ in range(reps)]
    return float(np.percentile(draws, 2.5)), float(np.percentile(draws, 97.5))


def interval_two(x: Sequence[float], y: Sequence[float], stat: Callable, reps: int = 20_000,
                 rng: np.random.Generator | None = None) -> tuple[float, float]:
    """The 95% percentile-bootstrap interval of ``stat(x, y)`` over independent resamples
    of x's and y's seeds."""
    rng = rng if rng is not None else np.random.default_rng(0)
    a, b = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    draws = [stat(rng.choice(a, len(a)), rng.choice(b, len(b))) for _ in range(reps)]
    return float(np.percentile(draws, 2.5)), float(np.percentile(draws, 97.5))
