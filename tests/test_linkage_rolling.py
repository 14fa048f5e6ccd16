"""Tests of rolling contact (``Linkage.roll``): two profiles rolling without slip.

References that do not share the code path of Linkage:
* pure rolling of a wheel on the ground (the main notes' "Pure rolling" page:
  ``V_C = 0``, ``A_C = ω² R ĵ``, ``V_A = −ω R î``, ``A_A = −α R î``,
  ``A_B = −2 α R î − ω² R ĵ`` for the top point B): the centre moves r·θ and a
  rim point traces a cycloid;
* friction wheels on fixed pivots (the notes' GEARS page, Norton Fig. 9-1
  "rolling cylinders", ``r1 ω1 = r2 ω2`` in magnitude): ``ω_b/ω_a = −r_a/r_b``
  (external) and ``+r_a/r_b`` (internal);
* a planetary train with a fixed ring: Willis' formula
  ``(ω_s − ω_arm)/(ω_r − ω_arm) = −r_r/r_s``;
* conservation of power ``T ω + ΣP_ext = d(KE)/dt + d(PE)/dt`` with KE and PE
  computed here from the returned motion, and virtual work for massless links.
"""

from __future__ import annotations

import numpy as np
import pytest

from machdyn.errors import InputError, ModelError
from machdyn.linkage import Linkage

# every test on the NumPy path and on the compiled kernels (tests/conftest.py)
pytestmark = pytest.mark.usefixtures("backend")

R = 1.0  # wheel radius
G = 9.81


def wheel_on_ground(**masses) -> Linkage:
    """A wheel (centre C, rim point W) rolling on the ground line y = 0, its centre
    pinned to a rod whose far end B slides on a horizontal guide at y = 2.5."""
    lk = Linkage({"T": (0, 0), "C": (0, R), "W": (R, R), "B": (2.0, 2.5), "O": (0, 2.5)})
    lk.ground("T", "O")
    lk.link("wheel", "C", "W", **masses.get("wheel", {}))
    lk.link("rod", "C", "B", **masses.get("rod", {}))
    lk.link("block", "B", **masses.get("block", {}))
    lk.slider("block", "ground", "B", 0.0, through="O", name="guide")
    lk.roll("wheel", "C", R, "ground", "T", np.inf, name="tyre")
    return lk.drive("wheel")


def test_wheel_on_ground_pure_rolling():
    lk = wheel_on_ground()
    assert lk.mobility() == 1  # L = 4, J1 = roll + 2 pins + slider
    theta = np.linspace(-1.0, 5.0, 61)
    omega = 2.0 + np.sin(theta)
    alpha = 0.5 - np.cos(theta)
    m = lk.solve(theta, velocity=omega, acceleration=alpha)
    assert m.ok.all()
    # centre moves -r θ (CCW rolling goes to -x), at constant height r
    np.testing.assert_allclose(m.points["C"], -R * theta + 1j * R, atol=1e-10)
    # a rim point traces a cycloid: W = C + r e^{jθ}
    cycloid = -R * theta + 1j * R + R * np.exp(1j * theta)
    np.testing.assert_allclose(m.points["W"], cycloid, atol=1e-10)
    # V_centre = -r ω, A_centre = -r α (rolling on the ground)
    np.testing.assert_allclose(m.point_velocity["C"], -R * omega, atol=1e-10)
    np.testing.assert_allclose(m.point_acceleration["C"], -R * alpha, atol=1e-10)
    # the material point at the contact: V = 0, A = r ω² upward (toward the centre)
    r_ct = -1j * R  # contact relative to the centre
    v_ct = m.point_velocity["C"] + 1j * omega * r_ct
    a_ct = m.point_acceleration["C"] + (1j * alpha - omega**2) * r_ct
    np.testing.assert_allclose(v_ct, 0.0, atol=1e-10)
    np.testing.assert_allclose(a_ct, 1j * R * omega**2, atol=1e-9)
    # the top point B of the rim (the notes: A_B = −2 α R î − ω² R ĵ)
    r_top = 1j * R
    a_top = m.point_acceleration["C"] + (1j * alpha - omega**2) * r_top
    np.testing.assert_allclose(a_top, -2 * alpha * R - 1j * omega**2 * R, atol=1e-9)
    # the block follows the centre (rod translates)
    np.testing.assert_allclose(m.points["B"] - m.points["C"], 2.0 + 1.5j, atol=1e-10)


