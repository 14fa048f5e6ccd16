"""Dual numbers over arrays: values with their first derivatives along many directions.

``Dual(v, d)`` holds an array of values ``v`` (real or complex, any shape) and
their derivatives ``d`` with one more, last axis: one column per direction
(e.g. per dimension of a linkage). Arithmetic follows the chain rule, so a
formula written once gives its value and its exact first derivatives
(forward-mode differentiation). It serves the sensitivity analysis: the loop
equations are differentiated implicitly (each derivative order is a linear
system with the position Jacobian), and these numbers carry the chain rule
through the systems' coefficients.

Examples
--------
>>> import numpy as np
>>> x = Dual.seed(np.array([1.0, 2.0]), 0, 2)      # x, d/dx
>>> y = Dual.seed(np.array([3.0, 4.0]), 1, 2)      # y, d/dy
>>> f = x * x * y + 1.0
>>> f.v.tolist(), f.d.tolist()                      # 2xy, x²
([4.0, 17.0], [[6.0, 1.0], [16.0, 4.0]])
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["Dual", "Jet", "cross", "expj", "lift", "solve_pair"]


class Dual:
    """Values ``v`` and derivatives ``d`` (``d.shape == v.shape + (m,)``)."""

    __slots__ = ("d", "v")
    __array_ufunc__ = None  # numpy arrays defer to Dual's operators (array * Dual)

    def __init__(self, v: Any, d: Any) -> None:
        self.v = v if type(v) is np.ndarray else np.asarray(v)
        self.d = d if type(d) is np.ndarray else np.asarray(d)

    @classmethod
    def seed(cls, v: Any, index: int, m: int) -> Dual:
        """A variable: derivative 1 along direction ``index`` of ``m``."""
        v = np.asarray(v, dtype=float)
        d = np.zeros((*v.shape, m))
        d[..., index] = 1.0
        return cls(v, d)

    @classmethod
    def constant(cls, v: Any, m: int) -> Dual:
        """A value that does not depend on the directions."""
        v = np.asarray(v)
        return cls(v, np.zeros((*v.shape, m), dtype=v.dtype if v.dtype.kind == "c" else float))

    def __add__(self, other: Any) -> Dual:
        if isinstance(other, Dual):
            return Dual(self.v + other.v, self.d + other.d)
        return Dual(self.v + other, self.d)

    __radd__ = __add__

    def __sub__(self, other: Any) -> Dual:
        if isinstance(other, Dual):
            return Dual(self.v - other.v, self.d - other.d)
        return Dual(self.v - other, self.d)

    def __rsub__(self, other: Any) -> Dual:
        return Dual(other - self.v, -self.d)

    def __neg__(self) -> Dual:
        return Dual(-self.v, -self.d)

    def __mul__(self, other: Any) -> Dual:
        if isinstance(other, Dual):
            d = self.d * other.v[..., None]
            add = other.d * self.v[..., None]
            if d.shape == add.shape and (d.dtype == add.dtype or d.dtype.kind == "c"):
                d += add  # in place: one temporary fewer
            else:
                d = d + add
            return Dual(self.v * other.v, d)
        if np.ndim(other) == 0:
            return Dual(self.v * other, self.d * other)
        other = np.asarray(other)
        return Dual(self.v * other, self.d * other[..., None])

    __rmul__ = __mul__

    def __truediv__(self, other: Any) -> Dual:
        if isinstance(other, Dual):
            q = self.v / other.v
            return Dual(q, (self.d - other.d * q[..., None]) / other.v[..., None])
        other = np.asarray(other)
        return Dual(self.v / other, self.d / other[..., None])

    def __rtruediv__(self, other: Any) -> Dual:
        q = other / self.v
        return Dual(q, -self.d * (q / self.v)[..., None])

    def __pow__(self, k: int) -> Dual:
        return Dual(self.v**k, k * self.v[..., None] ** (k - 1) * self.d)

    @property
    def real(self) -> Dual:
        """Real part."""
        return Dual(self.v.real, self.d.real)

    @property
    def imag(self) -> Dual:
        """Imaginary part."""
        return Dual(self.v.imag, self.d.imag)

    def conj(self) -> Dual:
        """Complex conjugate."""
        return Dual(np.conj(self.v), np.conj(self.d))

    def __getitem__(self, index: Any) -> Dual:
        return Dual(self.v[index], self.d[index])


def lift(x: Any, m: int) -> Dual:
    """``x`` as a :class:`Dual` (a constant unless it already is one)."""
    return x if isinstance(x, Dual) else Dual.constant(x, m)


def expj(theta: Dual) -> Dual:
    """``e^{jθ}`` of a real dual angle."""
    e = np.exp(1j * theta.v)
    return Dual(e, 1j * e[..., None] * theta.d)


def cross(a: Dual, b: Dual) -> Dual:
    """The planar cross product ``a × b = Im(conj(a) b)`` of two complex duals."""
    return (a.conj() * b).imag


def solve_pair(c1: Dual, c2: Dual, k: Dual) -> tuple[Dual, Dual]:
    """Real ``x1, x2`` of ``c1 x1 + c2 x2 = k`` (complex coefficients), by Cramer's rule.

    Crossing with ``c2`` and ``c1`` eliminates one unknown each:
    ``x1 = (c2 × k)/(c2 × c1)``, ``x2 = (c1 × k)/(c1 × c2)``.

    Examples
    --------
    >>> one = Dual.constant(np.array(1.0 + 0j), 1)
    >>> x1, x2 = solve_pair(one, one * 1j, Dual.constant(np.array(3.0 + 4.0j), 1))
    >>> float(x1.v), float(x2.v)
    (3.0, 4.0)
    """
    det = cross(c2, c1)
    return cross(c2, k) / det, -(cross(c1, k) / det)


class Jet:
    """A quantity and its first time derivatives ``(x, ẋ[, ẍ])``, each a :class:`Dual`.

    Products follow Leibniz (``(ab)″ = a″b + 2a′b′ + ab″``), so a position
    constraint written once with jets gives its velocity and acceleration
    constraints too. A jet holds 1, 2 or 3 coefficients (the orders needed).

    Examples
    --------
    >>> t = Dual.constant(np.array(0.5), 1)
    >>> theta = Jet(t, t * 0.0 + 2.0, t * 0.0)          # θ = 0.5, θ̇ = 2
    >>> e = theta.expj()
    >>> bool(np.isclose(e.c[1].v, 2j * np.exp(0.5j)))     # d/dt e^{jθ} = jθ̇ e^{jθ}
    True
    """

    __slots__ = ("c",)

    def __init__(self, *c: Any) -> None:
        self.c = c

    def __add__(self, other: Any) -> Jet:
        if isinstance(other, Jet):
            return Jet(*(a + b for a, b in zip(self.c, other.c, strict=True)))
        return Jet(self.c[0] + other, *self.c[1:])

    __radd__ = __add__

    def __sub__(self, other: Any) -> Jet:
        if isinstance(other, Jet):
            return Jet(*(a - b for a, b in zip(self.c, other.c, strict=True)))
        return Jet(self.c[0] - other, *self.c[1:])

    def __rsub__(self, other: Any) -> Jet:
        return (-self) + other

    def __neg__(self) -> Jet:
        return Jet(*(-a for a in self.c))

    def __mul__(self, other: Any) -> Jet:
        if not isinstance(other, Jet):  # a constant in time
            return Jet(*(a * other for a in self.c))
        a, b = self.c, other.c
        out = [a[0] * b[0]]
        if len(a) > 1:
            out.append(a[0] * b[1] + a[1] * b[0])
        if len(a) > 2:
            out.append(a[0] * b[2] + (a[1] * b[1]) * 2.0 + a[2] * b[0])
        return Jet(*out)

    __rmul__ = __mul__

    def expj(self) -> Jet:
        """``e^{jθ}`` of a real angle: ``(E, jθ̇ E, (jθ̈ − θ̇²) E)``."""
        e = expj(self.c[0])
        out = [e]
        if len(self.c) > 1:
            out.append(1j * self.c[1] * e)
        if len(self.c) > 2:
            t1 = self.c[1]
            out.append((1j * self.c[2] - t1 * t1) * e)
        return Jet(*out)

    def conj(self) -> Jet:
        """Complex conjugate."""
        return Jet(*(a.conj() for a in self.c))

    @property
    def real(self) -> Jet:
        """Real part."""
        return Jet(*(a.real for a in self.c))

    @property
    def imag(self) -> Jet:
        """Imaginary part."""
        return Jet(*(a.imag for a in self.c))
