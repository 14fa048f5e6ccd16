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