def test_wheel_driven_by_slider_turns_minus_d_over_r():
    lk = wheel_on_ground().drive("guide")
    d = np.linspace(2.0, -6.0, 41)  # drawn d = 2 (B from the foot of O)
    m = lk.solve(d, velocity=3.0)
    assert m.ok.all()
    np.testing.assert_allclose(m.theta["wheel"], -(d - 2.0) / R, atol=1e-10)
    np.testing.assert_allclose(m.omega["wheel"], -3.0 / R, atol=1e-10)


def friction_wheels(r_a: float, r_b: float, internal: bool) -> Linkage:
    d = abs(r_a - r_b) if internal else r_a + r_b
    lk = Linkage({"Oa": (0, 0), "Ob": (d * 0.6, d * 0.8), "P": (r_a, 0), "Q": (0.3, -r_b)})
    lk.ground("Oa", "Ob").link("a", "Oa", "P").link("b", "Ob", "Q")
    return lk.roll("a", "Oa", r_a, "b", "Ob", r_b, internal=internal).drive("a")


@pytest.mark.parametrize(
    ("r_a", "r_b", "internal", "ratio"),
    [(2.0, 3.0, False, -2.0 / 3.0), (1.5, 4.0, True, 1.5 / 4.0), (5.0, 2.0, True, 5.0 / 2.0)],
)
def test_friction_wheels_speed_ratio(r_a, r_b, internal, ratio):
    lk = friction_wheels(r_a, r_b, internal)
    assert lk.mobility() == 1  # the centre distance is fixed by the ground: no-slip only
    theta = np.linspace(0.0, 4 * np.pi, 50)
    m = lk.solve(theta, velocity=7.0, acceleration=-2.0)
    assert m.ok.all()
    np.testing.assert_allclose(m.omega["b"], ratio * 7.0, rtol=1e-12)
    np.testing.assert_allclose(m.alpha["b"], ratio * -2.0, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(m.theta["b"] - m.theta["b"][0], ratio * theta, atol=1e-10)


def planetary(r_s=2.0, r_p=1.0, **masses) -> tuple[Linkage, float]:
    r_r = r_s + 2 * r_p
    lk = Linkage({"O": (0, 0), "S": (r_s, 0), "Pc": (0, r_s + r_p), "Q": (r_p, r_s + r_p)})
    lk.ground("O")
    lk.link("sun", "O", "S", **masses.get("sun", {}))
    lk.link("arm", "O", "Pc", **masses.get("arm", {}))
    lk.link("planet", "Pc", "Q", **masses.get("planet", {}))
    lk.roll("sun", "O", r_s, "planet", "Pc", r_p, name="sun/planet")
    lk.roll("planet", "Pc", r_p, "ground", "O", r_r, internal=True, name="planet/ring")
    return lk.drive("sun"), r_r


def test_planetary_train_willis():
    lk, r_r = planetary()
    assert lk.mobility() == 1
    m = lk.solve(np.linspace(0, 2 * np.pi, 37), velocity=10.0)
    assert m.ok.all()
    # Willis with ω_ring = 0: (ω_s − ω_arm)/(0 − ω_arm) = −r_r/r_s, i.e. ω_arm = 10·2/6
    w_arm = m.omega["arm"]
    np.testing.assert_allclose((10.0 - w_arm) / (0.0 - w_arm), -r_r / 2.0, rtol=1e-12)
    np.testing.assert_allclose(w_arm, 10.0 * 2.0 / 6.0, rtol=1e-12)
    # sun/planet relative to the arm: (ω_s − ω_arm) r_s = −(ω_p − ω_arm) r_p
    w_rel = m.omega["planet"] - w_arm
    np.testing.assert_allclose((10.0 - w_arm) * 2.0, -w_rel * 1.0, rtol=1e-12)
    # a massless train: virtual work T_s ω_s + T_arm ω_arm = 0
    f = lk.forces(m, external_torques={"arm": -3.0})
    np.testing.assert_allclose(f.driver["sun"] * 10.0, 3.0 * m.omega["arm"], rtol=1e-10)


def kinetic_and_potential(lk, m, names):
    ke = sum(
        0.5 * lk._links[n].mass * np.abs(m.cg_velocity[n]) ** 2
        + 0.5 * lk._links[n].inertia * m.omega[n] ** 2
        for n in names
    )
    dke = sum(
        lk._links[n].mass * (np.conj(m.cg_velocity[n]) * m.cg_acceleration[n]).real
        + lk._links[n].inertia * m.omega[n] * m.alpha[n]
        for n in names
    )
    dpe = sum(lk._links[n].mass * G * m.cg_velocity[n].imag for n in names)
    return ke, dke, dpe


def test_power_balance_wheel_on_ground_with_masses():
    masses = {
        "wheel": {"mass": 4.0, "inertia": 2.0, "cg": (0.2, 0.1)},  # unbalanced wheel
        "rod": {"mass": 1.5, "inertia": 0.8, "cg": (1.0, 0.3)},
        "block": {"mass": 2.0, "inertia": 0.1},
    }
    lk = wheel_on_ground(**masses)
    theta = np.linspace(0.0, 6.0, 301)
    omega = 3.0 + np.sin(2 * theta)  # a non-uniform input
    alpha = 2 * np.cos(2 * theta) * omega  # dω/dt = dω/dθ · ω
    m = lk.solve(theta, velocity=omega, acceleration=alpha)
    f = lk.forces(
        m, gravity=G, external_torques={"rod": 1.2}, external_forces=[("block", "B", -4.0 + 1.0j)]
    )
    assert f.ok.all()
    ke, dke, dpe = kinetic_and_potential(lk, m, ["wheel", "rod", "block"])
    p_ext = 1.2 * m.omega["rod"] + (np.conj(-4.0 + 1.0j) * m.point_velocity["B"]).real
    np.testing.assert_allclose(f.driver["wheel"] * omega + p_ext, dke + dpe, atol=1e-8)
    # d(KE)/dt also by finite differences in θ (dKE/dt = dKE/dθ ω)
    dke_fd = np.gradient(ke, theta, edge_order=2) * omega
    np.testing.assert_allclose(dke_fd[2:-2], dke[2:-2], atol=1e-3 * np.abs(dke).max())
    # the contact force: on the wheel from the ground, at the contact point (under C)
    np.testing.assert_allclose(f.contact["tyre"], m.points["C"] - 1j * R, atol=1e-10)
    # Newton's law for the wheel rebuilt from the returned forces
    F_wheel = -f.rolling["tyre"] + f.F("rod", "wheel") - 4.0 * G * 1j
    np.testing.assert_allclose(F_wheel, 4.0 * m.cg_acceleration["wheel"], atol=1e-8)


def test_power_balance_planetary_with_masses():
    masses = {
        "sun": {"mass": 1.0, "inertia": 0.3, "cg": (0.1, 0.0)},
        "arm": {"mass": 2.0, "inertia": 0.5, "cg": (1.5, 0.0)},
        "planet": {"mass": 0.5, "inertia": 0.1, "cg": (0.2, 0.1)},
    }
    lk, _ = planetary(**masses)
    t = np.linspace(0.0, 3.0, 200)
    theta, omega, alpha = 2 * t + 0.3 * t**2, 2 + 0.6 * t, 0.6 + 0 * t
    m = lk.solve(theta, velocity=omega, acceleration=alpha)
    f = lk.forces(m, gravity=G)
    assert f.ok.all()
    _, dke, dpe = kinetic_and_potential(lk, m, ["sun", "arm", "planet"])
    np.testing.assert_allclose(f.driver["sun"] * omega, dke + dpe, atol=1e-8)
    # a carried contact transmits only a tangential force
    for name in ("sun/planet", "planet/ring"):
        n = m.points["Pc"] / np.abs(m.points["Pc"])
        np.testing.assert_allclose((f.rolling[name] * np.conj(n)).real, 0.0, atol=1e-9)


def rack_and_pinion(r: float = 0.5) -> Linkage:
    """A pinion (radius r, fixed pivot O) on a rack K-S sliding along the ground."""
    lk = Linkage({"O": (0, 0), "P": (r, 0), "K": (0, -r), "S": (1.0, -r), "E": (-3.0, -r)})
    lk.ground("O", "E").link("pinion", "O", "P").link("rack", "K", "S")
    lk.slider("rack", "ground", "S", 0.0, through="E", name="guide")
    return lk.roll("pinion", "O", r, "rack", "K", np.inf, name="mesh")


def test_rack_and_pinion_guided_rack():
    """The guide fixes the pinion–rack distance: no-slip only, ``ḋ = r ω`` (no slip at C)."""
    r = 0.5
    lk = rack_and_pinion(r).drive("pinion")
    assert lk.mobility() == 1
    theta = np.linspace(-1.0, 3.0, 21)
    m = lk.solve(theta, velocity=4.0, acceleration=1.0)
    assert m.ok.all()
    # the pinion's material point at the contact (0, −r) moves at ω r along +x
    np.testing.assert_allclose(m.lengths["guide"] - 4.0, r * theta, atol=1e-10)
    np.testing.assert_allclose(m.length_rate["guide"], r * 4.0, rtol=1e-12)
    np.testing.assert_allclose(m.length_acceleration["guide"], r * 1.0, rtol=1e-12)
    # massless, a load −10 on the rack: T ω = 10 · r ω (virtual work); the contact
    # pushes the rack with +10 along the profile
    f = lk.forces(m, external_forces=[("rack", "S", -10.0)])
    assert f.ok.all()
    np.testing.assert_allclose(f.driver["pinion"], 10.0 * r, rtol=1e-12)
    np.testing.assert_allclose(f.rolling["mesh"], 10.0, atol=1e-12)
    np.testing.assert_allclose(f.contact["mesh"], m.points["O"] - 1j * r, atol=1e-12)
    # driven by the rack instead: the pinion turns at ḋ / r
    m2 = rack_and_pinion(r).drive("guide").solve(np.array([4.0, 5.0]), velocity=2.0)
    np.testing.assert_allclose(m2.theta["pinion"], [0.0, 1.0 / r], atol=1e-10)
    np.testing.assert_allclose(m2.omega["pinion"], 2.0 / r, rtol=1e-12)


def test_wheel_rolling_inside_fixed_ring_driven_by_arm():
    """A wheel of radius r inside a ground ring of radius R0, its centre on an arm:
    its contact point is at rest: (R0 − r) ω_arm + r ω_w = 0 (a hypocycloid generator)."""
    r, R0 = 1.0, 4.0
    lk = Linkage({"O": (0, 0), "C": (R0 - r, 0), "W": (R0 - r, r)})
    lk.ground("O").link("arm", "O", "C").link("wheel", "C", "W")
    lk.roll("wheel", "C", r, "ground", "O", R0, internal=True).drive("arm")
    m = lk.solve(np.linspace(0, 2 * np.pi, 25), velocity=1.5)
    assert m.ok.all()
    np.testing.assert_allclose(m.omega["wheel"], -1.5 * (R0 - r) / r, rtol=1e-12)


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"radius_a": 0.0}, "radius_a"),
        ({"radius_a": -1.0}, "radius_a"),
        ({"radius_b": -3.0}, "radius_b"),
        ({"radius_b": float("nan")}, "radius_b"),
        ({"radius_b": -np.inf}, "radius_b"),
        ({"radius_b": "big"}, "radius_b"),
        ({"radius_a": np.inf}, "radius_a"),  # only link_b may be straight
        ({"radius_b": 2.5}, "centre_b"),  # 2 + 2.5 != 5: not touching
        ({"internal": True}, "centre_b"),  # |2 - 3| != 5
    ],
)
def test_bad_input_names_the_field(kwargs, field):
    lk = Linkage({"Oa": (0, 0), "Ob": (5, 0), "P": (2, 0), "Q": (5, 3)})
    lk.ground("Oa", "Ob").link("a", "Oa", "P").link("b", "Ob", "Q")
    args = {"radius_a": 2.0, "radius_b": 3.0, "internal": False} | kwargs
    with pytest.raises(InputError, match=field):
        lk.roll("a", "Oa", args["radius_a"], "b", "Ob", args["radius_b"], internal=args["internal"])


