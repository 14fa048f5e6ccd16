"""The equation of motion's coefficients over the input coordinate: tabulated or exact.

For one degree of freedom ``q`` (the driver's angle or travel) the equation of
motion is (Lagrange, or virtual work with d'Alembert's inertia loads)::

    I(q) q̈ + ½ I'(q) q̇² = T_drive + Q(q) − C(q) q̇ + Σ Q_load(q, q̇, t)

with ``I`` the generalised inertia, ``Q`` the generalised force of the model's
own position-dependent loads (gravity, springs, constant loads) and ``C`` its
viscous damping. They come from the model's force analysis itself — the one
assembler that also gives the pin forces — as the driver effort it needs for a
motion ``(q, q̇, q̈)``, which is ``T(q, q̇, q̈) = I q̈ + ½ I' q̇² + C q̇ − Q``::

    Q = −T(q, 0, 0)            I = T(q, 0, 1) + Q
    ½ I' = ½ [T(q, 1, 0) + T(q, −1, 0)] + Q       C = ½ [T(q, 1, 0) − T(q, −1, 0)]

A fifth sample ``T(q, 2, 0)`` checks the quadratic dependence on ``q̇`` (a law
that is not quadratic is refused rather than simulated wrong). The loads of
:mod:`~machdyn.simulate.loads` need their coordinate ``x(q)`` (a link angle or a
point) and its rate ``x'(q)`` (the kinematic coefficient).

:class:`Table` samples all of these once on a uniform grid — one period of a
crank, or the reachable range of a rocker or slider — and interpolates them by
cubic splines (periodic for a crank), so the integrator never re-solves the
linkage. Its accuracy is measured, not assumed: every function is also solved
exactly at every cell's midpoint and the grid is doubled until the largest
interpolation error is below ``tol`` relative to the function's size. A
range that ends at a toggle (where ``I`` grows without bound) keeps only the
cells that pass, and the simulation stops at their end, naming the toggle.
:class:`Exact` evaluates the same functions by solving the model at every call.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import ModelError

__all__ = ["Exact", "Span", "Table"]

#: Velocity/acceleration pairs sampled per node (see the module docstring).
_PAIRS = ((0.0, 0.0), (0.0, 1.0), (1.0, 0.0), (-1.0, 0.0), (2.0, 0.0))


@dataclass(frozen=True)
class Span:
    """Where the input coordinate may go: a period, or limits with their reasons."""

    period: float | None
    lo: float = -math.inf
    hi: float = math.inf
    lo_reason: str = ""
    hi_reason: str = ""


def coefficient_samples(plant: Any, loads: Any, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rows ``I, H = ½I', C, Q`` and each load's ``x``, ``x'`` (real parts) at ``q``.

    Returns the (F, n) array of values and the (n,) mask of samples the model
    solved. A torque load's angle row is unwrapped along ``q`` (a sorted grid).
    Raises :class:`ModelError` if the driver effort is not quadratic in the
    driver speed (then the table's equation of motion would be wrong).
    """
    efforts, ok = plant.efforts_at(q, _PAIRS)
    t00, t01, t10, tm10, t20 = efforts
    Q = -t00
    inertia = t01 - t00
    half_di = 0.5 * (t10 + tm10) - t00
    damping = 0.5 * (t10 - tm10)
    rows = [inertia, half_di, damping, Q]
    predicted = 4.0 * half_di + 2.0 * damping + t00
    scale = float(np.max(np.abs(efforts[:, ok]), initial=0.0))
    mismatch = np.abs(predicted - t20)[ok]
    if mismatch.size and float(mismatch.max()) > 1e-7 * max(scale, 1e-300):
        raise ModelError(
            "the model's driver effort is not quadratic in the driver speed (a nonlinear "
            "damper or Coulomb friction): the equation of motion I q'' + ½ I' q'^2 + C q' = Q "
            "does not hold; use viscous friction and linear dampers"
        )
    for load in loads:
        x, rate, ok_load = plant.geometry(load, q)
        ok = ok & ok_load
        if load.is_torque and np.size(x) > 1:
            x = np.where(ok_load, x, 0.0)
            x = np.unwrap(x)
        for part in (x, rate):
            if np.iscomplexobj(part):
                rows += [part.real, part.imag]
            else:
                rows.append(np.asarray(part, dtype=float))
    values = np.array([np.broadcast_to(r, q.shape) for r in rows], dtype=float)
    ok = ok & np.isfinite(values).all(axis=0)
    return values, ok


