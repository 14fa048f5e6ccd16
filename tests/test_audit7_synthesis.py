"""Audit 7: function and motion synthesis checked at the precision points, by geometry here.

* Freudenstein (the notes' function generation; Norton eq. 5.x):
  ``K1 cos θ4 − K2 cos θ2 + K3 = cos(θ2 − θ4)``, ``K1 = d/a``, ``K2 = d/c``,
  ``K3 = (a² − b² + c² + d²)/(2ac)``. A random four-bar's own poses (circle
  intersections here) must give back its lengths; a synthesised generator's
  linkage, assembled here by circle intersection, must pass through its
  precision points.
* Two- and three-position motion synthesis: the fixed pivots must be
  equidistant from the moving pivots in every position (each moving pivot
  turns about its fixed pivot), and the coupler carries the given line.
"""

from __future__ import annotations

import numpy as np
import pytest

from machdyn import synthesis
from machdyn.errors import MachdynError


def theta4_both(d, a, b, c, t2):
    """Both circle-intersection output angles of a four-bar (ground d, input a, coupler b,
    output c; signed a, c allowed: that link points the other way)."""
    A = a * np.exp(1j * t2)
    u = d - A
    r = abs(u)
    cos_g = (b * b + r * r - c * c) / (2 * b * r)
    if abs(cos_g) > 1:
        return []
    out = []
    for s in (1, -1):
        B = A + b * u / r * np.exp(1j * s * np.arccos(cos_g))
        out.append(np.angle((B - d) / c))  # the output link points from O4 to B (c > 0)
    return out


@pytest.mark.parametrize("seed", range(3))
def test_freudenstein_gives_back_the_linkage_that_made_the_points(seed):
    rng = np.random.default_rng(seed)
    done = 0
    while done < 25:
        d, a, b, c = rng.uniform(0.5, 3.0, 4)
        t2 = np.sort(rng.uniform(0, 2 * np.pi, 3))
        t4 = []
        for t in t2:
            both = theta4_both(d, a, b, c, t)
            if not both:
                break
            t4.append(both[0])
        if len(t4) < 3:
            continue
        try:
            k = synthesis.freudenstein_coefficients(t2, np.array(t4))
        except MachdynError:
            continue  # nearly repeated points: refused by name
        expected = [d / a, d / c, (a * a - b * b + c * c + d * d) / (2 * a * c)]
        np.testing.assert_allclose(k, expected, rtol=1e-6)
        np.testing.assert_allclose(synthesis.lengths_from_freudenstein(k, r1=d), (d, a, b, c))
        done += 1


@pytest.mark.parametrize(
    ("func", "x_range", "t2_range", "t4_range"),
    [
        (
            np.log10,
            (1.0, 10.0),
            (np.radians(30), np.radians(120)),
            (np.radians(60), np.radians(150)),
        ),
        (
            np.square,
            (0.0, 1.0),
            (np.radians(45), np.radians(135)),
            (np.radians(240), np.radians(300)),
        ),
        (
            np.sin,
            (0.0, np.pi / 2),
            (np.radians(-20), np.radians(70)),
            (np.radians(100), np.radians(20)),
        ),
    ],
)
def test_function_generator_linkage_passes_its_precision_points(func, x_range, t2_range, t4_range):
    try:
        fg = synthesis.function_generator(func, x_range, t2_range, t4_range)
    except MachdynError:
        pytest.skip("no four-bar for these ranges (refused by name)")
    x0, xf = x_range
    # Chebyshev spacing (Norton eq. 5.x): x_j = (x0 + xf)/2 − (xf − x0)/2 cos((2j − 1)π/(2n)).
    j = np.arange(1, 4)
    xs = (x0 + xf) / 2 - (xf - x0) / 2 * np.cos((2 * j - 1) * np.pi / 6)
    y0, yf = func(np.array([x0, xf]))
    t2 = t2_range[0] + (xs - x0) / (xf - x0) * (t2_range[1] - t2_range[0])
    t4 = t4_range[0] + (func(xs) - y0) / (yf - y0) * (t4_range[1] - t4_range[0])
    np.testing.assert_allclose(fg.x_precision, xs, rtol=1e-12)
    # The synthesised four-bar (lengths as given, link angles θ + offset), assembled here.
    d, a, b, c = fg.r1, fg.r2, fg.r3, fg.r4
    for t_in, t_out in zip(t2, t4, strict=True):
        both = theta4_both(d, a, b, c, t_in + fg.input_offset)
        gap = min(abs(np.angle(np.exp(1j * (t - t_out - fg.output_offset)))) for t in both)
        assert gap < 1e-9


def rigid_positions(rng, count):
    """A coupler line CD carried through ``count`` random rigid positions."""
    length = rng.uniform(0.5, 2.0)
    c = rng.normal(size=count) + 1j * rng.normal(size=count)
    angle = rng.uniform(0, 2 * np.pi, count)
    return c, c + length * np.exp(1j * angle)


@pytest.mark.parametrize("seed", range(3))
def test_three_position_pivots_are_centres_of_the_moving_pivots_circles(seed):
    rng = np.random.default_rng(40 + seed)
    done = 0
    while done < 15:
        c, d = rigid_positions(rng, 3)
        try:
            result = synthesis.three_position(c, d)
        except MachdynError:
            continue
        o2, o4 = complex(result.O2), complex(result.O4)
        # the moving pivots are C and D themselves here
        r2 = np.abs(c - o2)
        r4 = np.abs(d - o4)
        np.testing.assert_allclose(r2, r2[0], rtol=1e-9)
        np.testing.assert_allclose(r4, r4[0], rtol=1e-9)
        done += 1


@pytest.mark.parametrize("seed", range(3))
def test_two_position_pivots_lie_on_the_bisectors_at_the_asked_distances(seed):
    rng = np.random.default_rng(50 + seed)
    for _ in range(15):
        c, d = rigid_positions(rng, 2)
        s2, s4 = rng.uniform(-2, 2, 2)
        try:
            result = synthesis.two_position(c, d, s2=s2, s4=s4)
        except MachdynError:
            continue
        o2, o4 = complex(result.O2), complex(result.O4)
        assert abs(c[0] - o2) == pytest.approx(abs(c[1] - o2), rel=1e-9)
        assert abs(d[0] - o4) == pytest.approx(abs(d[1] - o4), rel=1e-9)
        # signed distance from the midpoint, positive to the left of C1 → C2
        left = 1j * (c[1] - c[0]) / abs(c[1] - c[0])
        assert ((o2 - (c[0] + c[1]) / 2) / left).real == pytest.approx(s2, abs=1e-9)
        left = 1j * (d[1] - d[0]) / abs(d[1] - d[0])
        assert ((o4 - (d[0] + d[1]) / 2) / left).real == pytest.approx(s4, abs=1e-9)
