"""Function generation (Freudenstein): precision points, least squares, Chebyshev, defects."""

from __future__ import annotations

import math

import numpy as np
import pytest

from machdyn.errors import AssemblyError, InputError
from machdyn.fourbar import FourBar
from machdyn.synthesis import (
    chebyshev_spacing,
    freudenstein_coefficients,
    function_generator,
    lengths_from_freudenstein,
)

LOG_CASE = dict(
    func=np.log10,
    x_range=(1.0, 2.0),
    theta2_range=np.radians((45, 105)),
    theta4_range=np.radians((135, 225)),
)


def test_chebyshev_spacing_closed_form():
    # n = 3: the midpoint and ±(h/2)·cos 30° (Norton ch. 5)
    x = chebyshev_spacing(1.0, 3.0, 3)
    np.testing.assert_allclose(x, [2 - math.sqrt(3) / 2, 2.0, 2 + math.sqrt(3) / 2])
    # the points are the roots of the Chebyshev polynomial T_n on the mapped interval
    for n in (4, 7):
        u = chebyshev_spacing(-1.0, 1.0, n)
        np.testing.assert_allclose(np.polynomial.chebyshev.chebval(u, [0] * n + [1]), 0, atol=1e-12)


def test_freudenstein_round_trip_recovers_a_known_linkage():
    """Precision points sampled from FourBar.solve (another code path) give back its lengths."""
    fb = FourBar(8, 4, 7, 6)
    th2 = np.radians([10.0, 55.0, 120.0])
    th4 = fb.solve(th2).theta4
    k = freudenstein_coefficients(th2, th4)
    # closed form of the coefficients: d/a, d/c, (a²−b²+c²+d²)/(2ac)
    np.testing.assert_allclose(k, [8 / 4, 8 / 6, (16 - 49 + 36 + 64) / (2 * 4 * 6)], rtol=1e-12)
    np.testing.assert_allclose(lengths_from_freudenstein(k, r1=8), (8, 4, 7, 6), rtol=1e-12)


def test_least_squares_recovers_a_linkage_from_many_exact_points(rng):
    fb = FourBar(7, 3, 8, 5)
    th2 = np.sort(rng.uniform(0, 2 * np.pi, 40))
    k = freudenstein_coefficients(th2, fb.solve(th2, form=2).theta4)
    np.testing.assert_allclose(lengths_from_freudenstein(k, r1=7), fb.lengths, rtol=1e-10)


def test_least_squares_residual_is_no_worse_than_any_three_points(rng):
    g = function_generator(**LOG_CASE, n=15)
    th2 = g.theta2_of(g.x_precision)
    th4 = g.theta4_of(np.log10(g.x_precision))

    def residual(k):
        return np.linalg.norm(k[0] * np.cos(th4) - k[1] * np.cos(th2) + k[2] - np.cos(th2 - th4))

    best = residual(g.k)
    for _ in range(20):
        pick = np.sort(rng.choice(th2.size, 3, replace=False))
        assert best <= residual(freudenstein_coefficients(th2[pick], th4[pick])) + 1e-15


def test_three_precision_points_are_exact_by_an_independent_solve():
    g = function_generator(**LOG_CASE)
    assert g.ok
    th2 = g.theta2_of(g.x_precision)
    m = g.fourbar.solve(th2 + g.input_offset, form=1 if g.branch == 1 else 2)
    want = g.theta4_of(np.log10(g.x_precision))
    got = m.theta4 - g.output_offset
    np.testing.assert_allclose(np.angle(np.exp(1j * (got - want))), 0.0, atol=1e-10)
    np.testing.assert_allclose(g.x_precision, chebyshev_spacing(1, 2, 3))


def test_structural_error_vanishes_only_at_precision_points():
    g = function_generator(**LOG_CASE)
    se = g.structural_error(n=2001)
    assert se.ok.all()
    # the error changes sign at each precision point: zero there, not elsewhere
    at = np.isin(se.x, g.x_precision)
    assert np.all(np.abs(se.error[at]) < 1e-12)
    crossings = np.flatnonzero(np.diff(np.sign(se.error[~at])) != 0)
    assert len(crossings) == 3


def test_chebyshev_spacing_beats_uniform_spacing():
    """Norton ch. 5: Chebyshev spacing lowers the largest structural error."""
    cheb = function_generator(**LOG_CASE, spacing="chebyshev").structural_error(n=2001)
    unif = function_generator(**LOG_CASE, spacing="uniform").structural_error(n=2001)
    assert cheb.max_abs < unif.max_abs
    # uniform spacing includes the ends, where the error is then zero
    assert abs(unif.error[0]) < 1e-12 and abs(unif.error[-1]) < 1e-12


def test_negative_length_becomes_an_angle_offset():
    g = function_generator(np.exp, (0.0, 1.0), np.radians((0, 90)), np.radians((180, 200)))
    assert min(g.fourbar.lengths) > 0
    # Freudenstein's signed lengths and the offsets agree
    _, a, _, c = lengths_from_freudenstein(g.k, g.r1)
    assert (a < 0) == (g.input_offset == math.pi)
    assert (c < 0) == (g.output_offset == math.pi)
    assert g.structural_error(x=g.x_precision).max_abs < 1e-10


def test_unreachable_range_is_reported():
    g = function_generator(np.exp, (0.0, 1.0), np.radians((10, 350)), np.radians((20, 340)))
    assert not g.ok
    assert "cannot be assembled" in g.defects[0]
    se = g.structural_error()
    assert not se.ok.all()
    assert np.all(np.isnan(se.error[~se.ok]))
    assert all(r for r in se.reason[~se.ok])


def test_no_fourbar_for_these_points():
    # K3 so large that b² = a² + c² + d² − 2acK3 < 0
    with pytest.raises(AssemblyError, match="no four-bar"):
        lengths_from_freudenstein([1.0, 1.0, 5.0])


def test_bad_input():
    with pytest.raises(InputError, match="spacing"):
        function_generator(**LOG_CASE, spacing="random")
    with pytest.raises(InputError, match="at least 3"):
        freudenstein_coefficients([0, 1], [0, 1])
    with pytest.raises(InputError, match="determine"):
        freudenstein_coefficients([0.1, 0.1, 0.1], [0.2, 0.2, 0.2])
    with pytest.raises(InputError, match="x_range"):
        function_generator(np.log10, (1.0, 1.0), (0, 1), (0, 1))
    with pytest.raises(InputError, match="func"):
        function_generator(np.cos, (-1.0, 1.0), (0, 1), (0, 1))  # f(x0) == f(xf)
    with pytest.raises(InputError, match="x_precision"):
        function_generator(**LOG_CASE, x_precision=[1.0, 1.5, 3.0])


def test_a_constant_function_is_refused_by_name():
    from machdyn import InputError
    from machdyn.synthesis import function_generator

    with pytest.raises(InputError, match="func"):
        function_generator(lambda x: 1.0, (1.0, 2.0), np.radians((45, 105)), np.radians((135, 225)))
