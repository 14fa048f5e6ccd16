"""Tests of Linkage.spring and Linkage.torsion_spring: springs and dampers as known loads.

A spring's tension is ``T = k (L - L0) + c dL/dt + preload`` (positive pulling its ends
together), a torsion spring's torque ``tau = kt (phi - phi0) + ct dphi/dt + preload`` with
``phi = theta_b - theta_a`` (``-tau`` on link b). References that do not share the code
path of the force analysis:

* statics of a lid pinned to the ground, by hand: the spring's moment about the pivot,
  ``T r h cos(theta) / L``, and a zero-free-length spring that balances gravity at every
  angle (the counterbalanced lamp: ``k r h = m g a``);
* conservation of power ``T12 omega2 - sum T dL/dt - sum tau dphi/dt = d(KE)/dt + d(PE)/dt``
  on a four-bar with masses (KE, PE, L, dL/dt computed here from the kinematics), with and
  without damping, and a spring's power ``-d/dt(k (L - L0)^2 / 2)`` by finite differences;
* virtual work on a massless four-bar: ``T12 = sum T dL/dtheta2 + sum tau dphi/dtheta2``,
  the derivatives by central finite differences of the solved positions;
* Newton's law for the whole mechanism: the shaking force is ``-sum m (a_G + j g)``
  whatever the springs do (a spring to the ground loads the frame).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

from closed_forms import circle_meet
from machdyn.errors import InputError, ModelError
from machdyn.linkage import FORCE_REASONS, Linkage

# every test on the NumPy path and on the compiled kernels (tests/conftest.py)
pytestmark = pytest.mark.usefixtures("backend")

G = 9.81


# ---------------------------------------------------------------------- statics by hand
R, H = 3.0, 4.0  # lid O2-A of length R; the spring's ground anchor S = (0, H)


def lid(mass: dict | None = None) -> Linkage:
    """A lid pinned to the ground at O2; its gas strut S-A is a free (undriven) actuator,
    which gives the lid its second joint and carries no force."""
    lk = Linkage({"O2": 0j, "A": R + 0j, "S": 1j * H}).ground("O2", "S")
    lk.link("lid", "O2", "A", **(mass or {}))
    return lk.actuator("strut", "S", "A").drive("lid")


def spring_moment(theta, T):
    """Moment about O2 of the tension T of a spring S-A on the lid (by hand)."""
    L = np.sqrt(R**2 + H**2 - 2 * R * H * np.sin(theta))
    return T * R * H * np.cos(theta) / L, L


def test_static_lid_held_by_a_spring_closed_form():
    k, L0, T0 = 250.0, 3.0, 40.0
    theta = np.radians(np.linspace(-80.0, 80.0, 33))
    lk = lid().spring("gas", "S", "A", stiffness=k, free_length=L0, preload=T0)
    m = lk.solve(theta, velocity=0.0)
    f = lk.forces(m)
    assert f.ok.all()
    L = np.sqrt(R**2 + H**2 - 2 * R * H * np.sin(theta))
    T = k * (L - L0) + T0
    M, _ = spring_moment(theta, T)
    # the driver holds the lid: T12 + M = 0 (massless, at rest)
    assert np.allclose(f.driver["lid"], -M, rtol=0, atol=1e-10 * np.abs(M).max())
    assert np.allclose(f.elements["gas"], T, rtol=1e-12)
    assert np.allclose(f.element_length["gas"], L, rtol=1e-12)
    assert np.allclose(f.element_rate["gas"], 0.0, atol=1e-12)
    # the free strut carries nothing: the pin O2 takes the spring's pull on A
    u = (m.points["A"] - m.points["S"]) / L
    assert np.allclose(f.F("ground", "lid"), T * u, atol=1e-10 * abs(T).max())


def test_static_lid_torque_vanishes_where_the_spring_is_free():
    """No gravity, no preload: T12 = 0 where L = L0, i.e. sin(theta) = (R^2 + H^2 - L0^2)/(2RH)."""
    k, L0 = 120.0, 4.5
    lk = lid().spring("gas", "S", "A", stiffness=k, free_length=L0)

    def torque(theta: float) -> float:
        return float(lk.forces(lk.solve([theta], velocity=0.0)).driver["lid"][0])

    root = brentq(torque, np.radians(-60.0), np.radians(60.0), xtol=1e-14)
    expected = np.arcsin((R**2 + H**2 - L0**2) / (2 * R * H))
    assert root == pytest.approx(expected, abs=1e-10)


def test_zero_free_length_spring_balances_gravity_at_every_angle():
    """The counterbalanced lamp: with T = k L (preload = k L0) the spring's moment is
    k R H cos(theta) and gravity's -m g a cos(theta); k R H = m g a balances every pose."""
    m_, a = 2.0, 1.2
    L0 = 1.0
    k = m_ * G * a / (R * H)
    lk = lid(dict(mass=m_, inertia=0.3, cg=a)).spring(
        "lamp", "S", "A", stiffness=k, free_length=L0, preload=k * L0
    )
    theta = np.radians(np.linspace(-85.0, 85.0, 35))
    f = lk.forces(lk.solve(theta, velocity=0.0), gravity=G)
    assert np.abs(f.driver["lid"]).max() <= 1e-12 * m_ * G * a
    # a stiffer spring: T12 = -(k R H - m g a) cos(theta)
    lk2 = lid(dict(mass=m_, inertia=0.3, cg=a)).spring(
        "lamp", "S", "A", stiffness=2 * k, free_length=L0, preload=2 * k * L0
    )
    f2 = lk2.forces(lk2.solve(theta, velocity=0.0), gravity=G)
    assert np.allclose(f2.driver["lid"], -(2 * k * R * H - m_ * G * a) * np.cos(theta), atol=1e-12)


