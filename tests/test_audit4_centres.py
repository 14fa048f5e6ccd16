"""Audit 4: instant centres → angular velocity ratios and mechanical advantage.

The centres' answers (``InstantCentres.omega_ratio``, ``.mechanical_advantage``,
``SliderCrank.mechanical_advantage(method="instant_centres")``,
``InvertedSliderCrank.instant_centres``) are checked against

* finite differences of *positions only* (five-point central differences in the
  input angle, step 1e-3 rad: truncation ~h⁴·|θ⁽⁵⁾| ≈ 1e-12 of the scale, far
  below the 1e-7 tolerance), never the velocity solution the centres may use;
* the power balance ``T_in ω_in + T_out ω_out = 0`` (``T_in ω_in = F_out v_out``
  for a slider) of the Newton–Euler forces of a massless linkage
  (``Linkage.forces``), a third path;
* Kennedy's rule for a Watt six-bar and a six-bar with a slider output whose
  every centre is compared pair by pair with the point of zero relative velocity
  computed here from differenced positions.
"""

from __future__ import annotations

from itertools import combinations

import numpy as np
import pytest

from closed_forms import circle_meet
from machdyn import InvertedSliderCrank, SliderCrank
from machdyn.centres import collinearity
from machdyn.linkage import Linkage

H = 1e-3
K = np.arange(-2, 3)


def d_dx(z):
    """Five-point central difference along the last axis (samples −2h … 2h)."""
    return (z[..., 0] - 8 * z[..., 1] + 8 * z[..., 3] - z[..., 4]) / (12 * H)


def watt_six_bar(rng):
    """Watt I: four-bar O2-A-B-O4, ternary coupler (A, B, C), ternary rocker (O4, B, D),
    dyad C-E-D closing the second loop."""
    while True:
        lk = _watt(rng)
        if lk is not None:
            return lk


def _watt(rng):
    with np.errstate(invalid="ignore"):
        return _watt_drawn(rng)


def _watt_drawn(rng):
    A = rng.uniform(1.5, 2.5) * np.exp(1j * rng.uniform(0.3, 1.2))
    O4 = complex(rng.uniform(6, 8), rng.uniform(-0.5, 0.5))
    B = circle_meet(A, rng.uniform(6, 7), O4, rng.uniform(4, 5), 1.0)
    C = A + (B - A) * complex(0.5, rng.uniform(0.4, 0.8))
    D = O4 + (B - O4) * complex(0.6, rng.uniform(-0.6, -0.3))
    E = circle_meet(C, rng.uniform(4, 5), D, rng.uniform(3, 4), 1.0)
    if not (np.isfinite(B) and np.isfinite(E)):
        return None
    pts = {"O2": 0j, "O4": O4, "A": A, "B": B, "C": C, "D": D, "E": E}
    lk = Linkage(pts).ground("O2", "O4")
    lk.link("crank", "O2", "A").link("coupler", "A", "B", "C").link("rocker", "O4", "B", "D")
    lk.link("link5", "C", "E").link("link6", "D", "E")
    return lk.drive("crank")


def slider_six_bar(rng):
    """Four-bar O2-A-B-O4 whose rocker (O4, B, D) drives a rod D-E and a block E
    sliding on the ground along a line of random direction."""
    A = rng.uniform(1.5, 2.5) * np.exp(1j * rng.uniform(0.3, 1.2))
    O4 = complex(rng.uniform(6, 8), rng.uniform(-0.5, 0.5))
    B = circle_meet(A, rng.uniform(6, 7), O4, rng.uniform(4, 5), 1.0)
    D = O4 + (B - O4) * complex(0.5, rng.uniform(-0.3, 0.3))
    E = D + rng.uniform(4, 6) * np.exp(1j * rng.uniform(-0.5, 0.5))
    u = np.exp(1j * rng.uniform(-0.8, 0.8))
    pts = {"O2": 0j, "O4": O4, "A": A, "B": B, "D": D, "E": E, "E2": E + u}
    lk = Linkage(pts).ground("O2", "O4")
    lk.link("crank", "O2", "A").link("coupler", "A", "B").link("rocker", "O4", "B", "D")
    lk.link("rod", "D", "E").link("block", "E", "E2")
    return lk.slider("block", "ground", "E", "E2", name="guide").drive("crank")


