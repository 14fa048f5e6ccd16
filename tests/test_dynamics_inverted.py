"""Newton–Euler forces of the inverted slider-crank (Norton §11.7), checked three ways apart.

Independent references, none sharing the closed forms' code path:

* an equivalent :class:`~machdyn.linkage.Linkage` drawn here (a crank, a block
  pinned to it and sliding on a slotted rocker), solved by ``Linkage.forces``
  (its own kinematics and, for the RPR group, its LU over the group's nine
  equations) — every force, the normal force, the couple, friction, shaking;
* the power balance ``T12 ω2 + ΣP_loads = d(KE)/dt`` with velocities and
  accelerations of every centre of mass taken by central differences of the
  *positions* along a constant-speed sweep (no solver rate enters);
* hand derivations for static poses: virtual work with ``ω4/ω2`` derived
  here from ``θ4 = arg(a e^{jθ2} − d)``, and the slotted link's moment about
  O4 for the normal force.
"""

from __future__ import annotations

import numpy as np
import pytest

from machdyn import InvertedSliderCrank
from machdyn.dynamics_inverted import (
    INVERTED_REASONS,
    InvertedSliderCrankForces,
    inverted_slidercrank_dynamics,
    inverted_slidercrank_forces,
)
from machdyn.errors import InputError
from machdyn.linkage import Linkage

A_, D_, C_ = 2.0, 4.0, 0.5
MASS, INERTIA = (1.0, 0.5, 3.0), (0.1, 0.01, 2.0)
CG = (1.0 + 0.2j, 0.1 + 0.05j, 2.0 + 0.3j)
THETA = np.radians(np.arange(0.0, 360.0, 15.0)) + 0.1
G = 9.81


@pytest.fixture(scope="module")
def isc():
    return InvertedSliderCrank(A_, D_, C_)


def drawn_linkage(
    isc: InvertedSliderCrank,
    theta2: float = np.radians(40.0),
    form: int = 1,
    mass=MASS,
    inertia=INERTIA,
    cg=CG,
) -> Linkage:
    """The same machine drawn as a Linkage: the block is link A→K (K one unit along the slot),
    the rocker O4→Q (Q one unit along the slot from O4), so the link frames are the model's."""
    m0 = isc.solve(theta2, form=form)
    A0, e4 = complex(m0.A), np.exp(1j * float(m0.theta4))
    lk = Linkage({"O2": 0j, "A": A0, "O4": isc.d + 0j, "K": A0 + e4, "Q": isc.d + e4})
    lk.ground("O2", "O4")
    for name, pts, k in (
        ("crank", ("O2", "A"), 0),
        ("block", ("A", "K"), 1),
        ("rocker", ("O4", "Q"), 2),
    ):
        lk.link(name, *pts, mass=mass[k], inertia=inertia[k], cg=cg[k])
    return lk.slider("block", "rocker", "A", float(m0.theta4), name="slot").drive("crank")


def test_every_force_equals_an_equivalent_linkages(isc):
    lk = drawn_linkage(isc)
    m = lk.solve(THETA, velocity=10.0, acceleration=2.0)
    loads = [("block", 0.3 + 0.1j, 20.0 - 5j), ("rocker", 1.5 + 0j, -8j)]
    ref = lk.forces(
        m, gravity=G, external_torques={"rocker": -3.0, "crank": 0.7}, external_forces=loads
    )
    f = isc.dynamics(
        THETA,
        10.0,
        2.0,
        mass=MASS,
        inertia=INERTIA,
        cg=CG,
        gravity=G,
        load_torque4=-3.0,
        external_torques={2: 0.7},
        external_forces=[(3, 0.3 + 0.1j, 20.0 - 5j), (4, 1.5, -8j)],
    )
    assert f.ok.all() and ref.ok.all()
    pairs = {
        "T12": (f.T12, ref.driver["crank"]),
        "F12": (f.F12, ref.F("ground", "crank")),
        "F32": (f.F32, ref.F("block", "crank")),
        "F43": (f.F43, ref.sliders["slot"]),
        "F14": (f.F14, ref.F("ground", "rocker")),
        "N": (f.N, ref.normal["slot"]),
        "C43": (f.couple, ref.couple["slot"]),
        "shaking force": (f.shaking_force, ref.shaking_force),
        "shaking moment": (f.shaking_moment, ref.shaking_moment),  # both about O2 = origin
    }
    for name, (ours, theirs) in pairs.items():
        scale = max(np.abs(theirs).max(), 1.0)
        assert np.abs(ours - theirs).max() <= 1e-9 * scale, name


