"""Newton–Euler forces group by group: closed forms against the LU, wedging at a slider.

The force system of a linkage splits into its Assur groups (block triangular);
drivers, RRR and RRP dyads are solved in closed form by
machdyn.linkage.newton_euler — the same functions FourBar.dynamics and
SliderCrank.dynamics call — and every other block by a batched LU. Here the
closed forms are checked against the LU on the same systems (the LU forced by
switching the closed forms off), and Coulomb friction's wedging (two normal
forces satisfying the equations) is flagged as SliderCrank.dynamics flags it.
"""

from __future__ import annotations

import numpy as np
import pytest

from machdyn.dynamics import slidercrank_dynamics
from machdyn.linkage import FORCE_REASONS, Linkage
from machdyn.linkage import forces as forces_module
from machdyn.massprops import point_mass, rod
from machdyn.slidercrank import SliderCrank
from test_linkage import _energy_rates, watt_ii
from test_linkage_groups import jansen_leg, press

THETA = np.radians(np.arange(0.0, 360.0, 5.0)) + 0.1


def with_masses(lk: Linkage) -> Linkage:
    """The same drawing with a mass, inertia and an off-line centre on every link."""
    out = Linkage(dict(lk.points)).ground(*lk.ground_points)
    for k, ln in enumerate(lk.links.values()):
        mass = {"mass": 1.0 + 0.3 * k, "inertia": 0.2 + 0.05 * k, "cg": 0.4 + 0.1j * (k % 3)}
        out.link(ln.name, *ln.points, **mass)
    for j in lk.joints:
        if j.kind == "slider":
            out.slider(*j.links, j.points[0], j.direction, through=j.through, name=j.name)
    return out.drive(*lk.drivers)


def lu_only(lk: Linkage, m, **kw):
    """The forces with every block solved by the LU (the closed forms switched off)."""
    original = forces_module._closed_form
    forces_module._closed_form = lambda *args: None
    try:
        return lk.forces(m, **kw)
    finally:
        forces_module._closed_form = original


@pytest.mark.parametrize("build", [watt_ii, jansen_leg, press])
def test_closed_form_groups_equal_the_lu(build):
    lk = with_masses(build())
    m = lk.solve(THETA, velocity=4.0, acceleration=-1.5)
    kw = {"gravity": 9.81, "external_torques": {lk.drivers[0]: 2.0}}
    if "ram" in lk._sliders:
        kw["coulomb"] = {"ram": 0.2}
    ours, ref = lk.forces(m, **kw), lu_only(lk, m, **kw)
    assert (ours.ok == ref.ok).all() and ours.ok.sum() > 0.9 * m.ok.sum()
    for table in ("pins", "driver", "normal", "couple"):
        for k, v in getattr(ref, table).items():
            w = getattr(ours, table)[k]
            scale = max(np.nanmax(np.abs(v)), 1.0)
            assert np.nanmax(np.abs(w - v)) <= 1e-9 * scale, (table, k)
    # and the power balance holds, written here: T ω = d(KE + PE)/dt (+ friction's loss)
    if "coulomb" not in kw:
        dke, dpe = _energy_rates(lk, m, 9.81)
        power = ours.driver[lk.drivers[0]] * 4.0 + 2.0 * 4.0
        good = ours.ok
        assert np.abs(power - dke - dpe)[good].max() <= 1e-9 * np.abs(dke[good]).max()


def issue_slider_crank() -> tuple[Linkage, float]:
    """Crank 0.08, rod 0.11 (issue #10): drawn at θ2 = 77.5°, where with μ = 1 it wedges."""
    theta2 = np.radians(77.5)
    A = 0.08 * np.exp(1j * theta2)
    B = A.real + np.sqrt(0.11**2 - A.imag**2)
    lk = Linkage({"O2": 0j, "A": A, "B": B}).ground("O2")
    lk.link("crank", "O2", "A", body=rod(0.5, 0.08)).link("rod", "A", "B", body=rod(0.4, 0.11))
    lk.link("block", "B", body=point_mass(0.3))
    return lk.slider("block", "ground", "B", 0.0, name="guide").drive("crank"), theta2


def test_coulomb_wedging_is_flagged_as_slidercrank_dynamics_flags_it():
    lk, theta2 = issue_slider_crank()
    theta = theta2 + np.radians([-60.0, -30.0, 0.0, 30.0])
    m = lk.solve(theta, velocity=150.0)
    f = lk.forces(m, coulomb={"guide": 1.0}, external_forces=[("block", "B", -600.0)])
    ref = slidercrank_dynamics(
        SliderCrank(0.08, 0.11),
        theta,
        150.0,
        mass=(0.5, 0.4, 0.3),
        inertia=(0.5 * 0.08**2 / 12, 0.4 * 0.11**2 / 12),
        cg=(0.04, 0.055),
        load_force4=-600.0,
        friction="coulomb",
        mu=1.0,
    )
    assert not f.ok[2] and f.reason[2] == FORCE_REASONS["wedging"]
    assert not ref.ok[2]  # SliderCrank.dynamics: jammed there too
    assert (f.ok == ref.ok).all()
    good = f.ok
    np.testing.assert_allclose(f.driver["crank"][good], ref.T12[good], rtol=1e-9)
    assert np.isnan(f.driver["crank"][~good]).all()