def solve_stencil(lk, n, rng):
    """Drawn-circuit samples θ0 near the drawing and the stencil θ0 + k h."""
    drawn = float(np.angle(lk.points["A"]))
    theta0 = drawn + rng.uniform(-0.35, 0.35, n)
    th = (theta0[:, None] + H * K[None, :]).ravel()
    pos = lk.solve(th)
    ok = pos.ok.reshape(-1, 5).all(axis=1)
    assert ok.sum() >= n // 2
    return theta0[ok], pos, ok


def stencil(values, ok):
    return np.asarray(values).reshape(-1, 5)[ok]


@pytest.mark.parametrize("build", [watt_six_bar, slider_six_bar])
@pytest.mark.parametrize("seed", range(3))
def test_omega_ratios_and_centres_from_differenced_positions(build, seed):
    rng = np.random.default_rng(7000 + seed)
    lk = build(rng)
    theta0, pos, ok = solve_stencil(lk, 12, rng)
    ics = lk.instant_centres(theta0)
    assert ics.valid.all()
    # ω_k / ω_crank from the positions alone
    rate = {"ground": np.zeros(theta0.size)}
    for link in lk.links:
        rate[link] = d_dx(np.unwrap(stencil(pos.theta[link], ok), axis=1))
    np.testing.assert_allclose(rate["crank"], 1.0, atol=1e-10)
    for link in lk.links:
        if link == "crank" or link == "block":
            continue
        got = ics.omega_ratio("crank", link)
        np.testing.assert_allclose(got, rate[link], rtol=1e-7, atol=1e-9, err_msg=link)
    # every centre: the point with the same velocity on both bodies (differenced)
    vel = {"ground": (np.zeros(theta0.size, complex), np.zeros(theta0.size, complex))}
    for link, spec in lk.links.items():
        p = spec.points[0]
        z = stencil(pos.points[p], ok)
        vel[link] = (z[:, 2], d_dx(z))  # a point of the link and its velocity per unit ω2
    bodies = ["ground", *lk.links]
    scale = max(abs(z) for z in lk.points.values())
    for a, b in combinations(bodies, 2):
        (Ra, Va), (Rb, Vb) = vel[a], vel[b]
        wa, wb = rate[a], rate[b]
        # V_a + j ω_a (P − R_a) = V_b + j ω_b (P − R_b): P j (ω_a − ω_b) = rhs
        rhs = Vb - Va + 1j * (wa * Ra - wb * Rb)
        h = np.stack([(-1j * rhs).real / scale, (-1j * rhs).imag / scale, wa - wb], axis=-1)
        h /= np.linalg.norm(h, axis=-1, keepdims=True)
        got = ics[a, b].homogeneous * np.array([1 / scale, 1 / scale, 1.0])
        got /= np.linalg.norm(got, axis=-1, keepdims=True)
        err = np.minimum(np.linalg.norm(h - got, axis=-1), np.linalg.norm(h + got, axis=-1))
        assert err.max() < 1e-7, (a, b, err.max())
    for a, b, c in combinations(bodies, 3):  # Kennedy
        res = collinearity(ics[a, b].homogeneous, ics[b, c].homogeneous, ics[a, c].homogeneous)
        assert np.abs(res).max() < 1e-9, (a, b, c)