@pytest.mark.parametrize("seed", range(6))
def test_random_machines_equal_the_linkage_both_forms(seed):
    """Random dimensions (offset of either sign, crank longer or shorter than the ground),
    masses, centres off the lines, either form: T12 and every joint force agree."""
    rng = np.random.default_rng(seed)
    a, d = rng.uniform(0.5, 3.0, 2)
    c = rng.uniform(-0.4, 0.4) * min(a, d)
    isc = InvertedSliderCrank(a, d, c)
    form = 1 + seed % 2
    mass = tuple(rng.uniform(0.2, 3.0, 3))
    inertia = tuple(rng.uniform(0.01, 1.0, 3))
    cg = tuple(rng.uniform(-1, 1, 3) + 1j * rng.uniform(-0.3, 0.3, 3))
    th = np.linspace(0.0, 2 * np.pi, 37)[:-1] + rng.uniform(0, 0.1)
    drawn = th[isc.solve(th, 1.0, form=form).ok][0]
    lk = drawn_linkage(isc, drawn, form, mass, inertia, cg)
    m = lk.solve(th, velocity=-6.0, acceleration=1.5)
    T4 = rng.uniform(-5, 5)
    ref = lk.forces(m, gravity=G, external_torques={"rocker": T4})
    f = isc.dynamics(
        th, -6.0, 1.5, form=form, mass=mass, inertia=inertia, cg=cg, gravity=G, load_torque4=T4
    )
    both = f.ok & ref.ok
    assert both.sum() >= 0.8 * f.ok.sum() > 0  # the Linkage keeps the drawn circuit
    for ours, theirs in (
        (f.T12, ref.driver["crank"]),
        (f.F12, ref.F("ground", "crank")),
        (f.F32, ref.F("block", "crank")),
        (f.F43, ref.sliders["slot"]),
        (f.F14, ref.F("ground", "rocker")),
        (f.couple, ref.couple["slot"]),
    ):
        scale = max(np.abs(theirs[both]).max(), 1.0)
        assert np.abs(ours[both] - theirs[both]).max() <= 1e-8 * scale


@pytest.mark.parametrize(
    ("friction", "coefficient"), [("coulomb", 0.3), ("coulomb", 1.5), ("viscous", 7.0)]
)
def test_slot_friction_equals_the_linkages(isc, friction, coefficient):
    lk = drawn_linkage(isc)
    m = lk.solve(THETA, velocity=10.0, acceleration=2.0)
    key = "coulomb" if friction == "coulomb" else "viscous"
    ref = lk.forces(m, gravity=G, external_torques={"rocker": -3.0}, **{key: {"slot": coefficient}})
    kw = {"mu": coefficient} if friction == "coulomb" else {"beta": coefficient}
    f = isc.dynamics(
        THETA,
        10.0,
        2.0,
        mass=MASS,
        inertia=INERTIA,
        cg=CG,
        gravity=G,
        load_torque4=-3.0,
        friction=friction,
        **kw,
    )
    assert (f.ok == ref.ok).all() and f.ok.all()
    for ours, theirs in ((f.T12, ref.driver["crank"]), (f.F43, ref.sliders["slot"])):
        assert np.abs(ours - theirs).max() <= 1e-9 * np.abs(theirs).max()
    # the friction opposes the block's sliding in the slot
    slide = f.motion.b_dot
    if friction == "coulomb":
        np.testing.assert_allclose(f.friction_force, -coefficient * np.abs(f.N) * np.sign(slide))
    else:
        np.testing.assert_allclose(f.friction_force, -coefficient * slide, atol=1e-12)


