"""Tests of machdyn.virtual_work: kinetostatics by power, mechanical advantage.

References: the second course notes (seeds/003_*), "Simple KinetoStatic force
analysis" examples. Those examples print the velocity solutions but not the
final forces, so the expected forces below are worked by hand in each test
from the printed velocities (the arithmetic is shown).
"""

from __future__ import annotations

import numpy as np
import pytest

from machdyn.dynamics import fourbar_dynamics
from machdyn.errors import InputError, SingularityError
from machdyn.fourbar import FourBar
from machdyn.virtual_work import (
    fourbar_input_torque,
    mechanical_advantage,
    power,
    virtual_work,
)

G = 9.81


def test_loader_input_torque():
    """Notes 2, kinetostatics example 1 (Bobcat loader): 1000 kg at P.

    Printed velocities: θ̇2 = 0.5 rad/s, V_P = (8.896, 108.6) cm/s.
    By hand: T12·0.5 + (−9810 N)(1.086 m/s) = 0 → T12 = 9810·1.086/0.5 = 21307.32 N·m.
    (The notes stop before the number; 4 printed digits of V_Py → 4–5 digits here.)
    """
    t12 = virtual_work(0.5, [(-1000 * G * 1j, 0.08896 + 1.086j)])
    assert float(t12) == pytest.approx(21307.32, rel=1e-6)


def test_loader_velocities_printed_in_the_notes():
    """The loader's velocity step (notes 2, velocity example 1), redone here by hand:
    L1x: −141·0.5·sin45 + 100·θ̇4 = 0;  L1y: 141·0.5·cos45 + 120·θ̇3 = 0."""
    w2 = 0.5
    w4 = 141 * w2 * np.sin(np.radians(45)) / 100
    w3 = -141 * w2 * np.cos(np.radians(45)) / 120
    vp = 141 * w2 * 1j * np.exp(1j * np.radians(45)) + 200 * w3 * 1j * np.exp(1j * np.radians(135))
    assert round(w4, 4) == 0.4985 and round(w3, 4) == -0.4154
    assert abs(vp.real - 8.896) < 5e-3  # the notes print 8.896 (from the rounded θ̇3)
    assert round(vp.imag, 1) == 108.6


def test_bike_suspension_shock_force():
    """Notes 2, kinetic force analysis (bike rear suspension): 500 N up at the axle P,
    V_P = (5, 125) cm/s, ṙ2 = 75 cm/s. By hand: F·75 + 500·125 = 0 → F = −833.33 N
    (along +r2: the shock must push against the extension, i.e. it is compressed)."""
    force = virtual_work(75.0, [(500j, 5 + 125j)])
    assert float(force) == pytest.approx(-2500 / 3, rel=1e-12)
    # the axle load is 0.6 of the shock force: MA = v_in / v_out
    assert float(mechanical_advantage(75.0, 125.0)) == pytest.approx(0.6)


def test_trebuchet_force_at_p():
    """Notes 2, floating-arm trebuchet: 100 kg on the vertical slider (end of r2,
    θ2 = −90°, ṙ2 = 250 cm/s, so it moves at −250 j cm/s), V_P = (360.75, 374.84) cm/s.
    Force at P perpendicular to the bar (θ3 = 150°, normal n = e^{j60°}):
    V_P·n = 360.75·0.5 + 374.84·0.8660254 = 504.996 cm/s; weight power = 981·250.
    F_n = −981·250 / 504.996 = −485.65 N: 485.65 N along e^{j240°}, against P's motion."""
    n = np.exp(1j * np.radians(60))
    f = virtual_work(360.75 + 374.84j, [(-100 * G * 1j, -250j)], direction=n)
    assert float(f) == pytest.approx(-981 * 250 / 504.996, rel=1e-5)
    assert round(float(f), 1) == -485.6


def test_exercise_machine_equivalent_input_torque():
    """Notes 2, exercise machine: T4 = −100 N·cm at θ̇4 = 20 rpm, θ̇2b = 10 rpm.
    T2·10 + (−100)·20 = 0 → T2 = 200 N·cm on link 2. The notes do not give the
    direction of r2a (where P sits on link 2) nor an answer, so the force at P is
    not checked; the equivalent torque on link 2 is (rpm cancel in the ratio)."""
    t2 = virtual_work(10.0, [(-100.0, 20.0)])
    assert float(t2) == pytest.approx(200.0)


def test_power_and_superposition():
    assert float(power(3 + 4j, 2 - 1j)) == 2.0
    assert float(power(2.0, -3.0)) == -6.0
    # superposition: the input effort for two loads is the sum of each
    a = virtual_work(2.0, [(1 + 2j, 3 - 1j)])
    b = virtual_work(2.0, [(-5.0, 0.5)])
    both = virtual_work(2.0, [(1 + 2j, 3 - 1j), (-5.0, 0.5)])
    assert float(both) == pytest.approx(float(a + b))


