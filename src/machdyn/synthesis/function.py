"""Function generation: a four-bar whose output angle is a function of its input angle.

Freudenstein's equation (Norton, *Design of Machinery*, ch. 4 and 5)
follows from the loop ``a e^{jθ2} + b e^{jθ3} − c e^{jθ4} − d = 0`` by
isolating ``b e^{jθ3}`` and taking its squared length:

``K1 cos θ4 − K2 cos θ2 + K3 = cos(θ2 − θ4)``,
``K1 = d/a``, ``K2 = d/c``, ``K3 = (a² − b² + c² + d²) / (2 a c)``.

It is linear in ``K1, K2, K3``: three precision points give them exactly,
more points by least squares. A function ``y = f(x)`` on ``[x0, xf]`` is
mapped linearly onto the input range ``θ2`` and the output range ``θ4``; the
precision points are best spaced by Chebyshev's rule, and between them the
linkage carries a *structural error* ``y_generated − f(x)``.

A negative ``a`` (or ``c``) means that link points the other way: the
linkage is built with ``|a|`` and its input angle is ``θ2 + π``
(``input_offset``); likewise ``output_offset`` for link 4.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from .._angles import wrap_pi
from .._validate import choice, count, finite_array, finite_scalar, items, positive
from ..errors import AssemblyError, InputError
from ..fourbar import FourBar, positions

__all__ = [
    "FunctionGenerator",
    "StructuralError",
    "chebyshev_spacing",
    "freudenstein_coefficients",
    "function_generator",
    "lengths_from_freudenstein",
]


def chebyshev_spacing(x0: float, xf: float, n: int) -> np.ndarray:
    """Chebyshev spacing of ``n`` precision points on ``[x0, xf]``.

    ``x_j = (x0 + xf)/2 − (xf − x0)/2 · cos((2j − 1)π / (2n))``, ``j = 1 … n``
    (Norton ch. 5): the roots of the Chebyshev polynomial, which minimise
    the largest interpolation error of a smooth function.

    Examples
    --------
    >>> np.round(chebyshev_spacing(0.0, 1.0, 3), 4)
    array([0.067, 0.5  , 0.933])
    """
    x0 = finite_scalar("x0", x0)
    xf = finite_scalar("xf", xf)
    n = count("n", n, minimum=1, bytes_each=8)
    j = np.arange(1, n + 1)
    return 0.5 * (x0 + xf) - 0.5 * (xf - x0) * np.cos((2 * j - 1) * np.pi / (2 * n))


def freudenstein_coefficients(theta2: Any, theta4: Any) -> np.ndarray:
    """``K1, K2, K3`` of Freudenstein's equation through pairs ``(θ2, θ4)``.

    Three pairs give the exact solution of the 3×3 system; more pairs the
    least-squares solution (minimising the residual of the equation).

    Raises
    ------
    InputError
        Fewer than three pairs, mismatched lengths, or pairs that do not fix
        ``K`` (a singular system, e.g. repeated precision points).

    Examples
    --------
    The notes' HW 6 linkage (d, a, b, c) = (8, 4, 7, 6): K1 = 2, K2 = 4/3,
    K3 = (16 − 49 + 36 + 64)/48.

    >>> th2 = np.radians([0, 40, 80])
    >>> th4 = np.array([positions(8, 4, 7, 6, t)[1] for t in th2])
    >>> k = freudenstein_coefficients(th2, th4)
    >>> print(np.round(k, 6), round(67 / 48, 6))
    [2.       1.333333 1.395833] 1.395833
    """
    theta2 = np.ravel(finite_array("theta2", theta2))
    theta4 = np.ravel(finite_array("theta4", theta4))
    if theta2.size != theta4.size:
        raise InputError("theta4", f"needs one value per theta2 ({theta2.size}), got {theta4.size}")
    if theta2.size < 3:
        raise InputError("theta2", f"needs at least 3 precision points, got {theta2.size}")
    m = np.column_stack([np.cos(theta4), -np.cos(theta2), np.ones_like(theta2)])
    rhs = np.cos(theta2 - theta4)
    sv = np.linalg.svd(m, compute_uv=False)
    if sv[-1] <= 1e-10 * sv[0]:
        raise InputError(
            "theta2",
            "the precision points do not determine the linkage (repeated or degenerate points); "
            "give distinct input and output angles",
        )
    if theta2.size == 3:
        return np.linalg.solve(m, rhs)
    return np.linalg.lstsq(m, rhs, rcond=None)[0]


def lengths_from_freudenstein(k: Any, r1: float = 1.0) -> tuple[float, float, float, float]:
    """Signed lengths ``(d, a, b, c)`` from ``K1, K2, K3`` and the ground length ``d``.

    ``a = d/K1``, ``c = d/K2``, ``b² = a² + c² + d² − 2 a c K3``. ``a`` or
    ``c`` may come out negative (that link points the other way).

    Raises
    ------
    AssemblyError
        If ``b² <= 0``: no four-bar generates these precision points.
    InputError
        If ``K1`` or ``K2`` is zero (an infinitely long link).

    Examples
    --------
    >>> lengths_from_freudenstein([2.0, 4 / 3, 67 / 48], r1=8.0)
    (8.0, 4.0, 7.0, 6.0)
    """
    k = np.ravel(finite_array("k", k))
    if k.size != 3:
        raise InputError("k", f"must hold the three coefficients K1, K2, K3, got {k.size}")
    k1, k2, k3 = (float(v) for v in k)
    d = positive("r1", r1)  # the scale: a ground of zero or negative length is no linkage
    if abs(k1) < 1e-12 or abs(k2) < 1e-12:
        raise InputError("k", "K1 and K2 must be non-zero (a zero K means an infinite link)")
    a, c = d / k1, d / k2
    b2 = a * a + c * c + d * d - 2.0 * a * c * k3
    if not b2 > 1e-12 * (a * a + c * c + d * d):
        raise AssemblyError(
            f"no four-bar generates these precision points (b² = {b2:.6g} <= 0); "
            "change the input or output range, or the precision points"
        )
    b = float(np.sqrt(b2))
    return float(d), float(a), b, float(c)


@dataclass(frozen=True, eq=False)
class StructuralError:
    """Structural error of a function generator over its range.

    Attributes
    ----------
    x, y_desired, y_generated, error : ndarray
        The function's argument, the desired and the generated values, and
        ``error = y_generated − y_desired`` (NaN where ``ok`` is False).
    theta2, theta4 : ndarray
        Input and output angles (the synthesis' angles, radians).
    ok : ndarray of bool
        False where the linkage cannot be assembled at that input.
    reason : ndarray of str
        Why a sample is not ok.
    """

    x: np.ndarray
    y_desired: np.ndarray
    y_generated: np.ndarray
    error: np.ndarray
    theta2: np.ndarray
    theta4: np.ndarray
    ok: np.ndarray
    reason: np.ndarray

    @property
    def max_abs(self) -> float:
        """Largest ``|error|`` over the assembled samples (inf if none is)."""
        return float(np.max(np.abs(self.error[self.ok]))) if self.ok.any() else float("inf")

    def to_pandas(self):
        """A :class:`pandas.DataFrame`, one row per sample (pandas imported lazily)."""
        import pandas as pd

        from ..units import columns, units_of

        system = units_of(self)
        if system is not None:  # x and y are pure numbers; the angles say their unit
            spec = [(k, None, getattr(self, k)) for k in ("x", "y_desired", "y_generated")]
            spec += [("error", None, self.error), ("theta2", "angle", self.theta2)]
            spec += [("theta4", "angle", self.theta4)]
            spec += [("ok", None, self.ok), ("reason", None, self.reason)]
            return pd.DataFrame(columns(system, spec, degrees=True))
        return pd.DataFrame(
            {
                "x": self.x,
                "y_desired": self.y_desired,
                "y_generated": self.y_generated,
                "error": self.error,
                "theta2": self.theta2,
                "theta4": self.theta4,
                "ok": self.ok,
                "reason": self.reason,
            }
        )

    def plot(self, ax=None):
        """Plot the error against ``x`` (matplotlib imported lazily); returns the axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots()
        ax.plot(self.x, self.error)
        ax.axhline(0.0, color="0.5", lw=0.5)
        ax.set_xlabel("x")
        ax.set_ylabel("structural error  y_generated − f(x)")
        return ax


@dataclass(frozen=True, eq=False)
class FunctionGenerator:
    """A four-bar synthesised to generate ``y = f(x)`` (Freudenstein's method).

    Attributes
    ----------
    fourbar : FourBar
        The linkage (positive lengths).
    k : ndarray
        ``K1, K2, K3``.
    r1, r2, r3, r4 : float
        Ground, input, coupler and output lengths.
    branch : int
        Sign of φ12 of the assembly that generates the function.
    input_offset, output_offset : float
        0 or π: the linkage's link angles are ``θ2 + input_offset`` and
        ``θ4 + output_offset`` (π where Freudenstein gave a negative length).
    x_range, theta2_range, theta4_range : tuple of float
        The linear maps ``x → θ2`` and ``y → θ4``: ``(start, end)`` each.
    y_range : tuple of float
        ``(f(x0), f(xf))``.
    x_precision : ndarray
        The precision points.
    defects : tuple of str
        Why the linkage cannot generate the function over the whole range.
    """

    fourbar: FourBar
    k: np.ndarray
    r1: float
    r2: float
    r3: float
    r4: float
    branch: int
    input_offset: float
    output_offset: float
    func: Callable[[np.ndarray], np.ndarray]
    x_range: tuple[float, float]
    y_range: tuple[float, float]
    theta2_range: tuple[float, float]
    theta4_range: tuple[float, float]
    x_precision: np.ndarray
    defects: tuple[str, ...]

    @property
    def ok(self) -> bool:
        """True when the linkage is assembled on one branch over the whole range."""
        return not self.defects

    def theta2_of(self, x: Any) -> np.ndarray:
        """Input angle for argument ``x`` (the linear map)."""
        (x0, xf), (t0, tf) = self.x_range, self.theta2_range
        return t0 + (finite_array("x", x) - x0) / (xf - x0) * (tf - t0)

    def theta4_of(self, y: Any) -> np.ndarray:
        """Output angle for value ``y`` (the linear map)."""
        (y0, yf), (t0, tf) = self.y_range, self.theta4_range
        return t0 + (finite_array("y", y) - y0) / (yf - y0) * (tf - t0)

    def structural_error(self, n: int = 201, x: Any = None) -> StructuralError:
        """Structural error at ``n`` evenly spaced arguments (or at ``x``).

        Examples
        --------
        >>> g = function_generator(np.log10, (1.0, 2.0), np.radians((45, 105)),
        ...                        np.radians((135, 225)))
        >>> se = g.structural_error()
        >>> bool(np.allclose(se.error[np.isin(se.x, g.x_precision)], 0.0))
        True
        >>> bool(se.max_abs < 1e-3)    # in y = log10(x), over the whole range
        True
        """
        if x is None:
            x = np.linspace(*self.x_range, count("n", n, minimum=2, bytes_each=96))
        x = np.ravel(finite_array("x", x))
        if x.size > 1:  # include the precision points (unless a sample already is one)
            gap = np.min(np.abs(self.x_precision[:, None] - x[None, :]), axis=1)
            extra = self.x_precision[gap > 1e-9 * abs(self.x_range[1] - self.x_range[0])]
            x = np.sort(np.concatenate([x, extra]))
        y_desired = _evaluate(self.func, x)
        theta2 = self.theta2_of(x)
        theta4_want = self.theta4_of(y_desired)
        _, th4, ok = positions(*self.fourbar.lengths, theta2 + self.input_offset, self.branch)
        theta4 = theta4_want + wrap_pi(th4 - self.output_offset - theta4_want)
        (y0, yf), (t0, tf) = self.y_range, self.theta4_range
        y_gen = y0 + (theta4 - t0) / (tf - t0) * (yf - y0)
        defined = np.isfinite(y_desired)
        reason = np.where(ok, "", "cannot be assembled at this input (outside link 2's range)")
        reason = np.where(defined, reason, "the function is not finite here")
        ok = ok & defined
        error = np.where(ok, y_gen - y_desired, np.nan)
        from ..units import units_of, with_units

        result = StructuralError(
            x, y_desired, np.where(ok, y_gen, np.nan), error, theta2, theta4, ok, reason
        )
        return with_units(result, units_of(self))  # a machine file's task: "theta2 [deg]"


def _evaluate(func: Callable[[np.ndarray], np.ndarray], x: np.ndarray) -> np.ndarray:
    """``func(x)`` as floats of x's shape, or :class:`InputError` naming ``func``.

    A function that ignores its argument (a constant) is broadcast to ``x``.
    """
    try:
        with np.errstate(all="ignore"):  # f undefined somewhere (log10(0)): NaN, flagged there
            y = np.asarray(func(x), dtype=float)
        return np.broadcast_to(y, x.shape).astype(float)
    except (TypeError, ValueError) as exc:
        raise InputError(
            "func", f"must map an array of x to numbers of the same shape ({exc})"
        ) from None


def function_generator(
    func: Callable[[np.ndarray], np.ndarray],
    x_range: tuple[float, float],
    theta2_range: tuple[float, float],
    theta4_range: tuple[float, float],
    *,
    n: int = 3,
    spacing: str = "chebyshev",
    x_precision: Any = None,
    r1: float = 1.0,
) -> FunctionGenerator:
    """Synthesise a four-bar function generator by Freudenstein's equation.

    Parameters
    ----------
    func : callable
        ``y = func(x)``, vectorised over numpy arrays.
    x_range : (x0, xf)
        Range of the argument.
    theta2_range, theta4_range : (start, end)
        Input and output angles (radians) that ``x0, xf`` and ``f(x0), f(xf)``
        map to; the maps are linear.
    n : int
        Number of precision points: 3 is exact, more is least squares.
    spacing : {"chebyshev", "uniform"}
        Chebyshev spacing, or uniform including both ends.
    x_precision : array_like, optional
        Explicit precision points (overrides ``n`` and ``spacing``).
    r1 : float
        Ground length (the scale of the linkage).

    Returns
    -------
    FunctionGenerator

    Raises
    ------
    InputError
        A degenerate range, or precision points outside it.
    AssemblyError
        When no four-bar generates the precision points.

    Examples
    --------
    ``y = log10(x)`` on [1, 2], θ2 from 45° to 105°, θ4 from 135° to 225°:

    >>> g = function_generator(np.log10, (1.0, 2.0), np.radians((45, 105)),
    ...                        np.radians((135, 225)))
    >>> g.ok, g.fourbar.is_grashof
    (True, False)
    >>> err = g.structural_error(x=g.x_precision).error     # exact at the precision points
    >>> bool(np.all(np.abs(err) < 1e-12))
    True
    """
    x0, xf = (finite_scalar("x_range", v) for v in items("x_range", x_range, 2, "values"))
    if x0 == xf:
        raise InputError("x_range", "start and end must differ")
    t20, t2f = (
        finite_scalar("theta2_range", v, "radian")
        for v in items("theta2_range", theta2_range, 2, "angles")
    )
    t40, t4f = (
        finite_scalar("theta4_range", v, "radian")
        for v in items("theta4_range", theta4_range, 2, "angles")
    )
    if t20 == t2f or t40 == t4f:
        raise InputError("theta2_range", "the input and output ranges must be non-zero")
    from ..units import warn_if_degrees

    warn_if_degrees("theta2_range", (t20, t2f))  # (45, 105) meant in degrees: say so
    warn_if_degrees("theta4_range", (t40, t4f))
    y0, yf = (float(v) for v in _evaluate(func, np.array([x0, xf])))
    if not (np.isfinite(y0) and np.isfinite(yf)) or y0 == yf:
        raise InputError(
            "func", f"f(x0) and f(xf) must be finite and differ to map onto θ4, got {y0}, {yf}"
        )
    if x_precision is None:
        n = count("n", n, minimum=3, bytes_each=1024, what="precision points")
        spacing = choice("spacing", spacing, ("chebyshev", "uniform"))
        xp = chebyshev_spacing(x0, xf, n) if spacing == "chebyshev" else np.linspace(x0, xf, n)
    else:
        xp = np.sort(np.ravel(finite_array("x_precision", x_precision)))
        lo, hi = min(x0, xf), max(x0, xf)
        if np.any((xp < lo) | (xp > hi)):
            raise InputError("x_precision", f"every precision point must lie in [{lo}, {hi}]")
    yp = _evaluate(func, xp)
    if not np.all(np.isfinite(yp)):
        raise InputError("func", "must be finite at every precision point")
    th2 = t20 + (xp - x0) / (xf - x0) * (t2f - t20)
    th4 = t40 + (yp - y0) / (yf - y0) * (t4f - t40)
    k = freudenstein_coefficients(th2, th4)
    d, a, b, c = lengths_from_freudenstein(k, r1)
    in_off = np.pi if a < 0 else 0.0
    out_off = np.pi if c < 0 else 0.0
    fb = FourBar(d, abs(a), b, abs(c))
    # the branch that passes through the precision points best
    errs = []
    for br in (1, -1):
        _, t4, ok = positions(*fb.lengths, th2 + in_off, br)
        e = np.abs(wrap_pi(t4 - out_off - th4))
        errs.append(np.where(ok, e, np.inf))
    best = int(np.argmin([np.max(e) for e in errs]))
    branch = (1, -1)[best]
    defects: list[str] = []
    if len(xp) == 3 and np.max(errs[best]) > 1e-6:
        split = [int(i) + 1 for i in np.flatnonzero(errs[best] > 1e-6)]
        defects.append(
            f"branch defect: precision points {split} lie on the other branch (sign of phi12); "
            "the linkage cannot pass them all without a toggle"
        )
    result = FunctionGenerator(
        fourbar=fb,
        k=k,
        r1=d,
        r2=abs(a),
        r3=b,
        r4=abs(c),
        branch=branch,
        input_offset=in_off,
        output_offset=out_off,
        func=func,
        x_range=(x0, xf),
        y_range=(y0, yf),
        theta2_range=(t20, t2f),
        theta4_range=(t40, t4f),
        x_precision=xp,
        defects=tuple(defects),
    )
    se = result.structural_error(n=401)
    if not se.ok.all():
        defects.append(
            f"cannot be assembled for x in {_runs(se.x, ~se.ok)}; "
            "the function range is beyond this four-bar's motion"
        )
        result = replace(result, defects=tuple(defects))
    return result


def _runs(x: np.ndarray, bad: np.ndarray) -> str:
    """The stretches of ``x`` where ``bad`` holds, as text: ``[0, 0.1], [0.9, 1]``."""
    edges = np.flatnonzero(np.diff(np.concatenate([[0], bad.astype(np.int8), [0]])))
    spans = [f"[{x[i]:.6g}, {x[j - 1]:.6g}]" for i, j in zip(edges[::2], edges[1::2], strict=True)]
    return ", ".join(spans)