def test_torsion_spring_on_the_lid_against_gravity_closed_form():
    """T12 = kt (theta - theta0) + preload + m g a cos(theta) (the driver holds both)."""
    m_, a, kt, th0, tau0 = 1.5, 1.0, 30.0, 0.4, 2.0
    lk = lid(dict(mass=m_, inertia=0.2, cg=a)).torsion_spring(
        "coil", "O2", stiffness=kt, free_angle=th0, preload=tau0
    )
    theta = np.radians(np.linspace(-170.0, 170.0, 35))
    f = lk.forces(lk.solve(theta, velocity=0.0), gravity=G)
    expected = kt * (theta - th0) + tau0 + m_ * G * a * np.cos(theta)
    assert np.allclose(f.driver["lid"], expected, rtol=0, atol=1e-11 * np.abs(expected).max())
    assert np.allclose(f.elements["coil"], kt * (theta - th0) + tau0, rtol=1e-12)
    assert np.allclose(f.element_length["coil"], theta, rtol=0, atol=1e-12)
    # the frame feels the driver's reaction -T12, the coil's +tau and the pin force at the
    # origin (no moment): -T12 + tau = -m g a cos(theta), gravity's moment about O2
    assert np.allclose(f.shaking_moment, -m_ * G * a * np.cos(theta), rtol=0, atol=1e-11)


# ---------------------------------------------------------------------- a four-bar
def hw6(masses: bool = False) -> Linkage:
    """HW 6 (notes) GCRR 8-4-7-6 drawn at theta2 = 0, B above the ground, with a coupler
    points P and U, a point Q on the rocker and a ground anchor S."""
    A, O4 = 4 + 0j, 8 + 0j
    B = circle_meet(A, 7.0, O4, 6.0)
    pts = {"O2": 0j, "O4": O4, "A": A, "B": B, "P": A + 0.4 * (B - A) + 1.5j}
    pts |= {"Q": O4 + 0.5 * (B - O4) + 0.8, "S": -2.0 + 6.0j, "U": A + 0.7 * (B - A) - 1.0j}
    lk = Linkage(pts).ground("O2", "O4", "S")
    kw = (
        [
            dict(mass=1.0, inertia=0.05, cg=2.0),
            dict(mass=2.5, inertia=0.4, cg="P"),
            dict(mass=1.8, inertia=0.3, cg=3.0),
        ]
        if masses
        else [{}, {}, {}]
    )
    lk.link("2", "O2", "A", **kw[0])
    lk.link("3", "A", "B", "P", "U", **kw[1])
    lk.link("4", "O4", "B", "Q", **kw[2])
    return lk.drive("2")


THETA2 = np.radians(np.arange(0.0, 360.0, 2.0))


def length_and_rate(m, start: str, end: str):
    """A spring's length and dL/dt from the solved points (not the library's springs)."""
    d = m.points[end] - m.points[start]
    L = np.abs(d)
    L_dot = ((m.point_velocity[end] - m.point_velocity[start]) * np.conj(d / L)).real
    return L, L_dot


