"""Mass properties: textbook formulas, parallel-axis theorem, composites, numeric integrals."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from machdyn.errors import InputError
from machdyn.massprops import (
    MassProperties,
    annulus,
    cg_motion,
    composite,
    disc,
    parallel_axis,
    plate,
    point_mass,
    radius_of_gyration,
    ring,
    rod,
)

positive = st.floats(0.01, 100.0)


def test_rod_about_end_is_ml2_over_3():
    # Notes ch. 10: I_O,rod = M l² / 3.
    bar = rod(2.5, 0.8)
    assert bar.cg == pytest.approx(0.4)
    assert bar.inertia_about(0) == pytest.approx(2.5 * 0.8**2 / 3)
    assert bar.inertia_about(0.8) == pytest.approx(2.5 * 0.8**2 / 3)


def test_lollipop_of_the_notes():
    # Notes ch. 10: I_O,disc = ½ M_d R² + M_d (l + R)², plus the rod's M_R l² / 3.
    m_r, length, m_d, radius = 1.2, 0.9, 3.0, 0.15
    lollipop = rod(m_r, length) + disc(m_d, radius, centre=length + radius)
    expected = m_r * length**2 / 3 + 0.5 * m_d * radius**2 + m_d * (length + radius) ** 2
    assert lollipop.inertia_about(0) == pytest.approx(expected, rel=1e-12)
    assert lollipop.mass == pytest.approx(m_r + m_d)
    assert lollipop.cg.real == pytest.approx(
        (m_r * length / 2 + m_d * (length + radius)) / (m_r + m_d)
    )


def numeric_inertia(points: np.ndarray, weights: np.ndarray, about: complex) -> float:
    """∫ |r − O|² dm by quadrature (independent of the closed forms)."""
    return float(np.sum(weights * np.abs(points - about) ** 2))


def test_shapes_against_numeric_integration():
    n = 400
    u = (np.arange(n) + 0.5) / n  # midpoint rule
    # Rectangular plate 0.3 × 0.2 centred at (1, 2), mass 6.
    x, y = np.meshgrid(-0.15 + 0.3 * u, -0.1 + 0.2 * u)
    pts = (1 + 2j) + (x + 1j * y).ravel()
    w = np.full(pts.size, 6.0 / pts.size)
    assert plate(6.0, 0.3, 0.2, centre=1 + 2j).inertia == pytest.approx(
        numeric_inertia(pts, w, 1 + 2j), rel=1e-4
    )
    # Solid disc of radius 0.5, mass 4: polar midpoint rule, dm ∝ r dr dθ.
    r, t = np.meshgrid(0.5 * u, 2 * np.pi * u)
    pts = (r * np.exp(1j * t)).ravel()
    w = (r / r.sum() * 4.0).ravel()
    assert disc(4.0, 0.5).inertia == pytest.approx(numeric_inertia(pts, w, 0), rel=1e-4)
    # Annulus 0.2..0.5.
    r, t = np.meshgrid(0.2 + 0.3 * u, 2 * np.pi * u)
    pts = (r * np.exp(1j * t)).ravel()
    w = (r / r.sum() * 4.0).ravel()
    assert annulus(4.0, 0.5, 0.2).inertia == pytest.approx(numeric_inertia(pts, w, 0), rel=1e-4)
    # Slender rod at 30° from (1, 1), length 2: points along the line.
    pts = (1 + 1j) + 2 * u * np.exp(1j * math.radians(30))
    w = np.full(n, 3.0 / n)
    bar = rod(3.0, 2.0, start=1 + 1j, angle=math.radians(30))
    assert bar.cg == pytest.approx(pts.mean())
    assert bar.inertia_about(1 + 1j) == pytest.approx(numeric_inertia(pts, w, 1 + 1j), rel=1e-4)


def test_ring_and_point_mass():
    assert ring(2.0, 0.3).inertia == pytest.approx(2.0 * 0.09)
    assert ring(2.0, 0.3).radius_of_gyration == pytest.approx(0.3)
    p = point_mass(5.0, 3 + 4j)
    assert p.inertia == 0.0
    assert p.inertia_about(0) == pytest.approx(5.0 * 25.0)
    assert p.radius_of_gyration_about(0) == pytest.approx(5.0)


def test_plate_with_a_hole():
    # 0.4 × 0.2 plate, density-consistent masses (areal density 50): a hole of radius 0.05
    # at x = +0.1 from the plate's centre.
    sigma = 50.0
    full = plate(sigma * 0.08, 0.4, 0.2)
    hole = disc(sigma * math.pi * 0.05**2, 0.05, centre=0.1)
    holed = full - hole
    m = sigma * (0.08 - math.pi * 0.0025)
    assert holed.mass == pytest.approx(m)
    assert holed.cg.real == pytest.approx(-sigma * math.pi * 0.0025 * 0.1 / m)
    # About the plate's centre: I = I_plate − (I_hole + m_hole d²), then move to G.
    i_centre = full.inertia - (0.5 * hole.mass * 0.05**2 + hole.mass * 0.1**2)
    assert holed.inertia_about(0) == pytest.approx(i_centre, rel=1e-12)
    assert holed.inertia == pytest.approx(i_centre - m * holed.cg.real**2, rel=1e-12)


@given(
    m=st.lists(positive, min_size=1, max_size=6),
    x=st.lists(st.floats(-5, 5), min_size=6, max_size=6),
    y=st.lists(st.floats(-5, 5), min_size=6, max_size=6),
    about=st.complex_numbers(max_magnitude=5.0),
)
def test_composite_of_points_matches_direct_sum(m, x, y, about):
    parts = [point_mass(mi, complex(xi, yi)) for mi, xi, yi in zip(m, x, y, strict=False)]
    body = composite(*parts)
    pts = np.array([p.cg for p in parts])
    w = np.array(m)
    assert body.mass == pytest.approx(w.sum())
    assert body.inertia_about(about) == pytest.approx(
        numeric_inertia(pts, w, about), rel=1e-9, abs=1e-9
    )


def test_moved_keeps_inertia_and_moves_cg():
    bar = rod(1.0, 2.0)
    turned = bar.moved(offset=3 + 0j, angle=math.pi)
    assert turned.cg == pytest.approx(2 + 0j)
    assert turned.inertia == bar.inertia


def test_functions_broadcast():
    out = parallel_axis(np.array([1.0, 2.0]), 2.0, np.array([1.0, 1j]))
    np.testing.assert_allclose(out, [3.0, 4.0])
    assert radius_of_gyration(8.0, 2.0) == pytest.approx(2.0)


@pytest.mark.parametrize(
    ("make", "field"),
    [
        (lambda: rod(0.0, 1.0), "mass"),
        (lambda: rod(1.0, -1.0), "length"),
        (lambda: disc(-2.0, 1.0), "mass"),
        (lambda: disc(1.0, 0.0), "radius"),
        (lambda: annulus(1.0, 1.0, 1.5), "inner_radius"),
        (lambda: plate(1.0, 0.0, 1.0), "width"),
        (lambda: MassProperties(1.0, 0j, -0.1), "inertia"),
        (lambda: MassProperties(float("nan"), 0j, 0.1), "mass"),
        (lambda: MassProperties(1.0, complex("nan"), 0.1), "cg"),
        (lambda: disc(1.0, 1.0) - disc(2.0, 1.0), "mass"),
        (lambda: disc(1.0, 1.0) - ring(0.9, 2.0), "inertia"),
        (lambda: composite(), "parts"),
        (lambda: radius_of_gyration(1.0, 0.0), "mass"),
        (lambda: point_mass(1.0, "here"), "at"),
        # review findings 8 and 9: these used to return −3, nan, or raise a bare ValueError
        (lambda: parallel_axis(-1.0, 2.0, 1.0), "inertia_g"),
        (lambda: parallel_axis(1.0, -2.0, 1.0), "mass"),
        (lambda: parallel_axis(float("nan"), 2.0, 1.0), "inertia_g"),
        (lambda: parallel_axis(1.0, 2.0, complex("nan")), "d"),
        (lambda: parallel_axis("a", 2.0, 1.0), "inertia_g"),
        (lambda: parallel_axis([1, 2], [1, 2, 3], 1), "mass"),
        (lambda: radius_of_gyration(float("nan"), 1.0), "inertia"),
        (lambda: radius_of_gyration(1.0, "x"), "mass"),
        (lambda: radius_of_gyration([1.0, 2.0], [1.0, 2.0, 3.0]), "mass"),
        (lambda: cg_motion(float("nan"), 1.0, 0.0, 1.0), "theta"),
        (lambda: cg_motion(0.0, "fast", 0.0, 1.0), "omega"),
        (lambda: cg_motion([0.0, 1.0], [1.0, 2.0, 3.0], 0.0, 1.0), "omega"),
        (lambda: cg_motion(0.0, 1.0, 0.0, 1.0, origin=complex("inf")), "origin"),
        (
            lambda: cg_motion([0.0, 1.0], 1.0, 0.0, 1.0, origin_velocity=[1j, 2j, 3j]),
            "origin_velocity",
        ),
    ],
)
def test_bad_input(make, field):
    with pytest.raises(InputError) as info:
        make()
    assert info.value.field == field


def test_cg_motion_against_finite_differences():
    # A coupler-like link: origin moving on a circle, link turning non-uniformly.
    from machdyn.massprops import cg_motion

    t = np.linspace(0.0, 2.0, 4001)
    h = t[1] - t[0]
    theta = 0.3 + 1.5 * t + 0.4 * np.sin(2 * t)
    omega = 1.5 + 0.8 * np.cos(2 * t)
    alpha = -1.6 * np.sin(2 * t)
    origin = 2.0 * np.exp(1j * 3 * t)
    v_origin = 6j * np.exp(1j * 3 * t)
    a_origin = -18.0 * np.exp(1j * 3 * t)
    cg = 0.7 + 0.2j
    R, V, A = cg_motion(theta, omega, alpha, cg, origin, v_origin, a_origin)
    np.testing.assert_allclose(R, origin + cg * np.exp(1j * theta), atol=1e-14)
    np.testing.assert_allclose(np.gradient(R, h)[2:-2], V[2:-2], atol=1e-5)
    np.testing.assert_allclose(np.gradient(V, h)[2:-2], A[2:-2], atol=1e-4)
    assert R.shape == t.shape