def test_bad_structure():
    lk = Linkage({"Oa": (0, 0), "Ob": (5, 0), "P": (2, 0), "Q": (5, 3)})
    lk.ground("Oa", "Ob").link("a", "Oa", "P").link("b", "Ob", "Q")
    with pytest.raises(ModelError, match="not on link"):
        lk.roll("a", "Ob", 2.0, "b", "Ob", 3.0)
    with pytest.raises(ModelError, match="unknown link"):
        lk.roll("a", "Oa", 2.0, "c", "Ob", 3.0)
    with pytest.raises(ModelError, match="itself"):
        lk.roll("a", "Oa", 1.0, "a", "P", 1.0)
    with pytest.raises(InputError, match="internal"):
        Linkage({"C": (0, 1), "T": (0, 0)}).ground("T").link("w", "C").roll(
            "w", "C", 1.0, "ground", "T", np.inf, internal=True
        )
    with pytest.raises(InputError, match="radius_b"):  # internal with equal radii
        lk.roll("a", "Oa", 2.0, "b", "Ob", 2.0, internal=True)
    lk.roll("a", "Oa", 2.0, "b", "Ob", 3.0, name="r")
    with pytest.raises(ModelError, match="twice"):
        lk.roll("a", "Oa", 2.0, "b", "Ob", 3.0, name="r")