def angle_rows(loads: Any, plant: Any) -> list[int]:
    """Rows of the coefficient vector that are link angles (compared modulo 2π)."""
    return [
        row
        for (row, _), load in zip(load_layout(loads, plant), loads, strict=True)
        if load.is_torque
    ]


def load_layout(loads: Any, plant: Any) -> list[tuple[int, bool]]:
    """Per load: the index of its first row in the coefficient vector, and complex or not."""
    layout, row = [], 4
    for load in loads:
        complex_ = plant.is_complex(load)
        layout.append((row, complex_))
        row += 4 if complex_ else 2
    return layout


class Table:
    """Cubic-spline table of the coefficients over a period or a range (see module doc).

    Parameters
    ----------
    plant : model adapter
        Gives ``efforts_at`` and ``geometry`` (see :mod:`machdyn.simulate._plant`).
    loads : sequence of Load
    q0 : float
        The initial coordinate (the table of a crank starts there).
    span : Span
        A period, or the limits of the range.
    tol : float
        Largest interpolation error allowed, relative to each function's size.
    n0, n_max : int
        First and largest number of cells (default 2¹⁵ over a period, 2¹³ over a range).
    """

    def __init__(
        self,
        plant: Any,
        loads: Any,
        q0: float,
        span: Span,
        tol: float = 1e-9,
        n0: int = 256,
        n_max: int | None = None,
    ) -> None:
        self.period = span.period
        self.span = span
        self.angles = angle_rows(loads, plant)
        if n_max is None:
            n_max = 1 << 15 if self.period is not None else 1 << 13
        nodes, spline, trend, cell_ok = self._refine(plant, loads, q0, tol, n0, n_max)
        if self.period is None:
            lo_cell, hi_cell = _run_around(cell_ok, _cell_of(nodes, float(self.s_of(q0))))
            if lo_cell > hi_cell:
                raise ModelError(
                    f"the coefficients of the equation of motion cannot be tabulated near "
                    f"q = {q0:.6g} (next to a toggle?): simulate with table=False"
                )
            self.lo, self.hi = (
                float(self.q_of(nodes[lo_cell])),
                float(self.q_of(nodes[hi_cell + 1])),
            )
        elif not cell_ok.all() and self.error > 100.0 * tol:
            raise ModelError(
                f"the coefficients vary too fast to tabulate with {self.cells} cells per period "
                f"(interpolation error {self.error:.2g}): the crank passes close to a toggle; "
                "simulate with table=False"
            )
        else:
            self.lo, self.hi = -math.inf, math.inf
        self.start = float(nodes[0])
        self.h = float(nodes[1] - nodes[0])
        self._inv_h = 1.0 / self.h
        if self.period is None:
            self._tanh_edge = math.tanh(self.edge)
        self.trend = trend
        self._trend = [(k, float(v)) for k, v in enumerate(trend) if v]
        self._coef = np.array(spline.c)  # (4, cells, F): c0 d³ + c1 d² + c2 d + c3
        self.force_scale = float(np.max(np.abs(self._coef[3, :, 3])))  # |Q| at the nodes
        self.functions = self._coef.shape[2]
        self._k = range(0, 4 * self.functions, 4)
        self._store()
        if self.angles:  # the model's own angle at q0, not another turn of it
            exact, _ = coefficient_samples(plant, loads, np.array([q0]))
            here = self(q0)
            for r in self.angles:
                self._coef[3, :, r] += (
                    2.0 * math.pi * round((exact[r, 0] - here[r]) / (2.0 * math.pi))
                )
            self._store()

    def _refine(self, plant, loads, q0, tol, n0, n_max):
        """Double the grid until every cell passes its midpoint check (a range: but its ends)."""
        if self.period is not None:
            nodes = np.linspace(q0, q0 + self.period, n0 + 1)
        else:
            if not (math.isfinite(self.span.lo) and math.isfinite(self.span.hi)):
                raise ModelError("a table over a range needs finite limits")
            self.mid = 0.5 * (self.span.hi + self.span.lo)
            self.half = 0.5 * (self.span.hi - self.span.lo)
            # q = mid + half tanh(s): cells shrink geometrically toward the limits (toggles),
            # where the coefficients grow like powers of the distance; the grid stops a
            # millionth of the range short of them
            self.edge = math.atanh(1.0 - 2e-6)
            nodes = np.linspace(-self.edge, self.edge, n0 + 1)
        n = n0
        values, ok = coefficient_samples(plant, loads, self.q_of(nodes))
        s0 = self.s_of(q0)
        while True:
            mids = 0.5 * (nodes[1:] + nodes[:-1])
            mid_values, mid_ok = coefficient_samples(plant, loads, self.q_of(mids))
            spline, trend = self._fit(nodes, values, ok)
            cell_ok, self.error = self._check(
                spline, trend, nodes[0], mids, mid_values, mid_ok, values, tol
            )
            done = bool(cell_ok.all()) or n >= n_max
            if self.period is None and not done:  # toggles at the ends: come within 1e-4 of them
                lo_cell, hi_cell = _run_around(cell_ok, _cell_of(nodes, s0))
                if lo_cell <= hi_cell:
                    near = 1e-4 * (self.span.hi - self.span.lo)
                    done = (
                        self.q_of(nodes[lo_cell]) - self.span.lo <= near
                        and self.span.hi - self.q_of(nodes[hi_cell + 1]) <= near
                    )
            if done:
                self.cells = n
                return nodes, spline, trend, cell_ok
            nodes, values, ok = _interleave(nodes, mids, values, mid_values, ok, mid_ok)
            n *= 2

    def q_of(self, s: Any) -> Any:
        """The coordinate at the table's abscissa ``s`` (``q = mid + half sin s`` over a range)."""
        if self.period is not None:
            return s
        return self.mid + self.half * np.tanh(s)

    def s_of(self, q: Any) -> Any:
        """The table's abscissa of ``q`` (the inverse of :meth:`q_of`; clipped to the range)."""
        if self.period is not None:
            return q
        x = np.clip((np.asarray(q, dtype=float) - self.mid) / self.half, -1.0, 1.0)
        return np.clip(np.arctanh(x), -self.edge, self.edge)

    def _store(self) -> None:
        """Per cell, the coefficients as one flat tuple (the fast scalar path reads these)."""
        flat = self._coef.transpose(1, 2, 0).reshape(self.cells, -1)
        self.rows = [tuple(row) for row in flat.tolist()]

    def _fit(self, nodes: np.ndarray, values: np.ndarray, ok: np.ndarray) -> tuple[Any, np.ndarray]:
        from scipy.interpolate import CubicSpline

        if self.period is None:
            filled = values.copy()
            if not ok.all():  # cells next to unsolved nodes fail the check below
                good = np.flatnonzero(ok)
                if good.size < 2:
                    raise ModelError("the model cannot be solved over its range")
                for row in filled:
                    row[~ok] = np.interp(nodes[~ok], nodes[good], row[good])
            return CubicSpline(nodes, filled.T, bc_type="not-a-knot"), np.zeros(values.shape[0])
        if not ok.all():
            bad = float(nodes[np.flatnonzero(~ok)[0]])
            raise ModelError(
                f"the model cannot be solved at q = {bad:.6g} within the period (a toggle on "
                "the crank's path?)"
            )
        trend = (values[:, -1] - values[:, 0]) / self.period  # a link angle gains 2π per turn
        detrended = values - trend[:, None] * (nodes - nodes[0])
        detrended[:, -1] = detrended[:, 0]
        return CubicSpline(nodes, detrended.T, bc_type="periodic"), trend

    def _check(self, spline, trend, origin, mids, mid_values, mid_ok, values, tol):
        """Per cell, whether every interpolated function matches its exact midpoint value."""
        predicted = spline(mids).T + trend[:, None] * (mids - origin)
        difference = predicted - mid_values
        for row in self.angles:  # unwrapped on different grids: compare modulo 2π
            difference[row] = np.remainder(difference[row] + math.pi, 2.0 * math.pi) - math.pi
        scale = np.percentile(np.abs(values), 90, axis=1)[:, None]
        local = np.maximum(np.abs(mid_values), scale)
        floor = 1e-12 * float(np.max(scale)) + 1e-300
        error = np.abs(difference) / np.maximum(local, floor)
        # a function that is zero but for round-off (½I' of a lone pendulum from a Linkage:
        # ~4e-16 where Q is ~6) passes when its difference stays at that noise level
        noise = (scale[:, 0] <= floor) & (np.abs(difference) <= floor).all(axis=1)
        error[noise] = 0.0
        cell_ok = mid_ok & (error <= tol).all(axis=0)
        worst = float(np.max(error[:, mid_ok])) if mid_ok.any() else math.inf
        return cell_ok, worst

    def __call__(self, q: float) -> list[float]:
        """The coefficient vector at ``q`` (pure Python: called once per right-hand side)."""
        if self.period is None:
            x = (q - self.mid) / self.half
            s = (
                math.atanh(x)
                if -self._tanh_edge < x < self._tanh_edge
                else math.copysign(self.edge, x)
            )
            i = math.floor((s - self.start) * self._inv_h)
            i = 0 if i < 0 else self.cells - 1 if i >= self.cells else i
            d = s - self.start - i * self.h
        else:
            i = math.floor((q - self.start) * self._inv_h)
            d = q - self.start - i * self.h
            i %= self.cells
        r = self.rows[i]
        if self.functions == 4:  # no loads: the four coefficients, unrolled
            out = [
                ((r[0] * d + r[1]) * d + r[2]) * d + r[3],
                ((r[4] * d + r[5]) * d + r[6]) * d + r[7],
                ((r[8] * d + r[9]) * d + r[10]) * d + r[11],
                ((r[12] * d + r[13]) * d + r[14]) * d + r[15],
            ]
        else:
            out = [((r[k] * d + r[k + 1]) * d + r[k + 2]) * d + r[k + 3] for k in self._k]
        if self._trend:
            shift = q - self.start
            for k, slope in self._trend:
                out[k] += slope * shift
        return out

    def many(self, q: np.ndarray) -> np.ndarray:
        """The coefficient vectors at an array of ``q``, shape (F, *q.shape) (vectorised)."""
        q = np.asarray(self.s_of(q), dtype=float)
        index = np.floor((q - self.start) * self._inv_h)
        if self.period is not None:
            cell = np.mod(index, self.cells).astype(np.intp)
        else:
            index = np.clip(index, 0, self.cells - 1)
            cell = index.astype(np.intp)
        d = (q - self.start - index * self.h)[None, ..., None]
        c = self._coef[:, cell]  # (4, *q.shape, F)
        out = np.moveaxis(((c[0:1] * d + c[1:2]) * d + c[2:3]) * d + c[3:4], -1, 0)[:, 0]
        for k, slope in self._trend:
            out[k] += slope * (q - self.start)
        return out

    def describe(self) -> str:
        """One line: cells, spacing and the measured interpolation error."""
        if self.period is not None:
            return (
                f"table of {self.cells} cells over the period, interpolation error {self.error:.1e}"
            )
        return (
            f"table of {self.cells} cells over the range (denser toward its ends), "
            f"interpolation error {self.error:.1e}"
        )


