"""Outlines of the drawn symbols in their own frames, shared by both back ends.

A symbol is drawn in *local* coordinates (complex numbers) and placed on the
page by a translation to a solved point and a rotation by a solved angle, so
the two back ends (matplotlib and SVG) draw the same shapes from one set of
numbers. Sizes are in drawing units (``unit`` = a hundredth of the drawing).
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "block",
    "damper",
    "ground_symbol",
    "motor_arrow",
    "placed",
    "spring",
]


def placed(local: np.ndarray, origin: complex, angle: float) -> np.ndarray:
    """Local outline points moved to ``origin`` and turned by ``angle`` (radians)."""
    return origin + np.exp(1j * angle) * np.asarray(local, dtype=complex)


def block(length: float, height: float) -> np.ndarray:
    """A slider block centred on the origin, its long side along +x (closed outline)."""
    hx, hy = 0.5 * length, 0.5 * height
    return np.array([-hx - 1j * hy, hx - 1j * hy, hx + 1j * hy, -hx + 1j * hy])


def ground_symbol(size: float) -> tuple[np.ndarray, np.ndarray]:
    """A pivot's support triangle (apex at the origin) and the hatched strip under it."""
    tri = np.array([0, -0.6 * size - 1j * size, 0.6 * size - 1j * size])
    strip = np.array(
        [
            -0.9 * size - 1j * size,
            0.9 * size - 1j * size,
            0.9 * size - 1.35j * size,
            -0.9 * size - 1.35j * size,
        ]
    )
    return tri, strip


def spring(amplitude: float, coils: int = 6) -> tuple[np.ndarray, np.ndarray]:
    """A zigzag from x = 0 to x = 1 (scaled along x only to the spring's length).

    Returns the x coordinates (fractions of the length) and the y offsets
    (drawing units).
    """
    n = 2 * coils
    x = np.concatenate([[0.0, 0.2], 0.2 + 0.6 * (np.arange(n) + 0.5) / n, [0.8, 1.0]])
    y = np.concatenate([[0.0, 0.0], amplitude * (-1.0) ** np.arange(n), [0.0, 0.0]])
    return x, y


def damper(width: float) -> list[tuple[np.ndarray, np.ndarray]]:
    """A dashpot from x = 0 to x = 1: rod, cup, piston, rod (polylines of (x, y))."""
    w = 0.5 * width
    return [
        (np.array([0.0, 0.42]), np.array([0.0, 0.0])),
        (np.array([0.52, 0.36, 0.36, 0.52]), np.array([w, w, -w, -w])),
        (np.array([0.45, 0.45]), np.array([0.7 * w, -0.7 * w])),
        (np.array([0.45, 1.0]), np.array([0.0, 0.0])),
    ]


def motor_arrow(radius: float) -> np.ndarray:
    """A three-quarter arc with an arrow head at its end, around the origin (a motor's sense).

    One polyline: the arc counter-clockwise from 45° to 315°, then the two
    barbs of the head (the polyline goes out along one and back).
    """
    t = np.linspace(0.25 * np.pi, 1.75 * np.pi, 31)
    arc = radius * np.exp(1j * t)
    tip = arc[-1]
    ahead = 1j * np.exp(1j * t[-1])  # direction of travel at the tip
    barbs = [tip - 0.55 * radius * ahead * np.exp(1j * s) for s in (0.45, -0.45)]
    return np.concatenate([arc, [barbs[0], tip, barbs[1]]])