def test_zero_mass_equals_newton_euler_kinetostatics():
    fb = FourBar(8, 4, 7, 6)
    theta2 = np.radians(np.arange(0.0, 360.0, 5.0))
    loads = [(3, 2.5 + 1j, 10 - 20j), (4, 4.0, -3 + 1j)]
    vw = fourbar_input_torque(
        fb, theta2, 1.0, load_torque4=-7.0, external_forces=loads, external_torques=[(3, 2.0)]
    )
    ne = fourbar_dynamics(
        fb,
        theta2,
        1.0,
        mass=(0, 0, 0),
        inertia=(0, 0, 0),
        cg=(0, 0, 0),
        load_torque4=-7.0,
        external_forces=loads,
        external_torques=[(3, 2.0)],
    )
    assert vw.ok.all() and ne.ok.all()
    np.testing.assert_allclose(vw.T12, ne.T12, rtol=1e-10, atol=1e-10 * np.max(np.abs(ne.T12)))


def test_with_inertia_equals_newton_euler():
    fb = FourBar(8, 4, 7, 6)
    theta2 = np.radians(np.arange(0.0, 360.0, 5.0))
    kw = dict(
        mass=(1.2, 2.5, 1.8),
        inertia=(0.8, 3.1, 1.4),
        cg=(1.5 + 0.3j, 3.0 - 0.8j, 2.5 + 0.4j),
        gravity=G,
        load_torque4=-3.0,
        external_forces=[(3, 2.0 + 1.0j, 4.0 - 7.0j)],
    )
    vw = fourbar_input_torque(fb, theta2, 12.0, -4.0, **kw)
    ne = fourbar_dynamics(fb, theta2, 12.0, -4.0, **kw)
    np.testing.assert_allclose(vw.T12, ne.T12, atol=1e-10 * np.max(np.abs(ne.T12)))
    assert len(vw.to_pandas()) == theta2.size


def test_statics_at_rest_with_gravity():
    """ω2 = 0: the kinematic coefficients still give the holding torque."""
    fb = FourBar(6, 2, 7, 9)
    theta2 = np.radians([10.0, 80.0, 200.0])
    kw = dict(mass=(1, 2, 3), inertia=(1, 1, 1), cg=(1, 3.5, 4.5), gravity=G)
    vw = fourbar_input_torque(fb, theta2, 0.0, **kw)
    ne = fourbar_dynamics(fb, theta2, 0.0, **kw)
    np.testing.assert_allclose(vw.T12, ne.T12, rtol=1e-12)
    # link 2 alone: holding torque of its own weight is m g c cos θ2
    only2 = fourbar_input_torque(
        fb, theta2, mass=(1, 0, 0), inertia=(1, 0, 0), cg=(1, 0, 0), gravity=G
    )
    np.testing.assert_allclose(only2.T12, G * np.cos(theta2), rtol=1e-12)


def test_mechanical_advantage_matches_fourbar():
    fb = FourBar(8, 4, 7, 6)
    theta2 = np.radians([20.0, 75.0, 130.0])
    m = fb.solve(theta2, omega2=1.0)
    ma = mechanical_advantage(1.0, m.omega4)
    np.testing.assert_allclose(ma, fb.mechanical_advantage(theta2), rtol=1e-12)
    assert np.isinf(mechanical_advantage(1.0, 0.0))


def test_toggle_flagged_in_input_torque():
    fb = FourBar(6, 9, 3, 8)
    rng_ = fb.input_range(form=1)
    out = fourbar_input_torque(fb, np.array([rng_.lo, 0.5 * (rng_.lo + rng_.hi)]), load_torque4=1.0)
    assert out.ok.tolist() == [False, True]
    assert "singular" in out.reason[0]


def test_bad_input():
    with pytest.raises(InputError) as err:
        virtual_work(1 + 1j, [(1.0, 1.0)])
    assert err.value.field == "direction"
    with pytest.raises(InputError):
        virtual_work(1 + 1j, [(1.0, 1.0)], direction=0)
    with pytest.raises(InputError):
        virtual_work(1.0, [(1.0,)])
    with pytest.raises(InputError):
        virtual_work(float("nan"), [])
    with pytest.raises(SingularityError):
        virtual_work(np.array([1.0, 0.0]), [(1.0, 1.0)])
    with pytest.raises(SingularityError):
        mechanical_advantage(0.0, 0.0)
    with pytest.raises(InputError):
        mechanical_advantage(1j, 1.0)
    with pytest.raises(InputError):
        fourbar_input_torque(FourBar(8, 4, 7, 6), 0.3, mass=(1, 2), inertia=(1, 1, 1))


def test_pint_quantities_in_si_base_units():
    pint = pytest.importorskip("pint")
    u = pint.UnitRegistry()
    t12 = virtual_work(
        0.5 * u.rad / u.s,
        [(-1000 * u.kg * 9.81 * u.m / u.s**2 * 1j, (8.896 + 108.6j) * u.cm / u.s)],
    )
    assert float(t12) == pytest.approx(21307.32, rel=1e-6)  # N·m


