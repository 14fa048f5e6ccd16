"""Small closed forms shared by several test files (written here, not in machdyn)."""

from __future__ import annotations

import numpy as np


def circle_meet(p: complex, r1: float, q: complex, r2: float, side: float = 1.0) -> complex:
    """Intersection of circles (p, r1) and (q, r2); ``side`` picks left/right of p→q."""
    d = abs(q - p)
    a = (r1**2 - r2**2 + d**2) / (2 * d)
    h = np.sqrt(r1**2 - a**2)
    u = (q - p) / d
    return p + a * u + side * h * 1j * u


def circle_line_meet(
    centre: complex, r: float, point: complex, direction: complex, side: float = 1.0
) -> complex:
    """Meet of the circle (centre, r) and the line point + t·direction, in real coordinates.

    ``side`` +1 takes the root further along ``direction`` (the quadratic's larger ``t``).
    """
    dx, dy = direction.real, direction.imag
    fx, fy = point.real - centre.real, point.imag - centre.imag
    a = dx * dx + dy * dy
    b = 2.0 * (fx * dx + fy * dy)
    c = fx * fx + fy * fy - r * r
    t = (-b + side * np.sqrt(b * b - 4.0 * a * c)) / (2.0 * a)
    return complex(point.real + t * dx, point.imag + t * dy)


def line_meet(p1: complex, u1: complex, p2: complex, u2: complex) -> complex:
    """Meet of the lines p1 + s·u1 and p2 + t·u2 (a 2 × 2 linear solve in real coordinates)."""
    m = np.array([[u1.real, -u2.real], [u1.imag, -u2.imag]])
    s, _ = np.linalg.solve(m, [p2.real - p1.real, p2.imag - p1.imag])
    return complex(p1.real + s * u1.real, p1.imag + s * u1.imag)


def tangent_angle(A: complex, C: complex, e: float, side: float = 1.0) -> float:
    """Angle of the line through C that passes at signed distance e from A (A on its right
    for e > 0); ``side`` +1: C lies ahead of the foot of A along the line."""
    r = np.hypot(C.real - A.real, C.imag - A.imag)
    t = side * np.sqrt(r * r - e * e)
    return float(np.arctan2(C.imag - A.imag, C.real - A.real) - np.arctan2(e, t))


def slide_meet(p: complex, r: float, g: complex, phi: float, side: float = 1.0) -> complex:
    """Point on the line ``g + t e^{jφ}`` at distance ``r`` from ``p``; ``side`` picks the
    root with ``t`` above (+1) or below (−1) the foot of the perpendicular from ``p``."""
    e = np.exp(1j * phi)
    foot = ((p - g) * np.conj(e)).real  # t of the foot of the perpendicular
    h2 = r**2 - (((p - g) * np.conj(e)).imag) ** 2
    return g + (foot + side * np.sqrt(h2)) * e
