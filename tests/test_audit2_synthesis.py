"""Audit 2: synthesis closed forms against an independent solve of what they return.

Motion generation (two / three positions, three positions with the fixed
pivots given; notes ch. 3, Norton §3.4–3.6 and Ex. 3-7), Freudenstein
function generation (Norton §5.9, Eq. 5.25–5.27) and the quick-return
crank-rocker (Norton §3.5, ``δ = π (TR − 1)/(TR + 1)``): every returned linkage
is moved here by a position solve written in this file (two circles, the
assembly kept by the side of ``B`` from the line ``A O4``), never by machdyn's
solver, and checked against the job it was asked to do. Inputs are seeded
random positions, functions and ranges.
"""

from __future__ import annotations

import numpy as np
import pytest

from machdyn.errors import AssemblyError, InputError
from machdyn.synthesis.function import function_generator
from machdyn.synthesis.motion import (
    driving_dyad,
    rotopole_link,
    three_position,
    three_position_fixed_pivots,
    two_position,
)
from machdyn.synthesis.quick_return import quick_return

TWO_PI = 2 * np.pi


def cross(a, b):
    return (np.conj(a) * b).imag


def pin_B(O2, O4, A, r3, r4, side):
    """B on circles (A, r3) and (O4, r4); ``side`` +1: left of A → O4 (φ12 = θ4 − θ3 > 0)."""
    d = np.abs(O4 - A)
    x = (r3**2 - r4**2 + d**2) / (2 * d)
    h2 = r3**2 - x**2
    u = (O4 - A) / d
    B = A + u * (x + 1j * side * np.sqrt(np.maximum(h2, 0.0)))
    return B, h2


def side_of(A, O4, B):
    """+1 when B is to the left of A → O4 (φ12 = θ4 − θ3 > 0), −1 to the right."""
    return np.sign(cross(O4 - A, B - A))


def drive(O2, O4, r2, r3, r4, psi, side):
    """Move the crank O2A through the global angles ``psi``: A, B and the smallest h²/r3²."""
    A = O2 + r2 * np.exp(1j * psi)
    B, h2 = pin_B(O2, O4, A, r3, r4, side)
    return A, B, h2 / r3**2


def can_carry(s, O2, O4, a, b, direction):
    """Turning the crank one way from position 1, does the coupler meet the positions in order?

    Returns True / False, or None when the path grazes a toggle (inconclusive).
    """
    r2, r3, r4 = abs(a[0] - O2), abs(b[0] - a[0]), abs(b[0] - O4)
    psi = np.angle(a - O2)
    travel = np.mod(direction * (psi - psi[0]), TWO_PI)
    travel[0] = 0.0
    if np.any(np.diff(travel) <= 0):
        return False  # the crank would meet them out of order turning this way
    side = side_of(a[0], O4, b[0])
    path = psi[0] + direction * np.linspace(0.0, travel[-1], 4000)
    _, _, h2 = drive(O2, O4, r2, r3, r4, path, side)
    if h2.min() < -1e-6:
        return False  # not assembled somewhere between: the crank cannot get there
    if h2.min() < 1e-6:
        return None
    _, B, _ = drive(O2, O4, r2, r3, r4, psi[0] + direction * travel, side)
    return bool(np.all(np.abs(B - b) < 1e-7 * (1 + np.abs(b).max())))


def random_positions(rng, n):
    """n positions of a coupler line CD (length 1–3) drawn at random."""
    L = rng.uniform(1.0, 3.0)
    c = rng.uniform(-3, 3, n) + 1j * rng.uniform(-3, 3, n)
    d = c + L * np.exp(1j * rng.uniform(-np.pi, np.pi, n))
    return c, d


def positions_of_a_fourbar(rng):
    """Three coupler positions that a real crank-rocker reaches turning CCW (solvable)."""
    while True:
        r2, r3, r4, r1 = 1.0, rng.uniform(2.5, 4), rng.uniform(2, 4), rng.uniform(2.5, 4)
        lengths = sorted([r1, r2, r3, r4])
        if lengths[0] == r2 and lengths[0] + lengths[3] < lengths[1] + lengths[2] - 0.3:
            break
    O2, O4 = 0j, r1 + 0j
    psi = np.sort(rng.uniform(0, TWO_PI, 3))
    if np.min(np.diff(psi)) < 0.3:
        psi = np.array([0.3, 1.9, 4.0])
    A, B, _ = drive(O2, O4, r2, r3, r4, psi, 1.0)
    P = complex(rng.uniform(-1, 2), rng.uniform(0.5, 2))  # coupler points in the coupler frame
    Q = P + 1.5 * np.exp(1j * rng.uniform(-np.pi, np.pi))
    e = (B - A) / abs(B[0] - A[0])
    positions_of_a_fourbar.pivots = (A[0], B[0], r1)  # the linkage that made them
    return A + e * P, A + e * Q