def test_wedging_is_flagged_where_the_linkage_flags_it(isc):
    lk = drawn_linkage(isc)
    m = lk.solve(THETA, velocity=10.0, acceleration=2.0)
    ref = lk.forces(m, gravity=G, external_torques={"rocker": -3.0}, coulomb={"slot": 4.0})
    f = isc.dynamics(
        THETA,
        10.0,
        2.0,
        mass=MASS,
        inertia=INERTIA,
        cg=CG,
        gravity=G,
        load_torque4=-3.0,
        friction="coulomb",
        mu=4.0,
    )
    assert not f.ok.all() and (f.ok == ref.ok).all()
    assert set(f.reason[~f.ok]) == {INVERTED_REASONS[3]}
    assert np.isnan(f.T12[~f.ok]).all() and np.isfinite(f.T12[f.ok]).all()
    good = f.ok
    np.testing.assert_allclose(f.T12[good], ref.driver["crank"][good], rtol=1e-9)


def _centres(isc, th, cg):
    """Centres of mass and link angles from the solved *positions* only."""
    m = isc.solve(th)
    e2 = m.A / isc.a
    e4 = np.exp(1j * m.theta4)
    G2, G3, G4 = cg[0] * e2, m.A + cg[1] * e4, isc.d + cg[2] * e4
    return (G2, G3, G4), (th, np.unwrap(m.theta4), np.unwrap(m.theta4)), m.b


@pytest.mark.parametrize("friction", ["smooth", "coulomb", "viscous"])
def test_power_balance_with_rates_from_differences_of_positions(isc, friction):
    """T12 ω2 + T4 ω4 + P_gravity + P_force + P_friction = d(KE)/dt, constant ω2 (Norton §11.3)."""
    w2, h, T4, F3 = 7.0, 1e-4, -3.0, 20.0 - 5j
    th = THETA
    kw = {"coulomb": {"mu": 0.3}, "viscous": {"beta": 7.0}, "smooth": {}}[friction]
    f = isc.dynamics(
        th,
        w2,
        mass=MASS,
        inertia=INERTIA,
        cg=CG,
        gravity=G,
        load_torque4=T4,
        external_forces=[(3, 0.0, F3)],
        friction=friction,
        **kw,
    )
    (Gm, angm, bm), (G0, ang0, _), (Gp, angp, bp) = (
        _centres(isc, th + s * h, CG) for s in (-1.0, 0.0, 1.0)
    )
    dt = h / w2
    dke = 0.0
    for k in range(3):
        vG = (Gp[k] - Gm[k]) / (2 * dt)
        aG = (Gp[k] - 2 * G0[k] + Gm[k]) / dt**2
        w = (angp[k] - angm[k]) / (2 * dt)
        al = (angp[k] - 2 * ang0[k] + angm[k]) / dt**2
        dke = dke + MASS[k] * (np.conj(vG) * aG).real + INERTIA[k] * w * al
    vA = (isc.solve(th + h).A - isc.solve(th - h).A) / (2 * dt)
    w4 = (angp[2] - angm[2]) / (2 * dt)
    b_dot = (bp - bm) / (2 * dt)
    power = f.T12 * w2 + T4 * w4 + (np.conj(vA) * F3).real
    for k in range(3):
        vG = (Gp[k] - Gm[k]) / (2 * dt)
        power = power - MASS[k] * G * vG.imag
    if friction == "coulomb":
        power = power - 0.3 * np.abs(f.N) * np.abs(b_dot)
    elif friction == "viscous":
        power = power - 7.0 * b_dot**2
    assert f.ok.all()
    scale = np.abs(f.T12 * w2).max()
    assert np.abs(power - dke).max() <= 2e-6 * scale


