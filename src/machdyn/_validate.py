"""Small argument checks shared by every module.

They raise :class:`machdyn.errors.InputError` naming the field, and accept pint
quantities (converted to ``unit`` once, at the boundary) as well as plain
numbers or arrays.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any

import numpy as np

from ._parallel import require_memory
from .errors import InputError
from .units import warn_if_degrees

__all__ = [
    "as_array",
    "boolean",
    "broadcast",
    "choice",
    "complex_array",
    "complex_scalar",
    "count",
    "finite_array",
    "finite_scalar",
    "in_range",
    "input_motion",
    "instance",
    "integer",
    "is_scalar",
    "items",
    "magnitude",
    "nonnegative",
    "point",
    "positive",
    "positive_length",
    "text",
]


#: Largest magnitude of any number machdyn computes with. Beyond it the products an
#: analysis forms (ω³·r, m·r·ω², r⁴ …) could overflow double precision (1.8e308), so a
#: larger input is refused with this reason rather than answered with inf or NaN.
LIMIT = 1e50
#: Smallest positive length, mass, speed … (its reciprocal, squared, stays below LIMIT²).
TINY = 1e-50
#: Lengths of the scale-free closed forms (FourBar, SliderCrank): they work on length
#: ratios, so their lengths may span this wider window (rates are checked against it).
LENGTH_LIMIT = 1e250
#: Largest value a result may reach before the analysis refuses its inputs.
RESULT_LIMIT = 1e300


def _is_quantity(value: Any) -> bool:
    return hasattr(value, "magnitude") and hasattr(value, "to") and hasattr(value, "units")


def magnitude(value: Any, unit: str | None = None, field: str = "value") -> Any:
    """Return ``value`` as a plain number/array, converting a pint quantity.

    With ``unit``, a quantity is converted to it (a quantity of another
    dimension is an :class:`InputError`). Without, only a dimensionless
    quantity is accepted (an angle in degrees becomes radians): the numeric API
    takes plain numbers in any consistent system, and a quantity in seconds
    given as a length is refused rather than stripped of its unit.

    Pint is not imported here: anything with ``.to``, ``.units`` and
    ``.magnitude`` is treated as a quantity, so plain floats cost nothing.

    Examples
    --------
    >>> magnitude(2.5)
    2.5
    """
    if not _is_quantity(value):
        return value
    if unit is None:
        if getattr(value, "dimensionless", False):
            return value.to("dimensionless").magnitude
        raise InputError(
            field,
            f"takes a plain number in one consistent unit system, not a quantity in "
            f"{value.units} (pass its magnitude in the units of the other inputs)",
        )
    try:
        return value.to(unit).magnitude
    except Exception as exc:  # pint.DimensionalityError and friends
        raise InputError(field, f"cannot be expressed in {unit}: {exc}") from None


def _describe(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 60 else f"{text[:57]}..."


def _real(field: str, value: Any, unit: str | None) -> float:
    """One real number (not a bool, a complex, a string or an array) as a float."""
    value = magnitude(value, unit, field)
    if isinstance(value, bool | np.bool_):
        raise InputError(field, f"must be a number, got the bool {value!r}")
    if isinstance(value, complex | np.complexfloating):
        raise InputError(
            field,
            f"must be a real number, got the complex {value!r} (its imaginary part is not 0)"
            if value.imag
            else f"must be a real number, got the complex {value!r}",
        )
    if isinstance(value, np.ndarray):
        if value.ndim != 0:
            raise InputError(field, f"must be one number, got an array of shape {value.shape}")
        if value.dtype.kind not in "fiu":
            raise InputError(field, f"must be a real number, got {value.dtype} {value!r}")
    elif isinstance(value, list | tuple):
        raise InputError(field, f"must be one number, got {_describe(value)}")
    try:
        return float(value)
    except OverflowError:
        raise InputError(
            field, "is too large for a floating-point number (beyond ±1.8e308)"
        ) from None
    except (TypeError, ValueError):
        raise InputError(field, f"must be a real number, got {_describe(value)}") from None


def finite_scalar(
    field: str, value: Any, unit: str | None = None, *, limit: float = LIMIT
) -> float:
    """Return ``value`` as a finite float or raise :class:`InputError`.

    Refused: None, text, bools, complex numbers, arrays, non-finite values,
    values beyond ``±limit``, integers beyond the float range and quantities of
    another dimension.

    Examples
    --------
    >>> finite_scalar("omega2", 3)
    3.0
    >>> finite_scalar("omega2", 1 + 2j)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: omega2: must be a real number, got the complex (1+2j) ...
    """
    if type(value) in (float, int) and -limit <= value <= limit:  # False for NaN
        return float(value)  # a plain number in range: what the checks below return
    out = _real(field, value, unit)
    if not np.isfinite(out):
        raise InputError(field, f"must be finite, got {out}")
    if abs(out) > limit:
        raise InputError(field, f"{out:g} is beyond ±{limit:g}, the range machdyn computes in")
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
    if out < TINY:
        raise InputError(field, f"{out:g} is below {TINY:g}, the range machdyn computes in")
    return out


def nonnegative(field: str, value: Any, unit: str | None = None) -> float:
    """Return ``value`` as a float >= 0 or raise :class:`InputError`.

    A positive value below :data:`TINY` is refused too: 1e-320 as a roller
    radius is neither a knife edge (0) nor a roller machdyn can compute with.

    Examples
    --------
    >>> nonnegative("roller_radius", 0)
    0.0
    >>> nonnegative("roller_radius", 1e-320)
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: roller_radius: 1e-320 is below 1e-50; give 0 or use smaller units
    """
    out = finite_scalar(field, value, unit)
    if out < 0.0:
        raise InputError(field, f"must be zero or positive, got {out}")
    if 0.0 < out < TINY:
        raise InputError(field, f"{out:g} is below {TINY:g}; give 0 or use smaller units")
    return out


def in_range(
    field: str,
    value: Any,
    lo: float = -np.inf,
    hi: float = np.inf,
    *,
    lo_open: bool = False,
    hi_open: bool = False,
    unit: str | None = None,
) -> float:
    """Return ``value`` as a finite float in ``[lo, hi]`` (ends open if asked) or raise.

    Examples
    --------
    >>> in_range("tol", 1e-9, 0.0, 1.0, lo_open=True)
    1e-09
    >>> in_range("tol", 0.0, 0.0, 1.0, lo_open=True)
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: tol: must be in (0, 1], got 0.0
    """
    out = finite_scalar(field, value, unit)
    below = out <= lo if lo_open else out < lo
    above = out >= hi if hi_open else out > hi
    if below or above:
        left, right = "(" if lo_open else "[", ")" if hi_open else "]"
        raise InputError(field, f"must be in {left}{lo:g}, {hi:g}{right}, got {out}")
    return out


def integer(field: str, value: Any, minimum: int | None = None, maximum: int | None = None) -> int:
    """Return ``value`` as an int (rejecting fractions) or raise :class:`InputError`.

    ``maximum`` bounds sizes and counts (samples, points, iterations).

    Examples
    --------
    >>> integer("teeth", 20.0, minimum=1)
    20
    >>> integer("teeth", 20.5)
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: teeth: must be a whole number, got 20.5
    >>> integer("n", 10**9, maximum=10**7)
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: n: must be at most 10000000, got 1000000000
    """
    if isinstance(value, str | bytes | bool | np.bool_ | complex | np.complexfloating):
        raise InputError(field, f"must be a whole number, got {_describe(value)}")
    if isinstance(value, int | np.integer):
        out = int(value)
    else:
        as_float = _real(field, value, None) if not _is_quantity(value) else None
        if as_float is None:
            as_float = _real(field, value, "dimensionless")
        if not np.isfinite(as_float) or as_float != int(as_float):
            raise InputError(field, f"must be a whole number, got {_describe(value)}")
        out = int(as_float)
    if minimum is not None and out < minimum:
        raise InputError(field, f"must be at least {minimum}, got {out}")
    if maximum is not None and out > maximum:
        raise InputError(field, f"must be at most {maximum}, got {_describe(out)}")
    return out


def count(
    field: str, value: Any, minimum: int = 1, bytes_each: float = 0.0, what: str = "samples"
) -> int:
    """A size (samples, points, iterations): a whole number ≥ ``minimum`` within the memory budget.

    ``bytes_each`` is what one unit costs in memory; the total must fit the
    budget of :func:`machdyn._parallel.memory_limit`.

    Examples
    --------
    >>> count("n", 360, bytes_each=200)
    360
    >>> count("n", 0)
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: n: must be at least 1, got 0
    """
    n = integer(field, value, minimum=minimum)
    if bytes_each:
        require_memory(field, n * bytes_each, f"{n:,} {what}")
    return n


def boolean(field: str, value: Any) -> bool:
    """Return ``value`` if it is a bool (Python or NumPy), else raise :class:`InputError`.

    Examples
    --------
    >>> boolean("crossed", False)
    False
    >>> boolean("crossed", "no")
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: crossed: must be True or False, got 'no'
    """
    if isinstance(value, bool | np.bool_):
        return bool(value)
    raise InputError(field, f"must be True or False, got {_describe(value)}")


def text(field: str, value: Any) -> str:
    """Return ``value`` if it is a non-empty string, else raise :class:`InputError`."""
    if isinstance(value, str) and value:
        return value
    raise InputError(field, f"must be a non-empty name (text), got {_describe(value)}")


def mapping(field: str, value: Any, what: str = "values") -> dict[str, Any]:
    """``value`` as a dict if it is a mapping with text keys, else raise :class:`InputError`.

    Examples
    --------
    >>> mapping("velocity", {"theta2": 10.0})
    {'theta2': 10.0}
    >>> mapping("velocity", 10.0, "rates by input name")
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: velocity: must be a mapping of names to rates by input name, got 10.0
    """
    if not isinstance(value, Mapping):
        raise InputError(field, f"must be a mapping of names to {what}, got {_describe(value)}")
    bad = [k for k in value if not isinstance(k, str)]
    if bad:
        raise InputError(field, f"names are text, got the key {_describe(bad[0])}")
    return dict(value)


def names(field: str, value: Any, what: str = "names") -> tuple[str, ...]:
    """A sequence of non-empty names (text) as a tuple, else raise :class:`InputError`.

    Examples
    --------
    >>> names("inputs", ["theta2", "theta5"])
    ('theta2', 'theta5')
    """
    if isinstance(value, str):
        raise InputError(field, f"must be a sequence of {what}, got the text {value!r}")
    return tuple(text(field, n) for n in items(field, value, what=what))


def _array(field: str, value: Any, unit: str | None, kinds: str, what: str) -> np.ndarray:
    """``value`` as an array whose dtype kind is in ``kinds`` (before conversion)."""
    value = magnitude(value, unit, field)
    if value is None or isinstance(value, str | bytes):
        raise InputError(field, f"must be {what}, got {_describe(value)}")
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError):
        raise InputError(
            field, f"must be {what} (a number or a rectangular array), got {_describe(value)}"
        ) from None
    kind = arr.dtype.kind
    if kind == "O":
        try:
            converted = arr.astype(complex if "c" in kinds else np.float64)
        except OverflowError:
            raise InputError(field, "holds a value too large for a floating-point number") from None
        except (TypeError, ValueError):
            raise InputError(field, f"must be {what}, got {_describe(value)}") from None
        if any(isinstance(v, bool | str | np.bool_) for v in arr.ravel()[:1000]):
            raise InputError(field, f"must be {what}, got {_describe(value)}")
        return converted
    if kind == "c" and "c" not in kinds:
        raise InputError(
            field,
            f"must be real, got complex values (the imaginary part would be lost): "
            f"{_describe(value)}",
        )
    if kind not in kinds + "iu" or kind == "b":
        raise InputError(field, f"must be {what}, got {arr.dtype} values {_describe(value)}")
    return arr


def as_array(field: str, value: Any, unit: str | None = None) -> np.ndarray:
    """Return ``value`` as a float64 array (any shape) or raise :class:`InputError`.

    Refused: None, text, bools, complex values, ragged lists and integers beyond
    the float range (non-finite values pass: see :func:`finite_array`).

    Examples
    --------
    >>> as_array("theta2", [1, 2]).tolist()
    [1.0, 2.0]
    >>> as_array("theta2", [1j])  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: theta2: must be real, got complex values (the imaginary part ...
    """
    return _array(field, value, unit, "f", "a number or an array of numbers").astype(
        np.float64, copy=False
    )


def finite_array(
    field: str, value: Any, unit: str | None = None, *, nan_ok: bool = False
) -> np.ndarray:
    """Return ``value`` as a finite float64 array or raise :class:`InputError`.

    With ``nan_ok``, NaN passes (a sample already marked unsolved, such as an
    unassembled pose from :func:`machdyn.fourbar.positions`; it stays NaN in
    what is computed from it); ±inf never does.

    Examples
    --------
    >>> finite_array("theta2", [0.0, float("nan")])
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: theta2: must be finite; sample 1 is nan
    """
    if type(value) in (float, int) and -LIMIT <= value <= LIMIT:  # False for NaN
        # a plain number in range (a guess, a steady speed): the array as_array would
        # make, without its checks (each a reduction over a 0-d array, a few µs)
        return np.array(float(value))
    out = as_array(field, value, unit)
    _require_finite(field, out, nan_ok)
    return out


def _require_finite(field: str, out: np.ndarray, nan_ok: bool = False) -> None:
    """Every value finite and within ±LIMIT (two reductions, no temporary array)."""
    if out.size == 0:
        return
    parts = (out.real, out.imag) if out.dtype.kind == "c" else (out,)
    if all(p.min() >= -LIMIT and p.max() <= LIMIT for p in parts):
        return  # NaN fails both comparisons
    flat = out.ravel()
    if nan_ok:
        flat = flat[~np.isnan(flat)]
        if flat.size == 0 or (flat.min() >= -LIMIT and flat.max() <= LIMIT):
            return
    bad = ~np.isfinite(flat)
    if bad.any():
        index = int(np.flatnonzero(bad)[0])
        raise InputError(field, f"must be finite; sample {index} is {flat[index]}")
    index = int(np.flatnonzero(np.abs(flat) > LIMIT)[0])
    raise InputError(
        field, f"sample {index} ({flat[index]:g}) is beyond ±{LIMIT:g}, the range machdyn handles"
    )


def complex_array(
    field: str, value: Any, unit: str | None = None, *, nan_ok: bool = False
) -> np.ndarray:
    """Return ``value`` as a finite complex128 array (points ``x + jy``) or raise.

    Real numbers are points on the x axis. Refused: None, text, bools, ragged
    lists, non-finite values (NaN passes with ``nan_ok``, as in
    :func:`finite_array`).

    Examples
    --------
    >>> complex_array("c", [1, 2j]).tolist()
    [(1+0j), 2j]
    """
    out = _array(field, value, unit, "fc", "a complex number x + jy or an array of them")
    out = out.astype(complex, copy=False)
    _require_finite(field, out, nan_ok)
    return out


def complex_scalar(field: str, value: Any, unit: str | None = None) -> complex:
    """Return ``value`` as one finite complex number ``x + jy`` or raise :class:`InputError`.

    Examples
    --------
    >>> complex_scalar("cg", 3)
    (3+0j)
    """
    out = complex_array(field, value, unit)
    if out.ndim != 0:
        raise InputError(field, f"must be one point x + jy, got an array of shape {out.shape}")
    return complex(out)


def point(field: str, value: Any, unit: str | None = None) -> complex:
    """A point given as ``x + jy`` or as a pair ``(x, y)``, as one finite complex number.

    Examples
    --------
    >>> point("A", (1, 2))
    (1+2j)
    >>> point("A", 1 + 2j)
    (1+2j)
    """
    if isinstance(value, list | tuple) or (isinstance(value, np.ndarray) and value.ndim == 1):
        if len(value) != 2:
            raise InputError(field, f"a point is (x, y) or x + yj, got {_describe(value)}")
        x, y = value
        return complex(finite_scalar(f"{field} x", x, unit), finite_scalar(f"{field} y", y, unit))
    return complex_scalar(field, value, unit)


def items(field: str, value: Any, count: int | None = None, what: str = "values") -> tuple:
    """``value`` (a list, tuple or array) as a tuple, with ``count`` items if given.

    Examples
    --------
    >>> items("mass", [1, 2, 3], 3)
    (1, 2, 3)
    >>> items("mass", 2.0, 3, "masses (links 2, 3, 4)")
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: mass: must be a sequence of 3 masses (links 2, 3, 4), got 2.0
    """
    size = "" if count is None else f"{count} "
    scalar_quantity = _is_quantity(value) and not np.ndim(value.magnitude)
    if value is None or isinstance(value, str | bytes) or scalar_quantity:
        raise InputError(field, f"must be a sequence of {size}{what}, got {_describe(value)}")
    try:
        out = tuple(value)
    except TypeError:
        raise InputError(
            field, f"must be a sequence of {size}{what}, got {_describe(value)}"
        ) from None
    if count is not None and len(out) != count:
        raise InputError(field, f"must have exactly {count} {what}, got {len(out)}")
    return out


def instance(field: str, value: Any, kind: type | tuple[type, ...], what: str = "") -> Any:
    """``value`` if it is an instance of ``kind``, else :class:`InputError` saying what is wanted.

    Examples
    --------
    >>> instance("fourbar", 3, dict, "a FourBar")
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: fourbar: must be a FourBar, got 3
    """
    if isinstance(value, kind):
        return value
    if not what:
        kinds = kind if isinstance(kind, tuple) else (kind,)
        what = " or ".join(f"a {k.__name__}" for k in kinds)
    raise InputError(field, f"must be {what}, got {_describe(value)}")


def is_scalar(value: Any) -> bool:
    """Whether ``value`` is one number (``np.ndim`` 0); False for ragged lists too.

    Examples
    --------
    >>> is_scalar(1.0), is_scalar([1.0]), is_scalar([[1.0], [2.0, 3.0]])
    (True, False, False)
    """
    try:
        return np.ndim(value) == 0
    except ValueError:
        return False


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
    if not isinstance(value, np.ndarray):
        flag = isinstance(value, bool | np.bool_)
        for option in options:
            if flag != isinstance(option, bool | np.bool_):
                continue  # True is not the option 1, nor 1 the option True
            try:
                same = value == option
            except Exception:  # a value that cannot even be compared is not an option
                continue
            if same is True or same is np.True_:
                return option
    listed = ", ".join(str(o) for o in options)
    raise InputError(field, f"must be one of {listed}; got {_describe(value)}")


def common_length_unit(**lengths: Any) -> tuple[dict[str, float], str | None]:
    """Convert lengths that may be pint quantities to plain floats in one unit.

    If any length carries a unit, all must: they are converted to the unit of
    the first one, which is returned (``None`` for plain numbers). A plain 0
    (an offset left at its default) is zero in any unit and needs none.

    Examples
    --------
    >>> common_length_unit(r1=8, r2=4)
    ({'r1': 8.0, 'r2': 4.0}, None)
    """
    has_unit = {k: _is_quantity(v) for k, v in lengths.items()}
    unit = None
    if any(has_unit.values()):
        missing = [k for k, u in has_unit.items() if not u and not _plain_zero(lengths[k])]
        if missing:
            raise InputError(
                missing[0], "give every length with a unit, or none (others carry units)"
            )
        first_name, first = next((k, v) for k, v in lengths.items() if has_unit[k])
        if str(getattr(first, "dimensionality", "[length]")) != "[length]":
            raise InputError(first_name, f"must be a length, got a quantity in {first.units}")
        unit = str(first.units)
    out = {k: length(k, v, unit) for k, v in lengths.items()}
    return out, unit


def _plain_zero(value: Any) -> bool:
    """True for a plain number 0 (not a bool, not a quantity)."""
    return (
        isinstance(value, int | float | np.integer | np.floating)
        and not isinstance(value, bool)
        and float(value) == 0.0
    )


def positive_length(field: str, value: Any, unit: str | None = None) -> float:
    """A link length of a scale-free closed form: positive, at most 1e250, not subnormal.

    Examples
    --------
    >>> positive_length("r2", 4)
    4.0
    >>> positive_length("r4", 1e-320)
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: r4: 1e-320 is subnormal (below 2.2e-308); use smaller units
    """
    out = length(field, value, unit)
    if out <= 0.0:
        raise InputError(field, f"must be a positive length, got {out:g}")
    if out < _SMALLEST_NORMAL:
        raise InputError(field, f"{out:g} is subnormal (below 2.2e-308); use smaller units")
    return out


def length(field: str, value: Any, unit: str | None = None) -> float:
    """A length (or offset) of a scale-free closed form: finite and within ±1e250.

    Examples
    --------
    >>> length("offset", -8e-200)
    -8e-200
    """
    return finite_scalar(field, value, unit, limit=LENGTH_LIMIT)


_SMALLEST_NORMAL = float(np.finfo(np.float64).tiny)


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
        try:
            value_shape = np.shape(value)
        except ValueError:
            message = "must be a number or a rectangular array (rows differ)"
            raise InputError(field, message) from None
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
    theta2: Any,
    omega2: Any,
    alpha2: Any,
    jerk2: Any,
    bytes_per_sample: float = 0.0,
    length: float = 1.0,
) -> tuple[tuple[int, ...], list[np.ndarray]]:
    """Validate an input link's angle and rates; return their common shape and the arrays.

    Pint quantities are converted to radians and radians per second (squared,
    cubed); every value must be finite, and the four must broadcast together.
    A caller whose results cost ``bytes_per_sample`` per pose has the total
    checked against the memory budget before any work. For links up to
    ``length`` long the points' velocities, accelerations and jerks are of order
    ``length · (ω + ω² + |α| + ω³ + |α ω| + |jerk|)``: rates that would carry
    them past :data:`RESULT_LIMIT` are refused.

    Examples
    --------
    >>> shape, (t, w, a, j) = input_motion([0.0, 1.0], 2.0, 0.0, 0.0)
    >>> shape, w.tolist()
    ((2,), [2.0, 2.0])
    """
    if bytes_per_sample:  # before any conversion: a broadcast view of 10^8 poses costs nothing yet
        _budget("theta2", bytes_per_sample + 32, theta2, omega2, alpha2, jerk2)
    theta2 = finite_array("theta2", theta2, "radian")
    warn_if_degrees("theta2", theta2, stacklevel=4)  # the caller of solve() is warned
    omega2 = finite_array("omega2", omega2, "radian / second")
    alpha2 = finite_array("alpha2", alpha2, "radian / second ** 2")
    jerk2 = finite_array("jerk2", jerk2, "radian / second ** 3")
    shape = broadcast(theta2=theta2, omega2=omega2, alpha2=alpha2, jerk2=jerk2)
    _rates_within(length, omega2=omega2, alpha2=alpha2, jerk2=jerk2)
    if bytes_per_sample:
        n = int(np.prod(shape))
        require_memory("theta2", n * (bytes_per_sample + 32), f"{n:,} poses")
    return shape, [np.broadcast_to(x, shape).astype(float) for x in (theta2, omega2, alpha2, jerk2)]


def _budget(field: str, bytes_each: float, *values: Any) -> None:
    """Check the memory budget from the shapes of arrays (and quantities) not yet converted.

    Values without a ``shape`` (lists, numbers) are already in memory at their
    full size and are checked after conversion; shapes that do not broadcast
    are left to :func:`broadcast`, which names the field.
    """
    shapes = [np.shape(v) for v in values if hasattr(v, "shape")]
    try:
        n = int(np.prod(np.broadcast_shapes(*shapes), dtype=float))
    except (ValueError, TypeError):
        return
    require_memory(field, n * bytes_each, f"{n:,} poses")


def _rates_within(length: float, **rates: np.ndarray) -> None:
    """Refuse input rates whose point jerks would overflow for links ``length`` long."""
    w, a, j = (
        float(max(-x.min(), x.max())) if x.size else 0.0 for x in rates.values()
    )  # |max|, from two reductions without a temporary
    terms = {"omega2": max(w, w * w, w**3), "alpha2": max(a, a * w), "jerk2": j}
    worst = max(terms, key=lambda k: terms[k])
    if length * max(1.0, terms[worst]) > RESULT_LIMIT:
        raise InputError(
            worst,
            f"is too large for links {length:g} long: the points' rates would exceed "
            f"{RESULT_LIMIT:g} (choose time units that bring the rates down)",
        )