@pytest.mark.parametrize("seed", range(3))
def test_mechanical_advantage_by_power_balance_of_the_newton_euler_forces(seed):
    """Massless six-bars, quasi-static (ω2 → 0 is the same balance: no inertia):
    a load on the output, the driving torque from ``Linkage.forces``; then
    ``T_in ω_in + T_out ω_out = 0`` and the centres' MA = F_out r_out ... /(T_in/r_in)."""
    rng = np.random.default_rng(7100 + seed)
    r_in, r_out = 0.7, 1.9
    # rotating output (Watt: link6), a torque load
    lk = watt_six_bar(rng)
    theta0, pos, ok = solve_stencil(lk, 10, rng)
    ratio = d_dx(np.unwrap(stencil(pos.theta["link6"], ok), axis=1))  # ω6 / ω2
    T_out = 5.0
    m = lk.solve(theta0, velocity=1.0)
    f = lk.forces(m, external_torques={"link6": T_out})
    T_in = f.driver["crank"]
    np.testing.assert_allclose(T_in * 1.0 + T_out * ratio, 0.0, atol=1e-8 * abs(T_out))
    ma = lk.instant_centres(theta0).mechanical_advantage("crank", "link6", r_in, r_out)
    # F_in = T_in / r_in drives F_out = T_out / r_out: MA = F_out / F_in (signed as ω_in/ω_out)
    np.testing.assert_allclose(np.abs(ma), np.abs((T_out / r_out) / (T_in / r_in)), rtol=1e-7)
    np.testing.assert_allclose(ma, (r_in / r_out) / ratio, rtol=1e-7)
    # sliding output: a force F along the guide on the block
    lk = slider_six_bar(rng)
    theta0, pos, ok = solve_stencil(lk, 10, rng)
    v_block = d_dx(stencil(pos.points["E"], ok))  # per unit ω2
    u = lk.points["E2"] - lk.points["E"]
    u /= abs(u)
    F = -8.0 * u  # resisting along the guide
    m = lk.solve(theta0, velocity=1.0)
    f = lk.forces(m, external_forces=[("block", "E", F)])
    T_in = f.driver["crank"]
    power_out = (np.conj(F) * v_block).real
    np.testing.assert_allclose(T_in + power_out, 0.0, atol=1e-8 * abs(F) * abs(v_block).max())
    ma = lk.instant_centres(theta0).mechanical_advantage("crank", "block", r_in)
    np.testing.assert_allclose(ma, r_in / np.abs(v_block), rtol=1e-7)
    np.testing.assert_allclose(ma, abs(F) / np.abs(T_in / r_in), rtol=1e-7)


@pytest.mark.parametrize("form", [1, 2])
def test_slidercrank_mechanical_advantage_both_methods_by_differenced_positions(form):
    rng = np.random.default_rng(7200 + form)
    for _ in range(10):
        a, b = rng.uniform(0.5, 2), rng.uniform(3, 7)
        c = rng.uniform(-0.7, 0.7) * (b - a)
        sc = SliderCrank(a, b, c)
        t0 = rng.uniform(0, 2 * np.pi, 20)
        th = (t0[:, None] + H * K[None, :]).ravel()
        pos = sc.solve(th, form=form)
        ok = pos.ok.reshape(-1, 5).all(axis=1)
        d_prime = d_dx(np.asarray(pos.d).reshape(-1, 5))[ok]  # ḋ per unit ω2
        keep = np.abs(d_prime) > 1e-2 * a  # away from the dead centres
        r_in = rng.uniform(0.5, 2)
        for method in ("power", "instant_centres"):
            ma = np.asarray(sc.mechanical_advantage(t0[ok], r_in, form=form, method=method))
            np.testing.assert_allclose(
                np.abs(ma[keep]), r_in / np.abs(d_prime[keep]), rtol=1e-7, err_msg=method
            )
        ics = sc.instant_centres(t0[ok], form=form)
        # ω3 / ω2 from the centres against the differenced rod angle
        w3 = d_dx(np.unwrap(np.asarray(pos.theta3).reshape(-1, 5), axis=1))[ok]
        np.testing.assert_allclose(ics.omega_ratio(2, 3), w3, rtol=1e-7, atol=1e-9)
        # I24 moves with the slider: ḋ = −ω2 Im(I24) for a horizontal slide (notes)
        I24 = ics[2, 4].point
        np.testing.assert_allclose(-I24.imag, d_prime, rtol=1e-7, atol=1e-9 * a)