def kinetic_rates(lk, m):
    dke = np.zeros(len(m))
    dpe = np.zeros(len(m))
    for name, link in lk._links.items():
        v, a = m.cg_velocity[name], m.cg_acceleration[name]
        dke += link.mass * (v.real * a.real + v.imag * a.imag)
        dke += link.inertia * m.omega[name] * m.alpha[name]
        dpe += link.mass * G * v.imag
    return dke, dpe


SPRINGS = {  # name: (start, end, k, L0, c, preload)
    "gas": ("S", "P", 80.0, 5.0, 3.0, -20.0),  # ground to coupler
    "return": ("A", "Q", 150.0, 6.0, 1.5, 10.0),  # crank to rocker
}
TORSIONS = {  # name: (pin, links, kt, phi0, ct, preload)
    "coil": ("O4", ("ground", "4"), 40.0, 1.0, 0.7, 5.0),  # rocker on its ground pivot
    "knee": ("B", ("3", "4"), 25.0, 0.2, 0.4, -3.0),  # coupler-rocker, a moving pin
}


def with_elements(lk: Linkage, damping: bool) -> Linkage:
    for name, (s, e, k, L0, c, T0) in SPRINGS.items():
        lk.spring(
            name, s, e, stiffness=k, free_length=L0, damping=c if damping else 0.0, preload=T0
        )
    for name, (at, links, kt, phi0, ct, tau0) in TORSIONS.items():
        lk.torsion_spring(
            name,
            at,
            stiffness=kt,
            free_angle=phi0,
            damping=ct if damping else 0.0,
            preload=tau0,
            links=links,
        )
    return lk


def efforts(m, damping: bool):
    """Every element's effort and rate, from the kinematics and the laws (by hand)."""
    out = {}
    for name, (s, e, k, L0, c, T0) in SPRINGS.items():
        L, L_dot = length_and_rate(m, s, e)
        out[name] = (k * (L - L0) + (c if damping else 0.0) * L_dot + T0, L, L_dot)
    for name, (_, (a, b), kt, phi0, ct, tau0) in TORSIONS.items():

        def th(n, table):
            return 0.0 if n == "ground" else table[n]

        phi = th(b, m.theta) - th(a, m.theta)
        phi_dot = th(b, m.omega) - th(a, m.omega)
        out[name] = (kt * (phi - phi0) + (ct if damping else 0.0) * phi_dot + tau0, phi, phi_dot)
    return out


@pytest.mark.parametrize("damping", [False, True])
def test_power_balance_fourbar_with_springs_dampers_and_masses(damping):
    """T12 omega2 - sum T L' - sum tau phi' + T4 omega4 = d(KE)/dt + d(PE)/dt at every
    sample, with gravity, a torque on the rocker and a non-uniform omega2."""
    lk = with_elements(hw6(masses=True), damping)
    w2 = 6.0 + 2.0 * np.sin(THETA2)
    a2 = 2.0 * np.cos(THETA2) * w2
    m = lk.solve(THETA2, velocity=w2, acceleration=a2)
    T4 = -7.0
    f = lk.forces(m, gravity=G, external_torques={"4": T4})
    assert f.ok.all()
    dke, dpe = kinetic_rates(lk, m)
    by_hand = efforts(m, damping)
    p_elements = sum(-T * rate for T, _, rate in by_hand.values())
    power = f.driver["2"] * w2 + T4 * m.omega["4"] + p_elements
    scale = np.abs(f.driver["2"] * w2).max() + np.abs(dke).max() + np.abs(p_elements).max()
    assert np.abs(power - dke - dpe).max() <= 1e-8 * scale
    for name, (T, L, rate) in by_hand.items():
        assert np.allclose(f.elements[name], T, rtol=0, atol=1e-10 * np.abs(T).max())
        assert np.allclose(f.element_length[name], L, rtol=0, atol=1e-12 * np.abs(L).max())
        assert np.allclose(f.element_rate[name], rate, rtol=0, atol=1e-10 * np.abs(rate).max())
    # the dampers dissipate: c L'^2 >= 0 is taken out of the mechanism
    if damping:
        loss = sum(
            -(f.elements[n] - (k * (f.element_length[n] - L0) + T0)) * f.element_rate[n]
            for n, (_, _, k, L0, _, T0) in SPRINGS.items()
        )
        assert (loss <= 1e-12).all() and loss.min() < 0