def test_fourbar_mechanical_advantage_by_finite_differences():
    """Point-to-point MA against central differences of positions (no velocity code)."""
    from machdyn.virtual_work import fourbar_mechanical_advantage

    fb = FourBar(8, 4, 7, 6)
    theta2 = np.radians(np.arange(10.0, 360.0, 25.0))
    d_in, d_out = np.exp(1j * 0.3), np.exp(1j * 2.0)
    ma = fourbar_mechanical_advantage(fb, theta2, (2, 3.0 + 0.5j, d_in), (4, 4.0 - 1j, d_out))

    def points(t):
        m = fb.solve(t)
        e2 = m.A / 4
        e4 = (m.B - 8) / 6
        return (3.0 + 0.5j) * e2, 8 + (4.0 - 1j) * e4

    h = 1e-6
    (pi_p, po_p), (pi_m, po_m) = points(theta2 + h), points(theta2 - h)
    v_in = power(d_in, (pi_p - pi_m) / (2 * h))
    v_out = power(d_out, (po_p - po_m) / (2 * h))
    np.testing.assert_allclose(ma, v_in / v_out, rtol=1e-6)
    # link to link: the FourBar method (instant centres there)
    np.testing.assert_allclose(
        fourbar_mechanical_advantage(fb, theta2),
        fb.mechanical_advantage(theta2, method="instant_centres"),
        rtol=1e-10,
    )
    with pytest.raises(InputError):
        fourbar_mechanical_advantage(fb, theta2, 5)
    with pytest.raises(InputError):
        fourbar_mechanical_advantage(fb, theta2, (3, 1.0))
    with pytest.raises(InputError):
        fourbar_mechanical_advantage(fb, theta2, (3, 1.0, 0.0))


def test_flagged_samples_with_loads_on_links_3_and_4():
    """Review finding 1: masses on links 3 and 4 and a point load on the coupler, over a
    batch with an unassemblable sample (60° is outside this GCRR's input range) and a
    toggle. The flagged samples hold NaN with a reason; the others equal Newton–Euler
    (which does not share the virtual-work code path)."""
    fb = FourBar(8, 6, 3, 4)
    rng_ = fb.input_range(form=1)
    theta2 = np.array([0.0, np.radians(30.0), np.radians(60.0), rng_.hi])
    kw = dict(
        mass=(1.0, 1.5, 2.0),
        inertia=(1.0, 0.5, 0.8),
        cg=(1.0, 1.0 + 0.5j, 2.0),
        gravity=G,
        external_forces=[(3, 1.0, 1j), (4, 2.0 - 0.5j, 3.0 - 2.0j)],
        external_torques=[(4, -1.5)],
    )
    vw = fourbar_input_torque(fb, theta2, 1.0, 0.5, **kw)
    ne = fourbar_dynamics(fb, theta2, 1.0, 0.5, **kw)
    assert vw.ok.tolist() == [True, True, False, False]
    assert "cannot be assembled" in vw.reason[2]
    assert "singular" in vw.reason[3] or "toggle" in vw.reason[3]
    assert np.isnan(vw.T12[2:]).all()
    np.testing.assert_allclose(vw.T12[:2], ne.T12[:2], rtol=1e-10)
    only_load = fourbar_input_torque(fb, theta2, external_forces=[(3, 1.0, 1j)])
    assert only_load.ok.tolist() == [True, True, False, False]
    assert np.isfinite(only_load.T12[:2]).all()


def test_mechanical_advantage_flags_unassemblable_samples():
    from machdyn.virtual_work import fourbar_mechanical_advantage

    fb = FourBar(8, 6, 3, 4)
    ma = fourbar_mechanical_advantage(fb, np.radians([0.0, 60.0]), 2, (3, 1.0, 1.0))
    assert np.isfinite(ma[0]) and np.isnan(ma[1])


def test_shape_mismatch_names_the_field():
    """Review finding 9: these raised a bare numpy ValueError."""
    with pytest.raises(InputError) as err:
        virtual_work([1.0, 2.0], [(1.0, [1.0, 2.0, 3.0])])
    assert err.value.field == "loads[0] rate"
    with pytest.raises(InputError) as err:
        virtual_work(1.0, [(np.ones(2), 1.0), (1.0, np.ones(3))])
    assert err.value.field == "loads[1] rate"
    with pytest.raises(InputError) as err:
        mechanical_advantage([1.0, 2.0], [1.0, 2.0, 3.0])
    assert err.value.field == "output_rate"
    with pytest.raises(InputError) as err:
        fourbar_input_torque(FourBar(8, 4, 7, 6), [0.1, 0.2, 0.3], [1.0, 2.0])
    assert err.value.field == "omega2"
    # broadcasting that is legal still works: one load rate per sample
    out = virtual_work([1.0, 2.0], [(3.0, [1.0, 1.0])])
    np.testing.assert_allclose(out, [-3.0, -1.5])