def test_static_pose_by_virtual_work_and_by_hand():
    """Massless shaper (c = 0), torque T4 on the slotted link, by hand.

    θ4 = arg(a e^{jθ2} − d), so ω4/ω2 = Re(a e^{jθ2} / (a e^{jθ2} − d))
    = a (a − d cos θ2) / (a² + d² − 2 a d cos θ2); virtual work:
    T12 ω2 + T4 ω4 = 0. The slotted link's moment about O4: the block pushes
    it with −N j û at distance b = |A − O4| along the slot, T4 − N b = 0.
    """
    a, d, T4 = 3.0, 7.0, -5.0
    th = np.radians([10.0, 75.0, 150.0, 250.0, 330.0])
    f = inverted_slidercrank_dynamics(
        InvertedSliderCrank(a, d),
        th,
        1.0,
        mass=(0, 0, 0),
        inertia=(0, 0, 0),
        cg=(0, 0, 0),
        load_torque4=T4,
    )
    ratio = a * (a - d * np.cos(th)) / (a * a + d * d - 2 * a * d * np.cos(th))
    np.testing.assert_allclose(f.T12, -T4 * ratio, rtol=1e-12)
    b = np.abs(a * np.exp(1j * th) - d)
    np.testing.assert_allclose(f.N, T4 / b, rtol=1e-12)
    np.testing.assert_allclose(f.couple, 0.0, atol=1e-12)  # a massless block carries no couple
    # two-force members: the ground holds link 4 with the block's push, the crank likewise
    np.testing.assert_allclose(f.F14, f.F43, atol=1e-12)
    np.testing.assert_allclose(f.F12, -f.F32, atol=1e-12)


def test_static_pose_under_gravity_by_virtual_work():
    """At rest (ω2 = α2 = 0) the crank holds the weights: T12 = Σ m g dy_G/dθ2 (by hand, c = 0)."""
    a, d = 3.0, 7.0
    m2, m3, m4, c2, c4 = 2.0, 0.7, 4.0, 1.2, 5.0
    th = np.radians([20.0, 100.0, 200.0, 300.0])
    f = inverted_slidercrank_dynamics(
        InvertedSliderCrank(a, d),
        th,
        0.0,
        mass=(m2, m3, m4),
        inertia=(0.3, 0.02, 6.0),
        cg=(c2, 0.0, c4),
        gravity=G,
    )
    th4 = np.angle(a * np.exp(1j * th) - d)
    dth4 = a * (a - d * np.cos(th)) / (a * a + d * d - 2 * a * d * np.cos(th))
    # y_G2 = c2 sin θ2, y_A = a sin θ2 (block at A), y_G4 = c4 sin θ4
    expected = G * (m2 * c2 * np.cos(th) + m3 * a * np.cos(th) + m4 * c4 * np.cos(th4) * dth4)
    np.testing.assert_allclose(f.T12, expected, rtol=1e-12)
    # the machine at rest: the ground carries the weights
    np.testing.assert_allclose(f.shaking_force, -1j * G * (m2 + m3 + m4), atol=1e-10)


def test_unassemblable_and_toggle_samples_are_flagged_not_zero():
    isc = InvertedSliderCrank(3.0, 2.0, 1.5)  # A passes closer to O4 than the offset
    th = np.linspace(0.0, 2 * np.pi, 73)
    f = isc.dynamics(th, 5.0, mass=MASS, inertia=INERTIA, cg=CG)
    m = f.motion
    assert (~f.ok).any() and f.ok.any()
    assert (f.status[m.status == 1] == 1).all()
    for name in ("T12", "F12", "F32", "F43", "F14", "normal", "couple", "shaking_force"):
        v = getattr(f, name)
        assert np.isnan(v[~f.ok]).all() and np.isfinite(v[f.ok]).all(), name
    assert set(f.reason[~f.ok]) <= set(INVERTED_REASONS[1:3])
    # at the limit b → 0 (A at the foot of the perpendicular): a toggle, flagged
    lo = np.arccos((9 + 4 - 1.5**2) / (2 * 3 * 2))  # |A − O4| = c
    f = isc.dynamics(np.array([lo]), 5.0, mass=MASS, inertia=INERTIA, cg=CG)
    assert not f.ok[0] and "toggle" in f.reason[0]