def test_spring_power_is_minus_the_rate_of_its_energy():
    """-T dL/dt = -d/dt (k (L - L0)^2 / 2), the latter by central differences in time
    (theta2 = omega2 t, the positions solved at theta2 +- h)."""
    lk = hw6().spring("gas", "S", "P", stiffness=80.0, free_length=5.0)
    lk.torsion_spring("knee", "B", stiffness=25.0, free_angle=0.2, links=("3", "4"))
    w2, h = 3.0, 1e-4
    f = lk.forces(lk.solve(THETA2, velocity=w2))

    def energy(theta2):
        m = lk.solve(theta2)
        L = np.abs(m.points["P"] - m.points["S"])
        phi = m.theta["4"] - m.theta["3"]
        return 0.5 * 80.0 * (L - 5.0) ** 2, 0.5 * 25.0 * (phi - 0.2) ** 2

    (ep, eq), (em, er) = energy(THETA2 + h), energy(THETA2 - h)
    for name, de in (("gas", (ep - em) / (2 * h / w2)), ("knee", (eq - er) / (2 * h / w2))):
        power = -f.elements[name] * f.element_rate[name]
        assert np.allclose(power, -de, rtol=0, atol=1e-6 * np.abs(de).max())


def test_massless_fourbar_driver_torque_by_virtual_work():
    """T12 dtheta2 - sum T dL - sum tau dphi = 0: T12 = sum T dL/dtheta2 + sum tau dphi/dtheta2,
    the derivatives by central differences of the solved positions (damping included,
    with dL/dt = omega2 dL/dtheta2)."""
    lk = with_elements(hw6(), damping=True)
    w2, h = 2.5, 1e-5
    f = lk.forces(lk.solve(THETA2, velocity=w2))
    mp, mm = lk.solve(THETA2 + h), lk.solve(THETA2 - h)
    m0 = lk.solve(THETA2)
    total = np.zeros_like(THETA2)
    for s, e, k, L0, c, T0 in SPRINGS.values():

        def L(mo, s=s, e=e):
            return np.abs(mo.points[e] - mo.points[s])

        dL = (L(mp) - L(mm)) / (2 * h)
        total += (k * (L(m0) - L0) + c * w2 * dL + T0) * dL
    for _, (a, b), kt, phi0, ct, tau0 in TORSIONS.values():

        def phi(mo, a=a, b=b):
            return mo.theta[b] - (0.0 if a == "ground" else mo.theta[a])

        dphi = (phi(mp) - phi(mm)) / (2 * h)
        total += (kt * (phi(m0) - phi0) + ct * w2 * dphi + tau0) * dphi
    assert np.allclose(f.driver["2"], total, rtol=0, atol=1e-6 * np.abs(total).max())


def test_return_spring_on_a_slider_block_closed_form():
    """Massless slider-crank (a = 2, b = 6) with a spring-damper from the ground point
    S = (-3, 0) on the slide line to the block B: L = x_B + 3 with
    x_B = a cos(theta) + sqrt(b^2 - a^2 sin^2(theta)) and T12 = T dx_B/dtheta (by hand)."""
    a, b, k, L0, c, T0, w2 = 2.0, 6.0, 500.0, 9.0, 4.0, 30.0, 7.0
    lk = (
        Linkage({"O2": 0j, "A": a + 0j, "B": a + b + 0j, "S": -3.0 + 0j})
        .ground("O2", "S")
        .link("crank", "O2", "A")
        .link("rod", "A", "B")
        .link("block", "B")
        .slider("block", "ground", "B", 0.0, name="guide")
        .spring("return", "S", "B", stiffness=k, free_length=L0, damping=c, preload=T0)
        .drive("crank")
    )
    theta = np.radians(np.arange(0.0, 360.0, 5.0))
    f = lk.forces(lk.solve(theta, velocity=w2))
    root = np.sqrt(b**2 - (a * np.sin(theta)) ** 2)
    x_b = a * np.cos(theta) + root
    dx = -a * np.sin(theta) - a**2 * np.sin(theta) * np.cos(theta) / root
    T = k * (x_b + 3.0 - L0) + c * w2 * dx + T0
    assert np.allclose(f.elements["return"], T, rtol=0, atol=1e-10 * np.abs(T).max())
    assert np.allclose(f.driver["crank"], T * dx, rtol=0, atol=1e-10 * np.abs(T * dx).max())
    # the rate from the solved velocities: dL/dt = omega2 dx_B/dtheta
    assert np.allclose(f.element_rate["return"], w2 * dx, rtol=0, atol=1e-10)


