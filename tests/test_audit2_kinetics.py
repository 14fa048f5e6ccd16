"""Audit 2: mechanical advantage, planetary trains and virtual work by hand.

* Mechanical advantage of a four-bar from its instant centres (the notes, review
  lecture 2, "FOURBAR INSTANT CENTERS": ``ω3 = R2 ω2 / d_A``, ``ω4 = d_B ω3 / R4``,
  ``M.A. = r_in d_A R4 / (r_out d_B R2)``; the wire cutter's ``r_in R4 / (r_out d_B)``),
  with ``I13`` found here as the meet of lines ``O2A`` and ``O4B`` and ``A``, ``B`` by
  two circles — not by machdyn's velocity solution.
* Compound epicyclic trains of random tooth counts: Willis' formula written from
  the chain (Norton §9.9, Eq. 9.13 ``R = (ω_L − ω_A)/(ω_F − ω_A)`` = ± product of
  driver/driven teeth), its torques by ``Σ T = 0`` and ``Σ T ω = 0``.
* ``virtual_work`` against the power of d'Alembert loads on a slider-crank moved
  here in closed form (Norton §11.6 / §10.15).
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from machdyn import FourBar, SliderCrank
from machdyn.errors import AssemblyError
from machdyn.gears import PlanetaryTrain
from machdyn.gears.power import planetary_power
from machdyn.virtual_work import fourbar_mechanical_advantage, virtual_work


def meet(p1, d1, p2, d2):
    """Intersection of lines p1 + s d1 and p2 + t d2 (complex)."""
    s = np.imag(np.conj(d2) * (p2 - p1)) / np.imag(np.conj(d2) * d1)
    return p1 + s * d1


def fourbar_pose(r1, r2, r3, r4, t2, sign):
    """A and B of a four-bar (O2 = 0, O4 = r1) by two circles; sign = sign of φ12."""
    A = r2 * np.exp(1j * t2)
    d = np.abs(r1 - A)
    x = (r3**2 - r4**2 + d**2) / (2 * d)
    h = np.sqrt(r3**2 - x**2)
    B = A + (r1 - A) / d * (x + 1j * sign * h)
    return A, B


@pytest.mark.parametrize("seed", range(25))
def test_mechanical_advantage_from_instant_centres(seed):
    rng = np.random.default_rng(6000 + seed)
    while True:
        r1, r2, r3, r4 = rng.uniform(1, 6, 4)
        fb = FourBar(r1, r2, r3, r4)
        t2 = rng.uniform(-np.pi, np.pi)
        form = int(rng.choice([1, 2]))
        try:
            m = fb.solve(t2, 1.0, form=form)
        except AssemblyError:
            continue
        if abs(np.sin(np.ravel(m.phi12)[0])) > 0.1:
            break
    sign = np.sign(np.sin(np.ravel(m.phi12)[0]))
    A, B = fourbar_pose(r1, r2, r3, r4, t2, sign)
    assert abs(np.ravel(m.B)[0] - B) < 1e-9  # the same assembly
    I13 = meet(0j, A, r1 + 0j, B - r1)
    # v_A = j ω2 A = j ω3 (A − I13);  v_B = j ω3 (B − I13) = j ω4 (B − O4)  (signed)
    w2 = 1.0
    w3 = np.real(w2 * A / (A - I13))
    w4 = np.real(w3 * (B - I13) / (B - r1))
    # torque in on 2, torque out on 4: T4/T2 = ω2/ω4; the notes' magnitudes d_A R4/(d_B R2)
    ma = float(np.ravel(fourbar_mechanical_advantage(fb, t2, 2, 4, form=form))[0])
    assert ma == pytest.approx(w2 / w4, rel=1e-9)
    dA, dB = abs(A - I13), abs(B - I13)
    assert abs(ma) == pytest.approx(dA * r4 / (dB * r2), rel=1e-9)
    # the wire cutter: torque in on the coupler (3), torque out on 4: |M.A.| = R4 / d_B
    ma34 = float(np.ravel(fourbar_mechanical_advantage(fb, t2, 3, 4, form=form))[0])
    assert abs(ma34) == pytest.approx(r4 / dB, rel=1e-9)
    # a force at a coupler point P along u (P in the coupler frame: origin A, x toward B)
    p = complex(*rng.uniform(-2, 3, 2))
    u = np.exp(1j * rng.uniform(-np.pi, np.pi))
    P = A + p * (B - A) / r3
    vP = 1j * w3 * (P - I13)
    ma_f = float(np.ravel(fourbar_mechanical_advantage(fb, t2, 2, (3, p, u), form=form))[0])
    assert ma_f == pytest.approx(w2 / np.real(np.conj(u) * vP), rel=1e-8)


def willis_by_hand(chain):
    """R from the chain: each external mesh −N_prev/N, internal +N_prev/N, shaft 1."""
    R = 1.0
    for (_, n_prev, *_), (_, n, kind) in itertools.pairwise(chain):
        R *= {"external": -n_prev / n, "internal": n_prev / n, "shaft": 1.0}[kind]
    return R


def random_chain(rng):
    chain = [("first", int(rng.integers(12, 60)))]
    for i in range(int(rng.integers(1, 4))):
        kind = ["external", "internal", "shaft"][int(rng.integers(0, 3))] if i else "external"
        chain.append((f"g{i}", int(rng.integers(12, 80)), kind))
    chain.append(
        ("last", int(rng.integers(12, 90)), ["external", "internal"][int(rng.integers(0, 2))])
    )
    return chain


@pytest.mark.parametrize("seed", range(30))
def test_compound_planetary_speeds_by_willis_and_torques_by_power(seed):
    rng = np.random.default_rng(7000 + seed)
    chain = random_chain(rng)
    train = PlanetaryTrain(chain)
    R = willis_by_hand(chain)
    assert train.train_value == pytest.approx(R, rel=1e-12)
    w_arm, w_first = rng.uniform(-500, 500, 2)
    sp = train.speeds(arm=w_arm, first=w_first)
    assert sp["last"] == pytest.approx(w_arm + R * (w_first - w_arm), rel=1e-10, abs=1e-9)
    # every gear: ω_i − ω_arm = R_i (ω_first − ω_arm), R_i the product up to gear i
    for k in range(1, len(chain)):
        Ri = willis_by_hand(chain[: k + 1])
        name = chain[k][0]
        assert sp[name] == pytest.approx(w_arm + Ri * (w_first - w_arm), rel=1e-10, abs=1e-9)
    # given the last and the arm instead: the same speeds
    back = train.speeds(last=sp["last"], arm=w_arm)
    assert back["first"] == pytest.approx(w_first, rel=1e-9, abs=1e-9)
    # ratio with one member fixed: arm fixed → R; first fixed: ω_last/ω_arm = 1 − R
    assert train.ratio("first", "last", fixed="arm") == pytest.approx(R, rel=1e-12)
    assert train.ratio("arm", "last", fixed="first") == pytest.approx(1 - R, rel=1e-12)
    if abs(1 - R) > 1e-9:
        assert train.ratio("first", "arm", fixed="last") == pytest.approx(-R / (1 - R), rel=1e-9)
    # torques: one given, the others from ΣT = 0 (statics of the whole train) and ΣTω = 0
    T = float(rng.uniform(-50, 50))
    for member in ("first", "last", "arm"):
        if member == "arm" and abs(1 - R) < 1e-9:
            continue
        p = planetary_power(train, {"arm": w_arm, "first": w_first}, {member: T})
        assert p[member] == pytest.approx(T)
        total = p["first"] + p["last"] + p["arm"]
        assert abs(total) < 1e-9 * (abs(T) + 1) * max(1.0, abs(R), 1 / abs(R))
        power = p["first"] * sp["first"] + p["last"] * sp["last"] + p["arm"] * sp["arm"]
        scale = (
            abs(p["first"] * sp["first"]) + abs(p["last"] * sp["last"]) + abs(p["arm"] * sp["arm"])
        )
        assert abs(power) <= 1e-9 * (scale + 1)
        for name, *_ in chain[1:-1]:
            assert p[name] == 0.0


def test_virtual_work_with_dalembert_loads_equals_newton_euler_of_a_slider_crank():
    """Virtual work (one power equation) and Newton–Euler (the 8 × 8 system) are two routes
    to T12: the inertia of an offset slider-crank as d'Alembert loads, its kinematics in
    closed form here (loop a e^{jθ2} + b e^{jθ3} = d + j c, Norton §4.6 / §7.3)."""
    a, b, c = 2.0, 7.0, 0.5  # crank, rod, offset
    m2, I2, m3, I3, m4 = 0.7, 0.2, 1.5, 0.8, 3.0
    g, F4 = 9.81, -200.0
    th = np.linspace(0.1, 6.2, 40)
    w2, al2 = 12.0, 3.0
    th3 = np.arcsin((c - a * np.sin(th)) / b)
    w3 = -a * np.cos(th) * w2 / (b * np.cos(th3))
    al3 = (-a * al2 * np.cos(th) + a * w2**2 * np.sin(th) + b * w3**2 * np.sin(th3)) / (
        b * np.cos(th3)
    )
    e2, e3 = np.exp(1j * th), np.exp(1j * th3)
    vA, aA = 1j * w2 * a * e2, (1j * al2 - w2**2) * a * e2
    vB, aB = vA + 1j * w3 * b * e3, aA + (1j * al3 - w3**2) * b * e3
    assert np.abs(vB.imag).max() < 1e-9 and np.abs(aB.imag).max() < 1e-9  # on the slide
    vG2, aG2 = 0.5 * vA, 0.5 * aA  # crank's centre of mass at its middle
    vG3 = vA + 1j * w3 * 0.5 * b * e3  # and the rod's
    aG3 = aA + (1j * al3 - w3**2) * 0.5 * b * e3
    loads = [
        (F4 + 0j, vB),
        (-m2 * aG2 - 1j * m2 * g, vG2),
        (-I2 * al2, w2),
        (-m3 * aG3 - 1j * m3 * g, vG3),
        (-I3 * al3, w3),
        (-m4 * aB - 1j * m4 * g, vB),
    ]
    T_vw = virtual_work(w2, loads)
    sc = SliderCrank(a, b, offset=c)
    m = sc.solve(th, w2, al2)
    assert np.allclose(m.B, a * e2 + b * e3, atol=1e-9)  # the same slider-crank
    f = sc.dynamics(
        th,
        w2,
        al2,
        mass=(m2, m3, m4),
        inertia=(I2, I3),
        cg=(a / 2, b / 2),
        gravity=g,
        load_force4=F4,
    )
    np.testing.assert_allclose(f.T12, T_vw, rtol=1e-9, atol=1e-9 * np.abs(T_vw).max())


@pytest.mark.parametrize("seed", range(12))
def test_slidercrank_counterweight_leaves_the_reciprocating_force(seed):
    """With the counterweight on, −Σ m a_G of crank (+ weight), rod and piston — written here
    from the loop in closed form — is −m_B (B̈ − f Ä): the rotating masses balanced exactly,
    a part f of the reciprocating one traded into y (Norton §13.6–13.7, overbalancing)."""
    from machdyn.shaking import slidercrank_counterweight

    rng = np.random.default_rng(9500 + seed)
    a = rng.uniform(0.5, 2.0)
    b = a * rng.uniform(2.5, 5.0)
    c = rng.uniform(-0.3, 0.3) * a
    m2, m3, m4 = rng.uniform(0.5, 3.0, 3)
    c2 = complex(rng.uniform(-0.5, 1.2) * a, rng.uniform(-0.2, 0.2) * a)
    c3 = complex(rng.uniform(0.2, 0.8) * b, rng.uniform(-0.1, 0.1) * b)
    f = float(rng.choice([0.0, 0.5, 1.0]))
    sc = SliderCrank(a, b, offset=c)
    bal = slidercrank_counterweight(sc, (m2, m3, m4), (c2, c3), fraction=f)
    R = rng.uniform(0.3, 1.0) * a
    mc = abs(bal.mR) / R
    th = np.linspace(0.0, 2 * np.pi, 37)
    w2, al2 = 50.0, 7.0
    th3 = np.arcsin((c - a * np.sin(th)) / b)
    w3 = -a * np.cos(th) * w2 / (b * np.cos(th3))
    al3 = (-a * al2 * np.cos(th) + a * w2**2 * np.sin(th) + b * w3**2 * np.sin(th3)) / (
        b * np.cos(th3)
    )
    e2, e3 = np.exp(1j * th), np.exp(1j * th3)
    aA = (1j * al2 - w2**2) * a * e2
    aB = aA + (1j * al3 - w3**2) * b * e3
    # every body's centre of mass: crank (origin O2, x to A), weight, rod (origin A, x to B)
    a2 = (1j * al2 - w2**2) * c2 * e2
    aw = (1j * al2 - w2**2) * (bal.mR / mc) * e2
    a3 = aA + (1j * al3 - w3**2) * c3 * e3
    Fs = -(m2 * a2 + mc * aw + m3 * a3 + m4 * aB)
    m = sc.solve(th, w2, al2)
    np.testing.assert_allclose(m.d_ddot, aB.real, rtol=1e-9, atol=1e-9 * np.abs(aB).max())
    np.testing.assert_allclose(bal.shaking_force(m), Fs, atol=1e-9 * np.abs(Fs).max())
    mB = m4 + m3 * c3 / b
    np.testing.assert_allclose(Fs, -mB * (aB - f * aA), atol=1e-9 * np.abs(Fs).max())
    if f == 0.0 and c3.imag == 0.0:  # only the piston's line is left shaking
        assert np.abs(Fs.imag).max() < 1e-9 * np.abs(Fs).max()


@pytest.mark.parametrize("seed", range(10))
def test_bearing_balance_cancels_the_bearing_forces_statics_written_here(seed):
    """A rotor with random unbalances U_i = m_i r_i e^{jφ_i} at z_i turning at ω: the bearings
    carry ω² ΣU with moments about the left bearing (statics in the rotating frame, Norton
    §12.2); bearing_balance of those forces must give corrections that leave ΣU = 0 and
    Σ U z = 0 — the balanced rotor loads neither bearing."""
    from machdyn.balancing import bearing_balance

    rng = np.random.default_rng(9900 + seed)
    n = int(rng.integers(1, 5))
    U = rng.uniform(0.01, 0.2, n) * np.exp(1j * rng.uniform(-np.pi, np.pi, n))
    z = rng.uniform(-5, 15, n)
    zL, zR = -10.0, 20.0
    omega = rng.uniform(10, 100)
    FR = omega**2 * np.sum(U * (z - zL)) / (zR - zL)
    FL = omega**2 * np.sum(U) - FR
    za, zb = rng.uniform(-8, 0), rng.uniform(5, 18)
    fix = bearing_balance([FL, FR], [zL, zR], omega, za, zb)
    total = np.sum(U) + fix.mR_a + fix.mR_b
    moment = np.sum(U * z) + fix.mR_a * za + fix.mR_b * zb
    scale = np.sum(np.abs(U)) * (1 + np.abs(z).max())
    assert abs(total) < 1e-12 * scale and abs(moment) < 1e-12 * scale * 20