def test_forces_of_a_given_motion_reuse_and_check_it(isc):
    m = isc.solve(THETA, 10.0, 2.0)
    f = inverted_slidercrank_forces(isc, m, mass=MASS, inertia=INERTIA, cg=CG)
    g = isc.dynamics(THETA, 10.0, 2.0, mass=MASS, inertia=INERTIA, cg=CG)
    np.testing.assert_array_equal(f.T12, g.T12)
    other = InvertedSliderCrank(A_, D_ + 0.1, C_)
    with pytest.raises(InputError, match="motion"):
        inverted_slidercrank_forces(other, m, mass=MASS, inertia=INERTIA, cg=CG)


@pytest.mark.parametrize(
    ("kw", "field"),
    [
        ({"mass": (1.0, 2.0)}, "mass"),
        ({"mass": (1.0, -2.0, 1.0)}, "mass m3"),
        ({"inertia": (0.1, 0.1, np.nan)}, "inertia IG4"),
        ({"friction": "dry"}, "friction"),
        ({"friction": "coulomb", "mu": -0.1}, "mu"),
        ({"gravity": -9.81}, "gravity"),
        ({"load_torque4": np.ones(3)}, "load_torque4"),
        ({"external_forces": [(5, 0.0, 1.0)]}, "external_forces[0] link"),
        ({"form": 3}, "form"),
    ],
)
def test_bad_input_is_refused_naming_the_field(isc, kw, field):
    args = {"mass": MASS, "inertia": INERTIA, "cg": CG} | kw
    with pytest.raises(InputError) as caught:
        isc.dynamics(THETA, 10.0, **args)
    assert str(caught.value).startswith(field + ":"), str(caught.value)


def test_wrong_model_or_motion_types_are_refused(isc):
    with pytest.raises(InputError, match="isc"):
        inverted_slidercrank_dynamics("shaper", THETA, 1.0, mass=MASS, inertia=INERTIA, cg=CG)
    with pytest.raises(InputError, match="motion"):
        inverted_slidercrank_forces(isc, {"theta2": THETA}, mass=MASS, inertia=INERTIA, cg=CG)


def test_short_repr_and_labelled_table():
    from machdyn.units import UnitSystem

    isc = InvertedSliderCrank(0.1, 0.3)
    isc.units = UnitSystem(length="m")
    f = isc.dynamics(THETA, 10.0, mass=MASS, inertia=INERTIA, cg=(0.05, 0, 0.1))
    text = repr(f)
    assert text.startswith("InvertedSliderCrankForces(24 samples, 24 ok") and len(text) < 1500
    assert "T12" in text and "normal" in text
    df = f.to_pandas()
    assert len(df) == THETA.size and df["ok"].all()
    labelled = [c for c in df.columns if c.startswith(("T12 [", "F32_x [", "N [", "C43 ["))]
    assert len(labelled) == 4, list(df.columns)
    np.testing.assert_allclose(df[labelled[0]], f.T12)  # SI: shown as computed
    plain = InvertedSliderCrank(2.0, 4.0).dynamics(0.3, 1.0, mass=MASS, inertia=INERTIA, cg=CG)
    assert list(plain.to_pandas().columns)[:2] == ["theta2", "T12"] and len(plain) == 1
    assert isinstance(plain, InvertedSliderCrankForces)