def test_coulomb_friction_at_a_dead_centre_opposes_the_impending_slip():
    """At θ2 = 0, π, 2π the block stops (ḋ is 0 but for rounding) and is about to move with
    d̈ = ω²(−a cos θ2 − a²/b) (by hand, sin θ2 = 0, in-line): friction along the guide is
    −μ|N| sign(d̈), never the sign of the rounding noise (as SliderCrank.dynamics)."""
    a, b, w2, mu = 50.0, 200.0, 314.159, 0.3
    A = a * np.exp(1j * np.radians(40.0))
    lk = Linkage({"O2": 0j, "A": A, "B": A.real + np.sqrt(b**2 - A.imag**2)}).ground("O2")
    lk.link("crank", "O2", "A", body=rod(1.0, a)).link("rod", "A", "B", body=rod(2.0, b))
    lk.link("block", "B", body=point_mass(1.5))
    lk.slider("block", "ground", "B", 0.0, name="guide").drive("crank")
    th = np.radians([0.0, 180.0, 360.0])
    m = lk.solve(th, velocity=w2)
    f = lk.forces(
        m, gravity=9810.0, coulomb={"guide": mu}, external_forces=[("block", "B", -2000.0)]
    )
    d_ddot = w2**2 * (-a * np.cos(th) - a * a / b)
    assert f.ok.all()
    friction = f.sliders["guide"].real  # the guide is along +x: its force's x part
    np.testing.assert_allclose(
        friction, -mu * np.abs(f.normal["guide"]) * np.sign(d_ddot), rtol=1e-12
    )


def test_coulomb_wedging_of_two_sliders_is_each_slider_cranks_own():
    """A V-twin: one crank, two rods, two blocks on guides at 0° and 90°, no gravity.

    Each rod-and-block dyad's forces are set by its own equilibrium, so the pair has
    one answer exactly where each slider-crank alone has one (SliderCrank.dynamics, the
    second in a frame turned by 90°), and the crank torque is the sum of the two. Every
    set of the two normal forces' signs is tried: a sample wedges where either does.
    """
    a, b1, b2, w2, mu = 0.08, 0.11, 0.13, 150.0, 1.0
    theta = np.radians(np.arange(0.0, 360.0, 7.5)) + 0.05
    A = a * np.exp(1j * theta[0])
    B1 = A.real + np.sqrt(b1**2 - A.imag**2)
    B2 = 1j * (A.imag + np.sqrt(b2**2 - A.real**2))
    lk = Linkage({"O2": 0j, "A": A, "B1": B1, "B2": B2}).ground("O2")
    lk.link("crank", "O2", "A", mass=0.5, inertia=1e-4, cg=0j)  # centre on the pivot
    lk.link("rod1", "A", "B1", body=rod(0.4, b1)).link("rod2", "A", "B2", body=rod(0.45, b2))
    lk.link("block1", "B1", body=point_mass(0.3)).link("block2", "B2", body=point_mass(0.35))
    lk.slider("block1", "ground", "B1", 0.0, name="g1")
    lk.slider("block2", "ground", "B2", np.pi / 2, name="g2").drive("crank")
    m = lk.solve(theta, velocity=w2)
    f = lk.forces(
        m, coulomb={"g1": mu, "g2": mu}, external_forces=[("block1", "B1", -600.0),
                                                          ("block2", "B2", -450.0j)]
    )  # fmt: skip
    common = dict(mass=(0.5, None, None), inertia=(1e-4, None), friction="coulomb", mu=mu)

    def alone(b, mass, theta_local, load):
        kw = {**common, "mass": (0.5, mass, 0.3 if b == b1 else 0.35)}
        kw["inertia"] = (1e-4, mass * b**2 / 12)
        return slidercrank_dynamics(SliderCrank(a, b), theta_local, w2, cg=(0.0, b / 2),
                                    load_force4=load, **kw)  # fmt: skip

    one = alone(b1, 0.4, theta, -600.0)
    two = alone(b2, 0.45, theta - np.pi / 2, -450.0)
    assert (~one.ok).any() or (~two.ok).any()  # some sample wedges
    assert (f.ok == (one.ok & two.ok)).all()
    jammed = {FORCE_REASONS["wedging"], FORCE_REASONS["coulomb"]}  # two answers, or none
    assert {f.reason[k] for k in np.flatnonzero(~f.ok)} <= jammed
    good = f.ok
    assert good.sum() > theta.size // 3
    np.testing.assert_allclose(f.driver["crank"][good], (one.T12 + two.T12)[good], rtol=1e-9)


def test_coulomb_friction_at_rest_with_no_acceleration_is_the_frictionless_answer():
    """Standing still (ω2 = 0, α2 = 0) no slip is impending from the motion, so the guide's
    friction is zero and the forces are the frictionless ones — also where the normal
    force is negative (the block pressed on the guide's other side), which every set of
    signs must then accept rather than call self-locking."""
    lk, _ = issue_slider_crank()
    theta = np.radians([30.0, 60.0, 120.0, 200.0, 300.0])
    m = lk.solve(theta, velocity=0.0)
    load = [("block", "B", -50.0)]
    f = lk.forces(m, gravity=9.81, coulomb={"guide": 0.3}, external_forces=load)
    smooth = lk.forces(m, gravity=9.81, external_forces=load)
    assert f.ok.all() and (smooth.normal["guide"] < 0).any()
    np.testing.assert_allclose(f.driver["crank"], smooth.driver["crank"], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(f.sliders["guide"], smooth.sliders["guide"], rtol=1e-12, atol=1e-12)