def test_power_balance_random_springs_on_the_fourbar(rng):
    """Seeded random attachments (ground-coupler, crank-rocker) and laws: the power balance
    holds to 1e-8 whatever the geometry."""
    for _ in range(6):
        lk = hw6(masses=True)
        lk.point("S", complex(*rng.uniform(-6.0, 10.0, 2)))
        k, c = rng.uniform(0.0, 300.0, 2)
        L0 = rng.uniform(1.0, 10.0)
        pre = rng.normal(0.0, 50.0)
        lk.spring("s1", "S", "P", stiffness=k, free_length=L0, damping=c, preload=pre)
        k2, c2, L2 = rng.uniform(0.0, 300.0), rng.uniform(0.0, 5.0), rng.uniform(1.0, 10.0)
        lk.spring("s2", "Q", "A", stiffness=k2, free_length=L2, damping=c2)
        w2 = rng.uniform(1.0, 8.0)
        m = lk.solve(THETA2, velocity=w2)
        f = lk.forces(m, gravity=G)
        assert f.ok.all()
        dke, dpe = kinetic_rates(lk, m)
        p_el = 0.0
        for name, (start, end, kk, ll, cc, t0) in {
            "s1": ("S", "P", k, L0, c, pre),
            "s2": ("Q", "A", k2, L2, c2, 0.0),
        }.items():
            L, L_dot = length_and_rate(m, start, end)
            T = kk * (L - ll) + cc * L_dot + t0
            assert np.allclose(f.elements[name], T, rtol=0, atol=1e-10 * np.abs(T).max())
            p_el = p_el - T * L_dot
        power = f.driver["2"] * w2 + p_el
        scale = np.abs(f.driver["2"] * w2).max() + np.abs(dke).max() + np.abs(p_el).max()
        assert np.abs(power - dke - dpe).max() <= 1e-8 * scale


def test_shaking_force_is_newtons_law_for_the_moving_links():
    """A spring to the ground loads the frame: Fs = -sum m (a_G + j g) still holds."""
    lk = with_elements(hw6(masses=True), damping=True)
    m = lk.solve(THETA2, velocity=5.0)
    f = lk.forces(m, gravity=G)
    newton = -sum(ln.mass * (m.cg_acceleration[n] + 1j * G) for n, ln in lk._links.items())
    assert np.allclose(f.shaking_force, newton, rtol=0, atol=1e-9 * np.abs(newton).max())


def test_springs_do_not_change_the_motion_or_the_mobility():
    bare, sprung = hw6(), with_elements(hw6(), damping=True)
    assert bare.mobility() == sprung.mobility() == 1
    m0, m1 = bare.solve(THETA2, velocity=1.0), sprung.solve(THETA2, velocity=1.0)
    for n in ("2", "3", "4"):
        assert np.array_equal(m0.theta[n], m1.theta[n])
    # and with no spring the forces have no elements
    assert dict(bare.forces(m0).elements) == {}


def test_zero_length_sample_is_flagged_not_nan_silently():
    """A spring from a ground point that the coupler point P passes through."""
    lk = hw6()
    theta2 = np.radians(np.arange(0.0, 181.0, 15.0))
    p_at = complex(lk.solve(theta2).points["P"][6])  # where P is at theta2 = 90 deg
    lk.point("S", p_at)
    lk.spring("gas", "S", "P", stiffness=10.0, free_length=1.0)
    f = lk.forces(lk.solve(theta2, velocity=1.0))
    assert not f.ok[6] and f.reason[6] == FORCE_REASONS["spring"]
    assert np.isnan(f.elements["gas"][6]) and np.isnan(f.driver["2"][6])
    assert f.ok[np.arange(theta2.size) != 6].all()


def test_tables_have_the_element_columns():
    lk = with_elements(hw6(), damping=False)
    df = lk.forces(lk.solve(THETA2[:5], velocity=1.0)).to_pandas()
    for name in [*SPRINGS, *TORSIONS]:
        assert {f"T_{name}", f"L_{name}", f"Ldot_{name}"} <= set(df.columns)
    assert np.allclose(df["L_gas"], length_and_rate(lk.solve(THETA2[:5], 1.0), "S", "P")[0])


# ---------------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    "kw, field",
    [
        (dict(stiffness=10.0, free_length=0.0), "gas.free_length"),
        (dict(stiffness=10.0, free_length=-2.0), "gas.free_length"),
        (dict(stiffness=-1.0, free_length=2.0), "gas.stiffness"),
        (dict(stiffness=1.0, free_length=2.0, damping=-0.5), "gas.damping"),
        (dict(stiffness=1.0, free_length=2.0, preload=np.nan), "gas.preload"),
        (dict(stiffness=np.inf, free_length=2.0), "gas.stiffness"),
    ],
)
def test_bad_spring_numbers(kw, field):
    with pytest.raises(InputError) as err:
        hw6().spring("gas", "S", "P", **kw)
    assert err.value.field == field