def sun_and_planet(**masses) -> Linkage:
    """A sun (radius 2, pivot O) and a planet (radius 1) rolling on it outside, the
    planet's centre C pinned to a rod whose end B slides on a guide at y = 4: two
    freedoms (L = 5, J1 = 2 pins + roll + pin + slider), driven by the sun and the guide."""
    C = 3.0 * np.exp(1j * np.pi / 3)
    pts = {"O": 0j, "S": 2 + 0j, "C": C, "W": C + 1, "B": 4 + 4j, "E": -5 + 4j}
    lk = Linkage(pts).ground("O", "E")
    lk.link("sun", "O", "S", **masses.get("sun", {}))
    lk.link("planet", "C", "W", **masses.get("planet", {}))
    lk.link("rod", "C", "B", **masses.get("rod", {}))
    lk.link("block", "B", **masses.get("block", {}))
    lk.slider("block", "ground", "B", 0.0, through="E", name="guide")
    lk.roll("sun", "O", 2.0, "planet", "C", 1.0, name="contact")
    return lk.drive("sun", "guide")


def sun_planet_inputs(n: int = 201):
    t = np.linspace(0.0, 1.0, n)
    values = {"sun": 2.0 * t + t**2, "guide": 9.0 - 1.5 * t + 0.5 * t**3}
    velocity = {"sun": 2.0 + 2 * t, "guide": -1.5 + 1.5 * t**2}
    acceleration = {"sun": 2.0 + 0 * t, "guide": 3.0 * t}
    return t, values, velocity, acceleration


