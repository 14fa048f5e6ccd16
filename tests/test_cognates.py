"""Roberts–Chebyshev cognates, checked against Roberts' theorem written out here.

For random placed four-bars with a coupler point, the joints of every pose come from
circle intersections written in this file (no machdyn solver). Roberts' theorem
(Norton, *Design of Machinery*, §3.7): cognate 2's input link turns with the
original's coupler, cognate 3's with the original's crank; both coupler points
coincide with the original's in every pose, and the new ground pivot makes a ground
triangle similar to the coupler triangle.
"""

from __future__ import annotations

import numpy as np
import pytest

from machdyn.errors import InputError
from machdyn.fourbar import FourBar
from machdyn.synthesis import PlacedFourBar, cognates


def _joints(lengths, coupler, O2, theta1, side, theta2):
    """Global A, B and P of a placed four-bar at ``theta2``, one assembly ``side``."""
    r1, r2, r3, r4 = lengths
    p, delta = coupler
    a = r2 * np.exp(1j * theta2)
    d = a - r1  # from O4 to A
    dist = np.abs(d)
    along = (dist**2 + r4**2 - r3**2) / (2 * dist)  # from O4 towards A
    with np.errstate(invalid="ignore"):  # (NaN where the linkage cannot be assembled)
        across = np.sqrt(r4**2 - along**2)
    b = r1 + d / dist * (along + 1j * side * across)
    P = a + p * np.exp(1j * delta) * (b - a) / r3
    to = O2 + np.exp(1j * theta1) * np.stack([a, b, P])
    return to[0], to[1], to[2]


def _random_cases(count):
    rng = np.random.default_rng(2026)
    out = []
    while len(out) < count:
        lengths = tuple(rng.uniform(0.5, 3.0, 4))
        s = np.sort(lengths)
        if s[3] >= s[:3].sum():
            continue
        coupler = (float(rng.uniform(0.3, 2.5)), float(rng.uniform(-np.pi, np.pi)))
        O2, theta1 = complex(*rng.normal(0, 2, 2)), float(rng.uniform(-np.pi, np.pi))
        side = float(rng.choice([-1.0, 1.0]))
        theta2 = np.linspace(0.0, 2 * np.pi, 721)
        B = _joints(lengths, coupler, O2, theta1, side, theta2)[1]
        ok = np.isfinite(B)
        if ok.sum() < 60:
            continue
        run = np.split(np.flatnonzero(ok), np.flatnonzero(np.diff(np.flatnonzero(ok)) != 1) + 1)
        out.append((lengths, coupler, O2, theta1, side, theta2[max(run, key=len)]))
    return out


def _placed(lengths, coupler, O2, theta1, side, theta2):
    """The original as a PlacedFourBar in the assembly of ``side`` (from its joints)."""
    A, B, P = _joints(lengths, coupler, O2, theta1, side, theta2[:1])
    O4 = O2 + lengths[0] * np.exp(1j * theta1)
    return PlacedFourBar.from_pivots(O2=O2, O4=O4, A=A[0], B=B[0], P=P[0])


def _circles_meet(c1, r1, c2, r2):
    """Both points at ``r1`` from ``c1`` and ``r2`` from ``c2`` (complex)."""
    d = c2 - c1
    dist = abs(d)
    along = (dist**2 + r1**2 - r2**2) / (2 * dist)
    across = np.sqrt(max(r1**2 - along**2, 0.0))
    return [c1 + d / dist * (along + 1j * s * across) for s in (1.0, -1.0)]


def _input_at(cog, point):
    """The cognate's input angle putting its coupler point at ``point``: its crank pin is
    where the circle of its crank about its pivot meets the circle of radius ``p``
    (its pin to its coupler point) about ``point``."""
    lengths, (p, _) = cog.fourbar.lengths, cog.fourbar.coupler
    r2 = lengths[1]
    tries = []
    for pin in _circles_meet(cog.O2, r2, point, p):
        theta = float(np.angle(pin - cog.O2)) - cog.theta1
        for side in (1.0, -1.0):
            got = _joints(lengths, cog.fourbar.coupler, cog.O2, cog.theta1, side, np.array([theta]))
            tries.append((abs(got[2][0] - point), theta))
    return min(tries)[1]


@pytest.mark.parametrize("case", _random_cases(12))
def test_cognates_trace_the_coupler_curve_with_roberts_timing(case):
    lengths, coupler, O2, theta1, side, theta2 = case
    A, B, P = _joints(lengths, coupler, O2, theta1, side, theta2)
    c2, c3 = cognates(_placed(*case))
    size = float(np.max(np.abs(P - P.mean())))
    # cognate 2's input turns with the original's coupler, cognate 3's with its crank: a
    # fixed angle apart, found at the first pose. (A cognate may change its assembly where
    # the original does not, e.g. cognate 2 where the original's crank and rocker are
    # parallel, so each pose takes the nearer of the cognate's two assemblies.)
    for cog, drive in ((c2, np.unwrap(np.angle(B - A))), (c3, np.unwrap(np.angle(A - O2)))):
        theta = _input_at(cog, P[0]) + drive - drive[0]
        lengths_c, coupler_c = cog.fourbar.lengths, cog.fourbar.coupler
        both = [_joints(lengths_c, coupler_c, cog.O2, cog.theta1, s, theta)[2] for s in (1, -1)]
        miss = np.fmin(np.abs(both[0] - P), np.abs(both[1] - P))
        assert np.max(miss) <= 1e-9 * size


@pytest.mark.parametrize("case", _random_cases(4))
def test_the_new_pivot_makes_a_ground_triangle_like_the_coupler_triangle(case):
    lengths, coupler, O2, theta1, side, theta2 = case
    A, B, P = _joints(lengths, coupler, O2, theta1, side, theta2[:1])
    original = _placed(*case)
    c2, c3 = cognates(original)
    assert abs(c2.O2 - original.O2) <= 1e-12  # cognate 2 keeps O2
    assert abs(c3.O4 - original.O4) <= 1e-12  # cognate 3 keeps O4
    O3 = c2.O4
    assert abs(c3.O2 - O3) <= 1e-12  # both share the third pivot
    z_coupler = (P[0] - A[0]) / (B[0] - A[0])
    z_ground = (O3 - O2) / (original.O4 - O2)
    assert abs(z_ground - z_coupler) <= 1e-12
    # Cayley's ratios: cognate 2's links |z| times the original's ground, coupler, crank, rocker
    k = abs(z_coupler)
    r1, r2, r3, r4 = lengths
    assert c2.lengths == pytest.approx((k * r1, k * r3, k * r2, k * r4), rel=1e-12)
    m = abs(1 - z_coupler)
    assert c3.lengths == pytest.approx((m * r1, m * r2, m * r4, m * r3), rel=1e-12)


def test_a_linkage_without_a_usable_coupler_point_is_refused():
    plain = PlacedFourBar(FourBar(5.0, 2.0, 5.0, 4.0), 0j, 0.0, 1)
    with pytest.raises(InputError, match="no coupler point"):
        cognates(plain)
    at_A = PlacedFourBar(FourBar(5.0, 2.0, 5.0, 4.0, coupler=(0.0, 0.3)), 0j, 0.0, 1)
    with pytest.raises(InputError, match="at A or B"):
        cognates(at_A)
    at_B = PlacedFourBar(FourBar(5.0, 2.0, 5.0, 4.0, coupler=(5.0, 0.0)), 0j, 0.0, 1)
    with pytest.raises(InputError, match="at A or B"):
        cognates(at_B)
    with pytest.raises(InputError, match="linkage"):
        cognates("not a linkage")
