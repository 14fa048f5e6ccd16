"""Argument checks shared by the gears modules (private).

They raise :class:`machdyn.errors.InputError` naming the offending argument,
so that a shape clash or an angle in degrees never surfaces as a bare numpy
error or a silently wrong number.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .._validate import LIMIT, TINY, as_array, magnitude
from ..errors import InputError

__all__ = ["finite", "pressure_angle_array"]


def finite(field: str, value: Any, message: str) -> np.ndarray:
    """Return ``value`` as a float array, raising ``InputError(field, message)`` if not finite.

    Examples
    --------
    >>> finite("k", [1.0, 0.8], "must be finite").tolist()
    [1.0, 0.8]
    """
    out = as_array(field, value)
    if not np.all(np.isfinite(out)):
        raise InputError(field, f"{message}, got {_short(value)}")
    size = np.abs(out)
    if np.any(size > LIMIT) or np.any((size > 0.0) & (size < TINY)):
        raise InputError(
            field, f"{message} within 1e-50 … 1e50 in magnitude (or 0), got {_short(value)}"
        )
    return out


def _short(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 60 else f"{text[:57]}..."


def pressure_angle_array(value: Any, upper_deg: float = 90.0) -> np.ndarray:
    """Return a pressure angle in radians, ``0 < φ < upper``, or raise.

    A pint quantity is converted; a plain number must be in radians, and the
    error points out a value that looks like degrees.

    Examples
    --------
    >>> float(pressure_angle_array(0.35))
    0.35
    >>> pressure_angle_array(20)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: pressure_angle: ... got 20; did you pass degrees? use np.radians(20)
    """
    phi = as_array("pressure_angle", magnitude(value, "radian", "pressure_angle"))
    upper = math.radians(upper_deg)
    bad = ~np.isfinite(phi) | (phi < TINY) | (phi >= upper)
    if np.any(bad):
        first = float(phi.ravel()[int(np.flatnonzero(bad.ravel())[0])])
        hint = f"; did you pass degrees? use np.radians({first:g})" if upper <= first < 90.0 else ""
        raise InputError(
            "pressure_angle",
            f"must be in radians between 0 and {upper:.4g} ({upper_deg:g}°), got {first:g}{hint}",
        )
    return phi