@pytest.mark.parametrize("form", [1, 2])
def test_inverted_slidercrank_centres_give_the_differenced_rates(form):
    rng = np.random.default_rng(7300 + form)
    for _ in range(10):
        a, d = rng.uniform(0.5, 4, 2)
        c = rng.uniform(-0.6, 0.6) * min(a, d)
        isc = InvertedSliderCrank(a, d, c)
        t0 = rng.uniform(0, 2 * np.pi, 20)
        th = (t0[:, None] + H * K[None, :]).ravel()
        pos = isc.solve(th, form=form)
        ok = pos.ok.reshape(-1, 5).all(axis=1)
        b = np.asarray(pos.b).reshape(-1, 5)
        ok &= np.abs(b[:, 2]) > 0.2 * max(a, d)
        w4 = d_dx(np.unwrap(np.asarray(pos.theta4).reshape(-1, 5), axis=1))[ok]
        ics = isc.instant_centres(t0[ok], form=form)
        np.testing.assert_allclose(ics.omega_ratio(2, 4), w4, rtol=1e-7, atol=1e-9)
        np.testing.assert_allclose(
            ics.omega_ratio(2, 3), w4, rtol=1e-7, atol=1e-9
        )  # block turns with 4
        for i, j, k in combinations(range(1, 5), 3):
            res = collinearity(ics[i, j].homogeneous, ics[j, k].homogeneous, ics[i, k].homogeneous)
            assert np.abs(res).max() < 1e-9, (i, j, k)
        r_in, r_out = 1.3, 0.4
        ma = ics.mechanical_advantage(2, 4, r_in, r_out)
        np.testing.assert_allclose(ma, (r_in / r_out) / w4, rtol=1e-7)


def test_fourbar_centrodes_by_line_meets_and_rolling_without_slip():
    """Centrodes of the coupler (3) on the ground (Norton §6.5): the fixed one is the
    locus of I13 = O2A ∩ O4B, the moving one the same points in the coupler's frame
    (origin A, x toward B); rolling without slip, equal arcs pass the contact on both."""
    from machdyn import FourBar
    from machdyn.centrodes import centrodes

    r1, r2, r3, r4 = 8.0, 4.0, 7.0, 6.0
    fb = FourBar(r1, r2, r3, r4)
    theta2 = np.radians(np.linspace(40, 120, 4001))
    c = centrodes(fb, theta2, 3)
    A = r2 * np.exp(1j * theta2)
    d = np.abs(r1 - A)
    x = (r3**2 - r4**2 + d**2) / (2 * d)
    B = A + (r1 - A) / d * (x + 1j * np.sqrt(r3**2 - x**2))
    assert np.abs(fb.solve(theta2).B - B).max() < 1e-12
    u, v = A, B - r1  # directions of O2A and O4B
    s = ((r1 - 0) * np.conj(v)).imag / (u * np.conj(v)).imag
    I13 = s * u
    assert c.ok.all()
    np.testing.assert_allclose(c.fixed, I13, atol=1e-9 * r1)
    e3 = (B - A) / r3
    np.testing.assert_allclose(c.moving, (I13 - A) / e3, atol=1e-9 * r1)
    # equal arc lengths (the rolling condition), to the polygon's O(h²) error
    arc_fixed = np.abs(np.diff(c.fixed)).sum()
    arc_moving = np.abs(np.diff(c.moving)).sum()
    assert arc_moving == pytest.approx(arc_fixed, rel=1e-6)
    # the moving frame: rotation θ3 and origin A in the ground frame
    np.testing.assert_allclose(np.exp(1j * c.angle), e3, atol=1e-12)
    np.testing.assert_allclose(c.origin, A, atol=1e-12)