class Exact:
    """The same coefficient vector, solving the model at every call (slow; exact)."""

    def __init__(self, plant: Any, loads: Any, span: Span) -> None:
        self.plant, self.loads = plant, loads
        self.angles = angle_rows(loads, plant)
        self.period = span.period
        self.lo, self.hi = span.lo, span.hi
        self.error = 0.0
        self.cells = 0
        self._last: list[float] | None = None
        if self.period is not None:
            q = np.linspace(0.0, self.period, 65)
        else:
            q = np.linspace(self.lo, self.hi, 67)[1:-1]
        values, ok = coefficient_samples(plant, loads, q)
        self.force_scale = float(np.max(np.abs(values[3, ok]), initial=0.0))  # |Q| over the span

    def __call__(self, q: float) -> list[float]:
        """The coefficient vector at ``q``, solving the model there."""
        values, ok = coefficient_samples(self.plant, self.loads, np.array([q]))
        if not ok[0]:
            raise _Unsolved(q)
        out = values[:, 0].tolist()
        if self._last is not None:  # link angles continue from the last call (not wrapped)
            for r in self.angles:
                out[r] += 2.0 * math.pi * round((self._last[r] - out[r]) / (2.0 * math.pi))
        self._last = out
        return out

    def many(self, q: np.ndarray) -> np.ndarray:
        """The coefficient vectors along a trajectory ``q`` (F, n), in one batched solve."""
        q = np.asarray(q, dtype=float)
        values, ok = coefficient_samples(self.plant, self.loads, q.ravel())
        if not ok.all():
            raise _Unsolved(float(q.ravel()[np.flatnonzero(~ok)[0]]))
        return values.reshape(-1, *q.shape)

    def describe(self) -> str:
        """``"exact (no table)"``."""
        return "exact (the model is solved at every step)"


