"""Audit 4: shaking force and moment, counterweights and a flywheel from a machine file.

* Shaking loads (Norton eq. 11.15, with gravity): the moving links press on the
  frame with ``Fs = Σ m (g − a_G)`` and, about the origin,
  ``Ms = Σ [r_G × m (g − a_G) − I_G α]`` — summed here link by link with ``a_G``
  and ``α`` from five-point time differences of the *positions* (input driven
  along ``θ0 + ω t + α t²/2``, step 1e-3 s: truncation ~h⁴ ≈ 1e-12 of the scale)
  — for a drawn Watt six-bar (``Linkage.forces``) and an inverted slider-crank
  (``inverted_slidercrank_dynamics``).
* Complete force balance (Berkof–Lowen, Norton §12.4) of random Watt II six-bars
  by ``linkage_counterweights``: the total centre of mass, summed here from the
  balanced links' positions, stays put over a whole turn, and the shaking force
  is zero to round-off at every angle.
* The press of docs/examples/press.toml through ``machdyn run --json``: the
  flywheel's T_avg and ΔE by this file's own quadrature of the four-bar's printed
  T12 column, I = ΔE/(k ω²) and the disc (I = ½ρπ t r⁴) converted by hand, and
  ω_min, ω_max by integrating ½I d(ω²)/dθ = T_avg − T12 with the time average
  of ω equal to ω_avg.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from closed_forms import circle_meet
from machdyn import InvertedSliderCrank
from machdyn.cli import main
from machdyn.dynamics_inverted import inverted_slidercrank_dynamics
from machdyn.linkage import Linkage
from machdyn.shaking import linkage_counterweights

EXAMPLES = Path(__file__).resolve().parents[1] / "docs" / "examples"
H = 1e-3
K = np.arange(-2, 3)
G_VEC = -9.81j


def time_derivs(z):
    """Velocity and acceleration at t = 0 from samples at t = −2h … 2h (last axis)."""
    d1 = (z[..., 0] - 8 * z[..., 1] + 8 * z[..., 3] - z[..., 4]) / (12 * H)
    d2 = (-z[..., 0] + 16 * z[..., 1] - 30 * z[..., 2] + 16 * z[..., 3] - z[..., 4]) / (12 * H * H)
    return d1, d2


def watt2(rng, masses=True):
    """Watt II: four-bar O2-A-B-O4 with a ternary rocker (O4, B, C) driving a second
    four-bar O4-C-D-O6; masses and centres of mass (off the link lines) at random."""
    while True:
        A = rng.uniform(1.5, 2.5) * np.exp(1j * rng.uniform(0.3, 1.2))
        O4 = complex(rng.uniform(6, 8), rng.uniform(-0.5, 0.5))
        O6 = O4 + complex(rng.uniform(4, 6), rng.uniform(-1, 1))
        with np.errstate(invalid="ignore"):
            B = circle_meet(A, rng.uniform(6, 7), O4, rng.uniform(4, 5), 1.0)
            C = O4 + (B - O4) * complex(rng.uniform(-0.4, 0.4), rng.uniform(-0.9, -0.5))
            D = circle_meet(C, rng.uniform(5, 7), O6, rng.uniform(3, 5), 1.0)
        if np.isfinite(B) and np.isfinite(D):
            break
    pts = {"O2": 0j, "O4": O4, "O6": O6, "A": A, "B": B, "C": C, "D": D}
    lk = Linkage(pts).ground("O2", "O4", "O6")
    links = {
        "crank": ("O2", "A"),
        "coupler": ("A", "B"),
        "rocker": ("O4", "B", "C"),
        "link5": ("C", "D"),
        "link6": ("O6", "D"),
    }
    for name, p in links.items():
        if masses:
            m, i = rng.uniform(0.5, 3), rng.uniform(0.05, 0.5)
            cg = (rng.uniform(-0.5, 3), rng.uniform(-0.5, 0.5))
            lk.link(name, *p, mass=m, inertia=i, cg=cg)
        else:
            lk.link(name, *p)
    return lk.drive("crank")


def stencil_motion(lk, theta0, w, al):
    """Positions at θ0 + ω t + α t²/2 for t = k h (positions only), shaped (n, 5)."""
    t = H * K
    th = (theta0[:, None] + w * t[None, :] + al * t[None, :] ** 2 / 2).ravel()
    return lk.solve(th)


def test_linkage_shaking_force_and_moment_are_the_sums_over_the_links():
    rng = np.random.default_rng(8000)
    lk = watt2(rng)
    theta0 = float(np.angle(lk.points["A"])) + np.linspace(-0.4, 0.4, 9)
    w, al = 7.0, -3.0
    pos = stencil_motion(lk, theta0, w, al)
    assert pos.ok.all()
    m = lk.solve(theta0, velocity=w, acceleration=al)
    f = lk.forces(m, gravity=9.81)
    Fs = np.zeros(theta0.size, complex)
    Ms = np.zeros(theta0.size)
    for name, link in lk.links.items():
        G = np.asarray(pos.cg[name]).reshape(-1, 5)
        _, aG = time_derivs(G)
        _, alpha = time_derivs(np.unwrap(np.asarray(pos.theta[name]).reshape(-1, 5), axis=1))
        load = link.mass * (G_VEC - aG)
        Fs += load
        Ms += (np.conj(G[:, 2]) * load).imag - link.inertia * alpha
    scale = np.abs(Fs).max()
    np.testing.assert_allclose(f.shaking_force, Fs, atol=1e-7 * scale)
    np.testing.assert_allclose(f.shaking_moment, Ms, atol=1e-7 * scale * 10)


@pytest.mark.parametrize("form", [1, 2])
def test_inverted_slidercrank_shaking_loads_are_the_sums_over_the_links(form):
    rng = np.random.default_rng(8100 + form)
    a, d = 1.5, 4.0
    c = 0.4
    isc = InvertedSliderCrank(a, d, c)
    mass = (1.2, 0.6, 2.5)
    inertia = (0.05, 0.01, 0.4)
    cg = (0.7 + 0.1j, 0.2 - 0.05j, 1.8 + 0.2j)  # frames: O2→A; A along the slot; O4 along
    theta0 = rng.uniform(0, 2 * np.pi, 8)
    w, al = 9.0, 4.0
    t = H * K
    th = theta0[:, None] + w * t + al * t**2 / 2
    pos = isc.solve(th, form=form)
    ok = np.asarray(pos.ok).all(axis=1)
    assert ok.sum() >= 4
    theta0, th = theta0[ok], th[ok]
    pos = isc.solve(th, form=form)
    A = np.asarray(pos.A)
    u = np.exp(1j * np.asarray(pos.theta4))
    G = (
        cg[0] * np.exp(1j * th),
        A + cg[1] * u,
        d + cg[2] * u,
    )
    angles = (th, np.asarray(pos.theta4), np.asarray(pos.theta4))
    f = inverted_slidercrank_dynamics(
        isc, theta0, w, al, form=form, mass=mass, inertia=inertia, cg=cg, gravity=9.81
    )
    Fs = np.zeros(theta0.size, complex)
    Ms = np.zeros(theta0.size)
    for k in range(3):
        _, aG = time_derivs(G[k])
        _, alpha = time_derivs(np.unwrap(angles[k], axis=1))
        load = mass[k] * (G_VEC - aG)
        Fs += load
        Ms += (np.conj(G[k][:, 2]) * load).imag - inertia[k] * alpha
    scale = np.abs(Fs).max()
    np.testing.assert_allclose(f.shaking_force, Fs, atol=1e-7 * scale)
    np.testing.assert_allclose(f.shaking_moment, Ms, atol=1e-6 * scale)


@pytest.mark.parametrize("seed", range(4))
def test_watt_six_bar_complete_balance_leaves_no_shaking_force(seed):
    rng = np.random.default_rng(8200 + seed)
    lk = watt2(rng)
    bal = linkage_counterweights(lk)
    assert bal.method == "complete"
    balanced = bal.apply(lk)
    drawn = float(np.angle(lk.points["A"]))
    theta = drawn + np.linspace(-np.pi, np.pi, 181)
    m = balanced.solve(theta, velocity=10.0, acceleration=2.0)
    ok = m.ok
    assert ok.sum() > 20
    # the total centre of mass, summed here from the balanced links' own cg
    total = sum(balanced.links[k].mass * np.asarray(m.cg[k]) for k in balanced.links)
    mass = sum(balanced.links[k].mass for k in balanced.links)
    size = max(abs(z) for z in lk.points.values())
    assert np.ptp(total[ok].real) / mass < 1e-10 * size
    assert np.ptp(total[ok].imag) / mass < 1e-10 * size
    # the unbalanced linkage does shake; the balanced one not at all (no gravity)
    before = lk.forces(lk.solve(theta, velocity=10.0, acceleration=2.0)).shaking_force
    after = balanced.forces(m).shaking_force
    assert np.nanmax(np.abs(before)) > 1.0
    assert np.max(np.abs(after[ok])) < 1e-9 * np.nanmax(np.abs(before))


def _run_press(capsys):
    assert main(["run", str(EXAMPLES / "press.toml"), "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_press_flywheel_numbers_by_hand(capsys):
    data = _run_press(capsys)
    assert data["units"]["torque"] == "N*m" and data["units"]["angular_velocity"] == "rpm"
    forces = data["parts"]["press"]["tables"]["forces"]
    cols = forces["columns"]
    rows = np.array(
        [[r[cols.index("theta2 [deg]")], r[cols.index("T12 [N*m]")]] for r in forces["rows"]]
    )
    theta, T = np.radians(rows[:, 0]), rows[:, 1]
    assert theta[0] == 0 and theta[-1] == pytest.approx(2 * np.pi)
    fw = data["parts"]["crank"]["summary"]
    # the flywheel takes the press's T12 over the whole turn (not only the table's rows):
    # the press (m, kg, s) at the gear's −360 rpm, its curve checked against the table
    from machdyn import FourBar

    w2 = -1440 * 18 / 72 * 2 * math.pi / 60
    press = dict(mass=(0.0, 2.0, 0.0), inertia=(0.0, 0.006, 0.0), cg=(0j, 0.09 + 0j, 0j),
                 gravity=9.80665, load_torque4=-20.0)  # fmt: skip

    def t12(angles):
        return FourBar(0.2, 0.05, 0.18, 0.12).dynamics(angles, w2, **press).T12

    np.testing.assert_allclose(t12(theta), T, rtol=1e-9, atol=1e-12)
    # T_avg and ΔE of the curve, by a far finer trapezoid here (O(h²): 1e-9 of machdyn's)
    fine = np.linspace(0, 2 * np.pi, 100001)
    t_lin = t12(fine)
    t_avg = np.trapezoid(t_lin, fine) / (2 * np.pi)
    assert fw["T_avg [N*m]"] == pytest.approx(t_avg, abs=1e-9 * np.abs(T).max())
    e = np.concatenate([[0], np.cumsum(0.5 * (t_lin[1:] + t_lin[:-1]) * np.diff(fine))])
    e -= t_avg * fine
    delta_e = e.max() - e.min()
    assert fw["delta_E [N*m]"] == pytest.approx(delta_e, rel=1e-6)
    # I = ΔE / (k ω²): ω = 360 rpm (the reducer's 1440 rpm · 18/72), k = 0.02
    omega = 1440 * 18 / 72 * 2 * math.pi / 60
    inertia = delta_e / (0.02 * omega**2)  # kg·m²
    assert fw["I (flywheel inertia) [kg*mm^2]"] == pytest.approx(inertia * 1e6, rel=1e-6)
    # a steel disc 30 mm thick: I = ½ (ρ π t r²) r²
    r = (2 * inertia / (7850 * math.pi * 0.030)) ** 0.25
    assert fw["disc outer radius [mm]"] == pytest.approx(r * 1e3, rel=1e-6)
    assert fw["disc mass [kg]"] == pytest.approx(7850 * math.pi * r * r * 0.030, rel=1e-6)

    # ω(θ): ½ I (ω² − ω_s²) = −E(θ), ω_s fixed by the time average 2π / ∫dθ/ω = ω_avg
    def time_average(ws):
        wt = np.sqrt(ws**2 - 2 * e / inertia)
        return 2 * np.pi / np.trapezoid(1 / wt, fine)

    lo, hi = omega, 1.1 * omega
    for _ in range(60):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if time_average(mid) < omega else (lo, mid)
    wt = np.sqrt(lo**2 - 2 * e / inertia) * 60 / (2 * math.pi)
    w_min, w_max = fw["omega min, max [rpm]"]
    assert w_min == pytest.approx(wt.min(), rel=1e-6)
    assert w_max == pytest.approx(wt.max(), rel=1e-6)
    k_asked, k_achieved = fw["k (asked, achieved)"]
    assert k_asked == 0.02
    assert k_achieved == pytest.approx((wt.max() - wt.min()) / 360.0, rel=1e-5)


@pytest.mark.parametrize("form", [1, 2])
def test_slidercrank_shaking_loads_are_the_sums_over_the_links(form):
    """Crank (O2 → A), rod (A → B), block at B: Σ m (g − a_G) and its moment about O2
    with −Σ I_G α, from differenced positions written here (A = a e^{jθ2}, B on the
    slide line y = c at distance b from A)."""
    from machdyn import SliderCrank
    from machdyn.dynamics import slidercrank_dynamics

    a, b, c = 1.0, 3.5, 0.3
    sc = SliderCrank(a, b, c)
    mass, inertia, cg = (1.5, 2.0, 1.2), (0.02, 0.2), (0.3 + 0.05j, 1.2 - 0.1j)
    rng = np.random.default_rng(8300 + form)
    theta0 = rng.uniform(0, 2 * np.pi, 10)
    w, al = 30.0, -5.0
    th = theta0[:, None] + w * H * K + al * (H * K) ** 2 / 2
    A = a * np.exp(1j * th)
    x = np.sqrt(b * b - (c - A.imag) ** 2) * (1 if form == 1 else -1)
    B = A.real + x + 1j * c
    assert np.abs(sc.solve(theta0, form=form).B - B[:, 2]).max() < 1e-12  # the same branch
    t3 = np.angle(B - A)
    G = (cg[0] * np.exp(1j * th), A + cg[1] * np.exp(1j * t3), B)
    angles = (th, t3, None)
    f = slidercrank_dynamics(
        sc, theta0, w, al, form=form, mass=mass, inertia=inertia, cg=cg, gravity=9.81
    )
    Fs = np.zeros(theta0.size, complex)
    Ms = np.zeros(theta0.size)
    for k in range(3):
        _, aG = time_derivs(G[k])
        load = mass[k] * (G_VEC - aG)
        Fs += load
        Ms += (np.conj(G[k][:, 2]) * load).imag
        if angles[k] is not None:
            Ms -= inertia[k] * time_derivs(np.unwrap(angles[k], axis=1))[1]
    scale = np.abs(Fs).max()
    np.testing.assert_allclose(f.shaking_force, Fs, atol=1e-7 * scale)
    np.testing.assert_allclose(f.shaking_moment, Ms, atol=1e-6 * scale)
