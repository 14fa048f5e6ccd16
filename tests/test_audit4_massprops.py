"""Audit 4: composite mass properties against a polygon's closed forms.

An L-shaped steel bracket with a round hole, built from ``plate`` and ``disc``
parts (``+`` and ``−``), against the shoelace formulas for a polygon of uniform
areal density written here (area, first moments and polar second moment about
the origin, Σ over edges of the triangle (0, p_i, p_i+1)), minus the hole's
πr², ½ m r² + m d². Then moved and turned: the centre of mass maps rigidly and
``I_G`` is unchanged, ``inertia_about`` obeys the parallel-axis theorem.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from machdyn.massprops import disc, plate

RHO = 7.85  # areal density (kg per unit area): any consistent number


def polygon(points):
    """Area, centroid and polar second moment about the origin of a simple polygon."""
    x, y = np.real(points), np.imag(points)
    x1, y1 = np.roll(x, -1), np.roll(y, -1)
    cross = x * y1 - x1 * y
    area = cross.sum() / 2
    cx = ((x + x1) * cross).sum() / (6 * area)
    cy = ((y + y1) * cross).sum() / (6 * area)
    ixx = ((y * y + y * y1 + y1 * y1) * cross).sum() / 12  # ∫ y² dA
    iyy = ((x * x + x * x1 + x1 * x1) * cross).sum() / 12  # ∫ x² dA
    return area, complex(cx, cy), ixx + iyy


@pytest.mark.parametrize("angle", [0.0, 0.7, -2.1])
def test_l_bracket_with_a_hole(angle):
    # L: a 6 × 1 foot along x and a 1 × 4 upright at the left end, hole r = 0.3 at (4, 0.5)
    outline = np.array([0, 6, 6 + 1j, 1 + 1j, 1 + 5j, 5j])
    area, c, j_origin = polygon(outline)
    assert area == pytest.approx(6 + 4)
    r, hole_at = 0.3, 4 + 0.5j
    hole_area = math.pi * r * r
    mass = RHO * (area - hole_area)
    first = RHO * (area * c - hole_area * hole_at)
    j_o = RHO * (j_origin - (hole_area * r * r / 2 + hole_area * abs(hole_at) ** 2))
    cg = first / mass
    i_g = j_o - mass * abs(cg) ** 2

    body = (
        plate(RHO * 6, 6, 1, centre=3 + 0.5j)
        + plate(RHO * 4, 1, 4, centre=0.5 + 3j)
        - disc(RHO * hole_area, r, centre=hole_at)
    )
    assert body.mass == pytest.approx(mass, rel=1e-12)
    assert body.cg == pytest.approx(cg, rel=1e-12)
    assert body.inertia == pytest.approx(i_g, rel=1e-12)
    assert body.inertia_about(0) == pytest.approx(j_o, rel=1e-12)
    # moved rigidly: G' = offset + G e^{jφ}, I_G the same, I about a point by parallel axes
    offset = 2 - 1j
    moved = body.moved(offset, angle)
    assert moved.cg == pytest.approx(offset + cg * np.exp(1j * angle), rel=1e-12, abs=1e-12)
    assert moved.inertia == pytest.approx(i_g, rel=1e-12)
    point = 1 + 3j
    assert moved.inertia_about(point) == pytest.approx(
        i_g + mass * abs(moved.cg - point) ** 2, rel=1e-12
    )
    assert moved.radius_of_gyration == pytest.approx(math.sqrt(i_g / mass), rel=1e-12)
