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


def line_meet(p: complex, r: float, g: complex, phi: float, side: float = 1.0) -> complex:
    """Point on the line ``g + t e^{jφ}`` at distance ``r`` from ``p``; ``side`` picks the
    root with ``t`` above (+1) or below (−1) the foot of the perpendicular from ``p``."""
    e = np.exp(1j * phi)
    foot = ((p - g) * np.conj(e)).real  # t of the foot of the perpendicular
    h2 = r**2 - (((p - g) * np.conj(e)).imag) ** 2
    return g + (foot + side * np.sqrt(h2)) * e