def check_rigid(s, c, d):
    """A_k, B_k ride on the coupler line, O2/O4 are the centres of their circles."""
    e = (d - c) / (d[0] - c[0])
    assert np.allclose(s.A, c + e * (s.A[0] - c[0]), atol=1e-9)
    assert np.allclose(s.B, c + e * (s.B[0] - c[0]), atol=1e-9)
    assert np.allclose(np.abs(s.A - s.O2), s.r2, rtol=1e-9)
    assert np.allclose(np.abs(s.B - s.O4), s.r4, rtol=1e-9)
    assert np.allclose(np.abs(s.B - s.A), s.r3, rtol=1e-9)
    assert abs(abs(s.O4 - s.O2) - s.r1) < 1e-9 * s.r1


def check_claim(s):
    """ok ⇔ the crank, turning one way, carries the coupler through the positions in order."""
    verdicts = {dr: can_carry(s, s.O2, s.O4, s.A, s.B, dr) for dr in (1, -1)}
    if None in verdicts.values():
        return "inconclusive"
    if s.ok:
        assert s.direction in (1, -1)
        assert verdicts[s.direction], f"said ok turning {s.direction}, but it cannot: {s}"
        return "ok"
    assert not any(verdicts.values()), f"defects {s.defects}, but direction(s) {verdicts} work"
    return "defect"


@pytest.mark.parametrize("seed", range(40))
def test_three_position_random_lines_do_what_they_claim(seed):
    rng = np.random.default_rng(1000 + seed)
    c, d = positions_of_a_fourbar(rng) if seed % 2 else random_positions(rng, 3)
    A = B = None
    if seed % 4 == 1:  # moving pivots elsewhere on the coupler
        A, B = c[0] + rng.uniform(-1, 1) + 1j, d[0] - 1j * rng.uniform(0.5, 1.5)
    try:
        s = three_position(c, d, A=A, B=B)
    except (InputError, AssemblyError):
        return  # collinear pivots / coincident fixed pivots: a refusal, not a wrong answer
    check_rigid(s, c, d)
    check_claim(s)


@pytest.mark.parametrize("seed", range(30))
def test_three_position_fixed_pivots_random(seed):
    rng = np.random.default_rng(2000 + seed)
    c, d = positions_of_a_fourbar(rng)
    O2 = complex(rng.uniform(-4, 4), rng.uniform(-4, 4))
    O4 = O2 + rng.uniform(2, 5) * np.exp(1j * rng.uniform(-np.pi, np.pi))
    try:
        s = three_position_fixed_pivots(c, d, O2, O4, reference=int(seed % 3))
    except (InputError, AssemblyError):
        return
    assert abs(s.O2 - O2) < 1e-9 and abs(s.O4 - O4) < 1e-9
    check_rigid(s, c, d)
    check_claim(s)


@pytest.mark.parametrize("seed", range(12))
def test_three_position_recovers_the_crank_rocker_that_made_the_positions(seed):
    """Positions of a real crank-rocker turning CCW, its pins as the moving pivots:
    the bisectors give back its pivots (O2 = 0, O4 = r1) and it must be ok, CCW."""
    rng = np.random.default_rng(5000 + seed)
    c, d = positions_of_a_fourbar(rng)
    A1, B1, r1 = positions_of_a_fourbar.pivots
    s = three_position(c, d, A=A1, B=B1)
    assert abs(s.O2) < 1e-9 and abs(s.O4 - r1) < 1e-9
    assert s.ok, s.defects
    assert s.direction == 1
    assert check_claim(s) == "ok"


def test_three_position_claims_cover_both_verdicts():
    """The random cases above exercise both ok and defective results (not only refusals)."""
    seen = set()
    for seed in range(40):
        rng = np.random.default_rng(1000 + seed)
        c, d = positions_of_a_fourbar(rng) if seed % 2 else random_positions(rng, 3)
        try:
            seen.add(check_claim(three_position(c, d)))
        except (InputError, AssemblyError):
            seen.add("refused")
    assert {"ok", "defect"} <= seen


