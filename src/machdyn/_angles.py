"""Angle helpers shared by the models (no physics)."""

from __future__ import annotations

import numpy as np

TWO_PI = 2.0 * np.pi


def wrap_pi(angle: np.ndarray | float) -> np.ndarray:
    """Wrap to ``(−π, π]`` (the notes' range of the fundamental angles φij).

    Examples
    --------
    >>> wrap_pi(np.array([np.pi, -np.pi, 3 * np.pi / 2])) / np.pi
    array([ 1. ,  1. , -0.5])
    """
    return np.pi - np.mod(np.pi - np.asarray(angle, dtype=np.float64), TWO_PI)


def wrap_2pi(angle: np.ndarray | float) -> np.ndarray:
    """Wrap to ``[0, 2π)`` (the notes' convention for θ2, θ3, θ4).

    Examples
    --------
    >>> wrap_2pi(np.array([-np.pi / 2, 2 * np.pi, -1e-300])) / np.pi
    array([1.5, 0. , 0. ])
    """
    out = np.mod(np.asarray(angle, dtype=np.float64), TWO_PI)
    # A tiny negative angle (rounding of 0) would land at 2π − ε: report it as 0.
    return np.where(out >= TWO_PI - 4 * np.finfo(float).eps * TWO_PI, 0.0, out)
