"""Small argument checks shared by every module.

They raise :class:`machdyn.errors.InputError` naming the field, and accept pint
quantities (converted to ``unit`` once, at the boundary) as well as plain
numbers or arrays.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import numpy as np

from .errors import InputError

__all__ = [
    "as_array",
    "broadcast",
    "choice",
    "finite_array",
    "finite_scalar",
    "input_motion",
    "integer",
    "magnitude",
    "nonnegative",
    "positive",
]


def magnitude(value: Any, unit: str | None = None, field: str = "value") -> Any:
    """Return ``value`` as a plain number/array, converting a pint quantity.

    Pint is not imported here: anything with ``.to`` and ``.magnitude`` is
    treated as a quantity, so plain floats cost nothing.

    Examples
    --------
    >>> magnitude(2.5)
    2.5
    """
    if hasattr(value, "magnitude") and hasattr(value, "to"):
        if unit is None:
            return value.magnitude
        try:
            return value.to(unit).magnitude
        except Exception as exc:  # pint.DimensionalityError and friends
            raise InputError(field, f"cannot be expressed in {unit}: {exc}") from None
    return value


def finite_scalar(field: str, value: Any, unit: str | None = None) -> float:
    """Return ``value`` as a finite float or raise :class:`InputError`.

    Examples
    --------
    >>> finite_scalar("omega2", 3)
    3.0
    """
    value = magnitude(value, unit, field)
    try:
        out = float(value)
    except (TypeError, ValueError):
        raise InputError(field, f"must be a real number, got {value!r}") from None
    if not np.isfinite(out):
        raise InputError(field, f"must be finite, got {out}")
    return out


def positive(field: str, value: Any, unit: str | None = None) -> float:
    """Return ``value`` as a float > 0 or raise :class:`InputError`.

    Examples
    --------
    >>> positive("r2", 4)
    4.0
    >>> positive("r2", 0)
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: r2: must be positive, got 0.0
    """
    out = finite_scalar(field, value, unit)
    if out <= 0.0:
        raise InputError(field, f"must be positive, got {out}")
    return out


def nonnegative(field: str, value: Any, unit: str | None = None) -> float:
    """Return ``value`` as a float >= 0 or raise :class:`InputError`."""
    out = finite_scalar(field, value, unit)
    if out < 0.0:
        raise InputError(field, f"must be zero or positive, got {out}")
    return out


def integer(field: str, value: Any, minimum: int | None = None) -> int:
    """Return ``value`` as an int (rejecting fractions) or raise :class:`InputError`.

    Examples
    --------
    >>> integer("teeth", 20.0, minimum=1)
    20
    >>> integer("teeth", 20.5)
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: teeth: must be a whole number, got 20.5
    """
    if isinstance(value, str | bytes | bool | np.bool_):
        raise InputError(field, f"must be a whole number, got {value!r}")
    try:
        as_float = float(value)
    except (TypeError, ValueError):
        raise InputError(field, f"must be a whole number, got {value!r}") from None
    if not np.isfinite(as_float) or as_float != int(as_float):
        raise InputError(field, f"must be a whole number, got {value!r}")
    out = int(as_float)
    if minimum is not None and out < minimum:
        raise InputError(field, f"must be at least {minimum}, got {out}")
    return out


def as_array(field: str, value: Any, unit: str | None = None) -> np.ndarray:
    """Return ``value`` as a float64 array (any shape) or raise :class:`InputError`."""
    value = magnitude(value, unit, field)
    try:
        return np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError(field, f"must be a number or an array of numbers, got {value!r}") from None


def finite_array(field: str, value: Any, unit: str | None = None) -> np.ndarray:
    """Return ``value`` as a finite float64 array or raise :class:`InputError`.

    Examples
    --------
    >>> finite_array("theta2", [0.0, float("nan")])
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: theta2: must be finite; sample 1 is nan
    """
    out = as_array(field, value, unit)
    bad = ~np.isfinite(out)
    if bad.any():
        index = int(np.flatnonzero(bad.ravel())[0])
        raise InputError(field, f"must be finite; sample {index} is {out.ravel()[index]}")
    return out


def choice(field: str, value: Any, options: Iterable[Any]) -> Any:
    """Return ``value`` if it is one of ``options``, else raise listing them.

    Examples
    --------
    >>> choice("form", 1, (1, 2))
    1
    >>> choice("form", 3, (1, 2))
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: form: must be one of 1, 2; got 3
    """
    options = tuple(options)
    if value not in options:
        listed = ", ".join(str(o) for o in options)
        raise InputError(field, f"must be one of {listed}; got {value!r}")
    return value


def common_length_unit(**lengths: Any) -> tuple[dict[str, float], str | None]:
    """Convert lengths that may be pint quantities to plain floats in one unit.

    If any length carries a unit, all must: they are converted to the unit of
    the first one, which is returned (``None`` for plain numbers).

    Examples
    --------
    >>> common_length_unit(r1=8, r2=4)
    ({'r1': 8.0, 'r2': 4.0}, None)
    """
    has_unit = {k: hasattr(v, "magnitude") and hasattr(v, "to") for k, v in lengths.items()}
    if not any(has_unit.values()):
        return {k: finite_scalar(k, v) for k, v in lengths.items()}, None
    missing = [k for k, u in has_unit.items() if not u]
    if missing:
        raise InputError(missing[0], "give every length with a unit, or none (others carry units)")
    first_name, first = next(iter(lengths.items()))
    if str(getattr(first, "dimensionality", "[length]")) != "[length]":
        raise InputError(first_name, f"must be a length, got a quantity in {first.units}")
    unit = str(first.units)
    return {k: finite_scalar(k, v, unit) for k, v in lengths.items()}, unit


def broadcast(**arrays: Any) -> tuple[int, ...]:
    """The common shape of named arrays, or :class:`InputError` naming the misfit.

    Used by every model and analysis that takes several array arguments.

    Examples
    --------
    >>> broadcast(theta2=np.zeros(3), omega2=1.0)
    (3,)
    >>> broadcast(theta2=np.zeros(3), omega2=np.ones(2))
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: omega2: shape (2,) does not broadcast with theta2 (3,)
    """
    shape: tuple[int, ...] = ()
    seen: list[str] = []
    for field, value in arrays.items():
        value_shape = np.shape(value)
        try:
            shape = np.broadcast_shapes(shape, value_shape)
        except ValueError:
            others = ", ".join(f"{name} {np.shape(arrays[name])}" for name in seen)
            raise InputError(
                field, f"shape {value_shape} does not broadcast with {others}"
            ) from None
        seen.append(field)
    return shape


def input_motion(
    theta2: Any, omega2: Any, alpha2: Any, jerk2: Any
) -> tuple[tuple[int, ...], list[np.ndarray]]:
    """Validate an input link's angle and rates; return their common shape and the arrays.

    Pint quantities are converted to radians and radians per second (squared,
    cubed); every value must be finite, and the four must broadcast together.

    Examples
    --------
    >>> shape, (t, w, a, j) = input_motion([0.0, 1.0], 2.0, 0.0, 0.0)
    >>> shape, w.tolist()
    ((2,), [2.0, 2.0])
    """
    theta2 = finite_array("theta2", theta2, "radian")
    omega2 = finite_array("omega2", omega2, "radian / second")
    alpha2 = finite_array("alpha2", alpha2, "radian / second ** 2")
    jerk2 = finite_array("jerk2", jerk2, "radian / second ** 3")
    shape = broadcast(theta2=theta2, omega2=omega2, alpha2=alpha2, jerk2=jerk2)
    return shape, [np.broadcast_to(x, shape).astype(float) for x in (theta2, omega2, alpha2, jerk2)]
