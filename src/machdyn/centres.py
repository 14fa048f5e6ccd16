"""Instant centres in homogeneous coordinates, and Kennedy's rule.

A point is stored as ``(x, y, w)``: the Cartesian point ``(x/w, y/w)`` when
``w ≠ 0``, and the *direction* ``(x, y)`` at infinity when ``w = 0`` (the
instant centre of a slider and its guide, or of two links whose Kennedy lines
are parallel). The line through two points is their cross product and the
intersection of two lines is the cross product of the lines, so centres at
infinity need no special cases (Norton, *Design of Machinery*, sec. 6.4; the
notes: "I.C. of two bodies in sliding contact is located at ∞ along the normal
to the plane of slip").
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass

import numpy as np

__all__ = [
    "InstantCentre",
    "InstantCentres",
    "at_infinity",
    "collinearity",
    "finite",
    "intersect",
    "line_through",
]

#: |w| below this fraction of |(x, y)| marks a point at infinity.
_INFINITY_RTOL = 1e-12


def finite(z: np.ndarray | complex) -> np.ndarray:
    """Homogeneous coordinates ``(x, y, 1)`` of finite points given as complex numbers."""
    z = np.asarray(z, dtype=complex)
    return np.stack([z.real, z.imag, np.ones(z.shape)], axis=-1)


def at_infinity(direction: np.ndarray | complex) -> np.ndarray:
    """Homogeneous coordinates ``(x, y, 0)`` of the point at infinity along ``direction``."""
    d = np.asarray(direction, dtype=complex)
    return np.stack([d.real, d.imag, np.zeros(d.shape)], axis=-1)


def line_through(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """The line through two homogeneous points (their cross product)."""
    return np.cross(p, q)


def intersect(l1: np.ndarray, l2: np.ndarray) -> np.ndarray:
    """The intersection of two homogeneous lines (their cross product)."""
    return np.cross(l1, l2)


def collinearity(p: np.ndarray, q: np.ndarray, r: np.ndarray) -> np.ndarray:
    """Scale-free collinearity residual of three homogeneous points (0 when collinear).

    The determinant of the three normalised coordinate vectors; it is the sine
    of a "solid angle" and is ~1e-16 for collinear points whatever their size.
    """

    def unit(v: np.ndarray) -> np.ndarray:
        return v / np.linalg.norm(v, axis=-1, keepdims=True)

    return np.linalg.det(np.stack([unit(p), unit(q), unit(r)], axis=-2))


@dataclass(frozen=True)
class InstantCentre:
    """One instant centre over a set of samples.

    Attributes
    ----------
    homogeneous : ndarray, shape (..., 3)
        ``(x, y, w)`` normalised to unit length with ``w >= 0``.
    """

    homogeneous: np.ndarray

    @property
    def at_infinity(self) -> np.ndarray:
        """True where the centre is a point at infinity."""
        h = self.homogeneous
        return np.abs(h[..., 2]) <= _INFINITY_RTOL * np.hypot(h[..., 0], h[..., 1])

    @property
    def point(self) -> np.ndarray:
        """The centre as a complex number; NaN where it is at infinity (see ``direction``)."""
        h = self.homogeneous
        inf = self.at_infinity
        with np.errstate(divide="ignore", invalid="ignore"):
            z = (h[..., 0] + 1j * h[..., 1]) / h[..., 2]
        return np.where(inf, complex(np.nan, np.nan), z)

    @property
    def direction(self) -> np.ndarray:
        """Unit direction (complex) of a centre at infinity; NaN where it is finite."""
        h = self.homogeneous
        with np.errstate(divide="ignore", invalid="ignore"):
            d = (h[..., 0] + 1j * h[..., 1]) / np.hypot(h[..., 0], h[..., 1])
        return np.where(self.at_infinity, d, complex(np.nan, np.nan))


def _normalise(h: np.ndarray) -> np.ndarray:
    with np.errstate(divide="ignore", invalid="ignore"):
        h = h / np.linalg.norm(h, axis=-1, keepdims=True)
        flip = h[..., 2:3] < 0
        return np.where(flip, -h, h)


class InstantCentres(Mapping):
    """The instant centres of a mechanism, keyed by link pairs ``(i, j)`` with ``i < j``.

    Also indexable as ``ics[j, i]``. ``valid`` is False for samples where the
    mechanism could not be assembled.
    """

    def __init__(self, centres: dict[tuple[int, int], np.ndarray], valid: np.ndarray) -> None:
        self._centres = {
            tuple(sorted(k)): InstantCentre(_normalise(np.asarray(v, dtype=float)))
            for k, v in centres.items()
        }
        self.valid = np.asarray(valid, dtype=bool)

    def __getitem__(self, key: tuple[int, int]) -> InstantCentre:
        return self._centres[tuple(sorted(key))]

    def __iter__(self) -> Iterator[tuple[int, int]]:
        return iter(sorted(self._centres))

    def __len__(self) -> int:
        return len(self._centres)

    def __repr__(self) -> str:
        return f"InstantCentres({', '.join(f'I{i}{j}' for i, j in self)})"

    def omega_ratio(self, i: int, j: int, ground: int = 1) -> np.ndarray:
        """Angular velocity ratio ``ω_j / ω_i`` of two links, from the centres alone.

        ``I_gi``, ``I_gj`` and ``I_ij`` are collinear (Kennedy); the common point
        ``I_ij`` moves alike on both links, so ``ω_i · |I_gi I_ij| = ω_j · |I_gj I_ij|``
        with signs: ``ω_j/ω_i = (I_ij − I_gi) / (I_ij − I_gj)`` along that line.
        Exact when ``I_ij`` is at infinity (ratio 1: equal angular velocities).
        """
        p = self[ground, i].homogeneous
        q = self[ground, j].homogeneous
        x = self[i, j].homogeneous
        # Signed ratio along the line, written with homogeneous coordinates so
        # that a point at infinity (x_w = 0) needs no special case:
        # (X/xw − P/pw) / (X/xw − Q/qw) = (X pw − P xw) qw / ((X qw − Q xw) pw).
        num = x[..., :2] * p[..., 2:3] - p[..., :2] * x[..., 2:3]
        den = x[..., :2] * q[..., 2:3] - q[..., :2] * x[..., 2:3]
        # project on the line direction for a scalar ratio
        axis = np.where(np.abs(den[..., :1]) >= np.abs(den[..., 1:2]), 0, 1)
        num_s = np.take_along_axis(num, axis, axis=-1)[..., 0] * q[..., 2]
        den_s = np.take_along_axis(den, axis, axis=-1)[..., 0] * p[..., 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = num_s / den_s
        return np.where(self.valid, ratio, np.nan)


def fourbar_centres(r1: float, A: np.ndarray, B: np.ndarray, valid: np.ndarray) -> InstantCentres:
    """The six centres of a pin-jointed four-bar with ``O2`` at 0 and ``O4`` at ``r1``."""
    A = np.asarray(A, dtype=complex)
    I12 = finite(np.zeros(A.shape, dtype=complex))
    I14 = finite(np.full(A.shape, r1, dtype=complex))
    I23 = finite(A)
    I34 = finite(B)
    I13 = intersect(line_through(I12, I23), line_through(I14, I34))
    I24 = intersect(line_through(I12, I14), line_through(I23, I34))
    return InstantCentres(
        {(1, 2): I12, (1, 4): I14, (2, 3): I23, (3, 4): I34, (1, 3): I13, (2, 4): I24}, valid
    )