def test_sun_and_planet_no_slip_between_moving_links():
    lk = sun_and_planet()
    assert lk.mobility() == 2
    t, values, velocity, acceleration = sun_planet_inputs()
    m = lk.solve(values, velocity=velocity, acceleration=acceleration)
    assert m.ok.all()
    o, C = m.points["O"], m.points["C"]
    np.testing.assert_allclose(np.abs(C - o), 3.0, rtol=1e-12)  # constant centre distance
    contact = o + 2.0 * (C - o) / 3.0
    v_sun = 1j * m.omega["sun"] * (contact - o)
    v_planet = m.point_velocity["C"] + 1j * m.omega["planet"] * (contact - C)
    np.testing.assert_allclose(v_planet, v_sun, atol=1e-10)  # no slip
    # rates by central finite differences in time (independent of the velocity solve)
    dt = t[1] - t[0]
    for name in ("planet", "rod"):
        fd = np.gradient(m.theta[name], dt, edge_order=2)
        np.testing.assert_allclose(fd[1:-1], m.omega[name][1:-1], atol=2e-4)
        fd2 = np.gradient(m.omega[name], dt, edge_order=2)
        np.testing.assert_allclose(fd2[1:-1], m.alpha[name][1:-1], atol=2e-3)


def test_power_balance_sun_and_planet_with_masses():
    masses = {
        "sun": {"mass": 3.0, "inertia": 1.0, "cg": (0.3, 0.2)},
        "planet": {"mass": 1.0, "inertia": 0.2, "cg": (0.1, -0.2)},
        "rod": {"mass": 0.7, "inertia": 0.3, "cg": (1.2, 0.1)},
        "block": {"mass": 1.5, "inertia": 0.05},
    }
    lk = sun_and_planet(**masses)
    _, values, velocity, acceleration = sun_planet_inputs()
    m = lk.solve(values, velocity=velocity, acceleration=acceleration)
    f = lk.forces(m, gravity=G, external_torques={"planet": -0.7})
    assert f.ok.all()
    _, dke, dpe = kinetic_and_potential(lk, m, list(masses))
    power_in = (
        f.driver["sun"] * velocity["sun"]
        + f.driver["guide"] * velocity["guide"]
        - 0.7 * m.omega["planet"]
    )
    np.testing.assert_allclose(power_in, dke + dpe, atol=1e-8)
    # the sun's equations rebuilt from the returned forces (moment about O)
    X = f.contact["contact"]
    F_on_sun = -f.rolling["contact"]
    F_pin = f.F("ground", "sun")
    np.testing.assert_allclose(
        F_pin + F_on_sun - 3.0 * G * 1j, 3.0 * m.cg_acceleration["sun"], atol=1e-8
    )
    r_g = m.cg["sun"]
    moment = (
        f.driver["sun"]
        + ((np.conj(X - r_g) * F_on_sun).imag)
        + ((np.conj(m.points["O"] - r_g) * F_pin).imag)
    )
    np.testing.assert_allclose(moment, 1.0 * m.alpha["sun"], atol=1e-8)