@pytest.mark.parametrize(
    "kw, field",
    [
        (dict(stiffness=-1.0, free_angle=0.0), "coil.stiffness"),
        (dict(stiffness=1.0, free_angle=0.0, damping=-1.0), "coil.damping"),
        (dict(stiffness=1.0, free_angle=np.inf), "coil.free_angle"),
        (dict(stiffness=1.0, free_angle=0.0, preload=np.nan), "coil.preload"),
    ],
)
def test_bad_torsion_numbers(kw, field):
    with pytest.raises(InputError) as err:
        hw6().torsion_spring("coil", "O4", **kw)
    assert err.value.field == field


def test_unknown_points_and_links():
    with pytest.raises(ModelError, match="'Z'"):
        hw6().spring("gas", "S", "Z", stiffness=1.0, free_length=1.0)
    with pytest.raises(ModelError, match="not on link '3'"):
        hw6().spring("gas", "S", "Q", stiffness=1.0, free_length=1.0, links=("ground", "3"))
    with pytest.raises(ModelError, match="'Z'"):
        hw6().torsion_spring("coil", "Z", stiffness=1.0, free_angle=0.0)
    # a drawn point that no link carries: refused when the linkage is compiled
    lk = hw6().point("X", (1.0, 1.0)).spring("gas", "S", "X", stiffness=1.0, free_length=1.0)
    with pytest.raises(ModelError, match="on no link"):
        lk.solve(THETA2)


def test_an_element_on_one_link_is_refused():
    """Both ends on one rigid link: the load is internal and does nothing, and its length
    never changes — refused (a ModelError naming the link), not warned, since a user who
    wrote it surely meant another link."""
    with pytest.raises(ModelError, match="both ends are on link '3'"):
        hw6().spring("s", "U", "P", stiffness=1.0, free_length=1.0).solve(THETA2)
    with pytest.raises(ModelError, match="both ends are on link 'ground'"):
        hw6().spring("s", "S", "O2", stiffness=1.0, free_length=1.0, links=("ground", "ground"))
    with pytest.raises(ModelError, match="both ends are on link '4'"):
        hw6().spring("s", "O4", "B", stiffness=1.0, free_length=1.0, links=("4", "4"))
    with pytest.raises(ModelError, match="both ends are on link '3'"):
        hw6().torsion_spring("t", "B", stiffness=1.0, free_angle=0.0, links=("3", "3"))
    with pytest.raises(ModelError, match="joins point 'A' to itself"):
        hw6().spring("s", "A", "A", stiffness=1.0, free_length=1.0)
    # at a pin the default carriers are two different links: A is on the crank and coupler,
    # so a spring from A to P (coupler only) acts between the crank and the coupler
    lk = hw6().spring("s", "A", "P", stiffness=1.0, free_length=1.0)
    assert lk._element_links("s") == ("2", "3")


def test_torsion_spring_needs_a_pin_and_says_which_links():
    with pytest.raises(ModelError, match="no pin"):
        hw6().torsion_spring("t", "P", stiffness=1.0, free_angle=0.0).solve(THETA2)
    lk = hw6().link("5", "B", "Q")  # B now joins 3, 4 and 5 (the mobility is off too)
    with pytest.raises(ModelError, match="say which two"):
        lk.torsion_spring("t", "B", stiffness=1.0, free_angle=0.0)._element_links("t")


def test_element_names_are_unique():
    lk = hw6().spring("gas", "S", "P", stiffness=1.0, free_length=1.0)
    with pytest.raises(ModelError, match="used twice"):
        lk.spring("gas", "S", "B", stiffness=1.0, free_length=1.0)
    with pytest.raises(ModelError, match="used twice"):
        lk.torsion_spring("gas", "O4", stiffness=1.0, free_angle=0.0)
    with pytest.raises(ModelError, match="used twice"):
        lk.spring("3", "S", "B", stiffness=1.0, free_length=1.0)
    with pytest.raises(ModelError, match="driver 'gas'"):
        lk.drive("gas")
    with pytest.raises(InputError):
        lk.spring("", "S", "B", stiffness=1.0, free_length=1.0)