class _Unsolved(ArithmeticError):
    """The model cannot be solved at ``q`` (raised inside the integration)."""

    def __init__(self, q: float) -> None:
        super().__init__(f"the model cannot be solved at q = {q:.9g}")
        self.q = q


def _open_grid(lo: float, hi: float, n: int) -> np.ndarray:
    """``n + 1`` nodes spaced ``(hi − lo)/(n + 1)``, half a step inside each limit."""
    h = (hi - lo) / (n + 1)
    return lo + h * (0.5 + np.arange(n + 1))


def _interleave(nodes, mids, values, mid_values, ok, mid_ok):
    """The grid with its midpoints added (their samples are reused)."""
    n = nodes.size + mids.size
    new_nodes = np.empty(n)
    new_nodes[0::2], new_nodes[1::2] = nodes, mids
    new_values = np.empty((values.shape[0], n))
    new_values[:, 0::2], new_values[:, 1::2] = values, mid_values
    new_ok = np.empty(n, dtype=bool)
    new_ok[0::2], new_ok[1::2] = ok, mid_ok
    return new_nodes, new_values, new_ok


def _cell_of(nodes: np.ndarray, q: float) -> int:
    return int(np.clip(np.searchsorted(nodes, q, side="right") - 1, 0, nodes.size - 2))


def _run_around(cell_ok: np.ndarray, cell: int) -> tuple[int, int]:
    """First and last cell of the run of passing cells that contains ``cell`` (lo > hi: none)."""
    if not cell_ok[cell]:
        return 1, 0
    bad = np.flatnonzero(~cell_ok)
    below = bad[bad < cell]
    above = bad[bad > cell]
    lo = int(below[-1]) + 1 if below.size else 0
    hi = int(above[0]) - 1 if above.size else cell_ok.size - 1
    return lo, hi