def test_random_friction_wheels_seeded():
    """Seeded random radii and layouts: the ratio is −ra/rb outside, +ra/rb inside."""
    rng = np.random.default_rng(20261121)
    for _ in range(12):
        r_a, r_b = rng.uniform(0.2, 5.0, 2)
        internal = bool(rng.integers(2)) and abs(r_a - r_b) > 0.05
        d = abs(r_a - r_b) if internal else r_a + r_b
        oa = complex(*rng.uniform(-3, 3, 2))
        ob = oa + d * np.exp(1j * rng.uniform(0, 2 * np.pi))
        pa = oa + r_a * np.exp(1j * rng.uniform(0, 2 * np.pi))
        qb = ob + 0.7 * np.exp(1j * rng.uniform(0, 2 * np.pi))
        lk = Linkage({"Oa": oa, "Ob": ob, "P": pa, "Q": qb}).ground("Oa", "Ob")
        lk.link("a", "Oa", "P").link("b", "Ob", "Q")
        lk.roll("a", "Oa", r_a, "b", "Ob", r_b, internal=internal).drive("a")
        w = rng.uniform(-5, 5)
        m = lk.solve(np.angle(pa - oa) + np.linspace(0, 1, 5), velocity=w)
        assert m.ok.all()
        ratio = (r_a / r_b) * (1.0 if internal else -1.0)
        np.testing.assert_allclose(m.omega["b"], ratio * w, rtol=1e-10, atol=1e-12)


def test_unreachable_sample_is_flagged_not_nan_silently():
    lk = sun_and_planet()
    values = {"sun": np.array([0.0, 0.0]), "guide": np.array([9.0, 30.0])}  # B far away
    m = lk.solve(values, velocity={"sun": 1.0, "guide": 0.0}, continuation=False)
    assert m.ok.tolist() == [True, False]
    assert m.reason[1] != ""
    f = lk.forces(m)
    assert f.ok.tolist() == [True, False]
    assert np.isnan(f.rolling["contact"][1]) and np.isnan(f.contact["contact"][1])
    assert np.isfinite(f.rolling["contact"][0])