SHAPER = """machdyn = 1
title = "Shaper"
gravity = true

[units]
length = "mm"
mass = "kg"
force = "N"
torque = "N*m"
angular_velocity = "rpm"

[inverted_slider_crank.shaper]
crank = 100
ground = 300
offset = 20

[inverted_slider_crank.shaper.motion]
theta2 = [0, 360, 45]
omega2 = "60 rpm"

[inverted_slider_crank.shaper.link2]
mass = 2.0
inertia = "0.01 kg*m^2"
cg = 50

[inverted_slider_crank.shaper.link3]
mass = 0.5
inertia = "0.001 kg*m^2"

[inverted_slider_crank.shaper.link4]
mass = 6.0
inertia = "0.2 kg*m^2"
cg = [250, 10]

[inverted_slider_crank.shaper.loads]
torque4 = "-40 N*m"
friction = "coulomb"
mu = 0.1
"""


def test_a_machine_file_prints_the_forces_in_its_units(tmp_path, capsys):
    """`machdyn run` of an inverted slider-crank part with masses: the forces table, in N and
    N·m, equals the same machine computed here in SI (m, kg, rad/s)."""
    import json

    from machdyn.cli import main

    path = tmp_path / "shaper.toml"
    path.write_text(SHAPER, encoding="utf-8")
    assert main(["run", str(path), "--json"]) == 0
    table = json.loads(capsys.readouterr().out)["parts"]["shaper"]["tables"]["forces"]
    cols = {
        name: np.array([row[k] for row in table["rows"]]) for k, name in enumerate(table["columns"])
    }
    si = InvertedSliderCrank(0.1, 0.3, 0.02).dynamics(
        np.radians(np.arange(0.0, 361.0, 45.0)),
        2 * np.pi,
        mass=(2.0, 0.5, 6.0),
        inertia=(0.01, 0.001, 0.2),
        cg=(0.05, 0.0, 0.25 + 0.01j),
        gravity=9.80665,
        load_torque4=-40.0,
        friction="coulomb",
        mu=0.1,
    )
    np.testing.assert_allclose(cols["T12 [N*m]"], si.T12, rtol=1e-9)
    np.testing.assert_allclose(cols["F32_y [N]"], si.F32.imag, rtol=1e-9)
    np.testing.assert_allclose(cols["N [N]"], si.N, rtol=1e-9)
    np.testing.assert_allclose(cols["C43 [N*m]"], si.couple, rtol=1e-9, atol=1e-12)
    assert main(["run", str(path)]) == 0
    assert "Forces on shaper" in capsys.readouterr().out


def test_the_report_of_a_machine_file_shows_the_forces_in_its_units(tmp_path, capsys):
    """`machdyn report` of the same file: peak crank torque in N·m as computed here in SI."""
    import re

    from machdyn.cli import main
    from machdyn.report.slidercrank import slidercrank_sweep

    path, out = tmp_path / "shaper.toml", tmp_path / "shaper.html"
    path.write_text(SHAPER, encoding="utf-8")
    assert main(["report", str(path), "-o", str(out)]) == 0
    page = out.read_text(encoding="utf-8")
    isc = InvertedSliderCrank(0.1, 0.3, 0.02)
    th = slidercrank_sweep(isc, 360)
    si = isc.dynamics(
        th,
        2 * np.pi,
        mass=(2.0, 0.5, 6.0),
        inertia=(0.01, 0.001, 0.2),
        cg=(0.05, 0.0, 0.25 + 0.01j),
        gravity=9.80665,
        load_torque4=-40.0,
        friction="coulomb",
        mu=0.1,
    )
    j = int(np.argmax(si.T12))
    shown = re.search(r'data-key="T12_max"[^>]*>(.*?)</td>', page).group(1)
    assert shown.startswith(f"{si.T12[j]:.4g} N·m at θ2 = {np.degrees(th[j]):.1f}°"), shown
    states = re.findall(r'data-check="[\w:]+".*?class="state">([\w ]+)<', page, re.S)
    assert len(states) == 11 and set(states) == {"pass"}  # no k: no flywheel check