@pytest.mark.parametrize("seed", range(20))
def test_two_position_pivots_on_the_bisectors(seed):
    rng = np.random.default_rng(3000 + seed)
    c, d = random_positions(rng, 2)
    s2, s4 = rng.uniform(-5, 5, 2)
    try:
        s = two_position(c, d, s2=s2, s4=s4)
    except (InputError, AssemblyError):
        return
    check_rigid(s, c, d)
    # O2 is s2 from the midpoint of A1A2 along the bisector, to the left of A1 → A2
    mid, n = 0.5 * (c[0] + c[1]), 1j * (c[1] - c[0]) / abs(c[1] - c[0])
    assert abs(s.O2 - (mid + s2 * n)) < 1e-9 * (1 + abs(mid) + abs(s2))
    check_claim(s)


# ---------------------------------------------------------------------------
# Freudenstein function generation
# ---------------------------------------------------------------------------

FUNCTIONS = [
    ("log10", np.log10, (1.0, 2.0)),
    ("square", np.square, (0.0, 1.0)),
    ("exp", np.exp, (0.0, 1.0)),
    ("sin", np.sin, (0.0, np.pi / 2)),
    ("inverse", np.reciprocal, (1.0, 2.0)),
    ("sqrt", np.sqrt, (1.0, 4.0)),
]


@pytest.mark.parametrize("seed", range(36))
def test_function_generator_meets_its_precision_points(seed):
    rng = np.random.default_rng(4000 + seed)
    _, func, xr = FUNCTIONS[seed % len(FUNCTIONS)]
    t2 = rng.uniform(-np.pi, np.pi)
    t4 = rng.uniform(-np.pi, np.pi)
    th2r = (t2, t2 + rng.choice([-1, 1]) * rng.uniform(0.6, 1.6))
    th4r = (t4, t4 + rng.choice([-1, 1]) * rng.uniform(0.6, 1.6))
    r1 = rng.uniform(0.5, 3.0)
    try:
        g = function_generator(func, xr, th2r, th4r, n=3, r1=r1)
    except AssemblyError:
        return
    # Freudenstein's K from the lengths (Norton Eq. 5.25), with the signs the offsets carry
    a = g.r2 * (-1 if g.input_offset else 1)
    c = g.r4 * (-1 if g.output_offset else 1)
    d, b = g.r1, g.r3
    assert d == pytest.approx(r1)
    K = np.array([d / a, d / c, (a * a - b * b + c * c + d * d) / (2 * a * c)])
    assert np.allclose(g.k, K, rtol=1e-9)
    # the linkage moved here: O2 = 0, O4 = d on +x, crank at θ2 + offset
    x = np.linspace(*xr, 301)
    x = np.sort(np.concatenate([x, g.x_precision]))
    th2 = th2r[0] + (x - xr[0]) / (xr[1] - xr[0]) * (th2r[1] - th2r[0])
    y0, yf = func(np.array(xr, float))
    want4 = th4r[0] + (func(x) - y0) / (yf - y0) * (th4r[1] - th4r[0])
    A = g.r2 * np.exp(1j * (th2 + g.input_offset))
    B, h2 = pin_B(0j, d, A, g.r3, g.r4, g.branch)
    th4 = np.angle(B - d) - g.output_offset
    err = np.angle(np.exp(1j * (th4 - want4)))
    at_p = np.isin(x, g.x_precision)
    if g.ok:
        assert np.all(h2 > 0), "said ok, but the linkage cannot be assembled over the range"
        assert np.abs(err[at_p]).max() < 1e-8, "said ok, but misses a precision point"
        # the structural error it reports is the one moved here (in y units)
        se = g.structural_error(x=x)
        y_gen = y0 + (want4 + err - th4r[0]) / (th4r[1] - th4r[0]) * (yf - y0)
        assert np.allclose(se.y_generated, y_gen, rtol=1e-7, atol=1e-9 * abs(yf - y0))
    else:
        # a defect must be real: off a precision point on this branch, or not assembled
        B_other, _ = pin_B(0j, d, A, g.r3, g.r4, -g.branch)
        err_other = np.angle(np.exp(1j * (np.angle(B_other - d) - g.output_offset - want4)))
        missed = np.abs(err[at_p]).max() > 1e-6 and np.abs(err_other[at_p]).max() > 1e-6
        assert missed or np.any(h2 <= 0), g.defects


# ---------------------------------------------------------------------------
# Quick return
# ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("swing_deg", "tr", "r4"),
    [
        (45, 1.25, 2.0),
        (30, 1.1, 1.0),
        (60, 1.4, 3.0),
        (80, 1.2, 0.5),
        (20, 1.5, 1.0),
        (50, 1.0, 1.0),
    ],
)
def test_quick_return_swing_and_time_ratio_by_moving_it(swing_deg, tr, r4):
    qr = quick_return(np.radians(swing_deg), tr, r4=r4)
    fb = qr.linkage
    O2, O4 = fb.O2, 0j
    r1, r2, r3, r4_ = (float(v) for v in fb.fourbar.lengths)
    assert r4_ == pytest.approx(r4)
    assert abs(abs(O2 - O4) - r1) < 1e-9 * r1
    # Grashof crank-rocker with the crank shortest (Barker GCRR)
    s, l_ = min(r1, r2, r3, r4_), max(r1, r2, r3, r4_)
    assert r2 == s and s + l_ < r1 + r2 + r3 + r4_ - s - l_
    # turn the crank a whole turn (CCW) on the drawn circuit from the drawn pose
    psi0 = float(np.angle(qr.B1 - O2))  # extended toggle: A on O2 → B1
    A0 = O2 + r2 * np.exp(1j * psi0)
    side = side_of(A0, O4, qr.B1)
    psi = psi0 + np.linspace(0.0, TWO_PI, 200001)
    _, B, h2 = drive(O2, O4, r2, r3, r4_, psi, side)
    assert h2.min() > 0
    beta = np.unwrap(np.angle(B - O4))
    assert np.degrees(beta.max() - beta.min()) == pytest.approx(swing_deg, abs=1e-3)
    # crank angles of the two extremes: the slow stroke over the quick one
    i, j = int(np.argmax(beta)), int(np.argmin(beta))
    one = abs(psi[i] - psi[j])
    ratio = max(one, TWO_PI - one) / min(one, TWO_PI - one)
    assert ratio == pytest.approx(tr, abs=2e-4)
    # the extremes are the toggles B1 (extended), B2 (folded)
    ends = {complex(np.round(B[i], 4)), complex(np.round(B[j], 4))}
    assert ends == {complex(np.round(qr.B1, 4)), complex(np.round(qr.B2, 4))}
    # and the minimum transmission angle it reports is the one met along the turn
    A = O2 + r2 * np.exp(1j * psi)
    cos_mu = np.real(np.conj(B - A) * (B - O4)) / (r3 * r4_)
    mu = np.arccos(np.abs(np.clip(cos_mu, -1, 1)))
    assert qr.mu_min == pytest.approx(mu.min(), abs=1e-4)


@pytest.mark.parametrize("seed", range(10))
def test_rotopole_link_carries_the_line_by_its_rotation(seed):
    rng = np.random.default_rng(8000 + seed)
    c, d = random_positions(rng, 2)
    link = rotopole_link(c, d)
    turn = np.exp(1j * link.rotation)
    for p1, p2 in ((c[0], c[1]), (d[0], d[1])):
        assert abs(link.pole + turn * (p1 - link.pole) - p2) < 1e-9 * (1 + abs(p2))


@pytest.mark.parametrize("seed", range(10))
def test_driving_dyad_swings_the_rocker_between_b1_and_b2_in_equal_times(seed):
    """Turn the crank a whole turn with the solve written here: the rocker's extremes are
    b1 and b2, half a turn of the crank apart (time ratio 1, Norton §3.4)."""
    rng = np.random.default_rng(9000 + seed)
    pivot = complex(*rng.uniform(-2, 2, 2))
    r4 = rng.uniform(1, 3)
    a1 = rng.uniform(-np.pi, np.pi)
    swing = rng.uniform(0.3, 1.2) * rng.choice([-1, 1])
    b1, b2 = pivot + r4 * np.exp(1j * a1), pivot + r4 * np.exp(1j * (a1 + swing))
    try:
        dy = driving_dyad(pivot, b1, b2, distance=rng.uniform(1.5, 4) * r4)
    except InputError:
        return
    assert dy.swing == pytest.approx(abs(swing), rel=1e-9)
    O6, r2, r3 = dy.crank_pivot, dy.crank, dy.coupler
    A0 = O6 + r2 * (O6 - b1) / abs(O6 - b1)  # the folded toggle: the pin at b1
    side = side_of(A0, pivot, b1) or 1.0
    psi0 = np.angle(A0 - O6)
    psi = psi0 + np.linspace(0, 2 * np.pi, 100001)
    _, B, h2 = drive(O6, pivot, r2, r3, r4, psi, side)
    assert h2.min() > 0
    beta = np.unwrap(np.angle(B - pivot))
    i, j = int(np.argmax(beta)), int(np.argmin(beta))
    assert beta[i] - beta[j] == pytest.approx(abs(swing), abs=1e-6)
    assert {complex(np.round(B[i], 5)), complex(np.round(B[j], 5))} == {
        complex(np.round(b1, 5)),
        complex(np.round(b2, 5)),
    }
    assert abs(abs(psi[i] - psi[j]) - np.pi) < 1e-3  # equal strokes
