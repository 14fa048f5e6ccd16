"""machdyn.sensitivity: derivatives by implicit differentiation, against central differences.

The reference re-solves the perturbed model with its own solver (FourBar.solve,
SliderCrank.solve, Linkage.solve and the Newton–Euler force analysis) and
differences the results: it shares no code with the implicit differentiation.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import machdyn
from machdyn.dynamics import fourbar_dynamics, slidercrank_dynamics
from machdyn.errors import InputError
from machdyn.linkage import Linkage

H = 1e-6
THETA = np.radians(np.arange(0.0, 360.0, 15.0))


def central(solve, base, k, h=H, wrap=()):
    """Central difference of every output of ``solve(params)`` with respect to params[k]."""
    up, down = list(base), list(base)
    up[k] += h
    down[k] -= h
    hi, lo = solve(up), solve(down)
    out = {}
    for name in hi:
        diff = hi[name] - lo[name]
        if name in wrap:
            diff = np.remainder(diff + math.pi, 2 * math.pi) - math.pi
        out[name] = diff / (2 * h)
    return out


def assert_matches(sens, solve, base, wrap=(), rel=2e-7):
    for k in range(len(base)):
        fd = central(solve, base, k, wrap=wrap)
        for name, expected in fd.items():
            got = sens.derivative[name][:, k]
            scale = np.abs(sens.derivative[name]).max() + 1.0
            assert np.abs(got - expected).max() < rel * scale, (sens.dimensions[k], name)


def test_fourbar_against_central_differences():
    masses = dict(mass=(1.0, 2.0, 3.0), inertia=(0.1, 0.5, 0.8), cg=(2 + 0.3j, 3.5 - 1j, 3.0))

    def solve(p):
        fb = machdyn.FourBar(*p[:4], coupler=(p[4], p[5]))
        m = fb.solve(THETA, 10.0, 3.0)
        torque = fourbar_dynamics(fb, THETA, 10.0, 3.0, gravity=9.81, load_torque4=-2.0, **masses)
        return {
            "theta3": m.theta3, "theta4": m.theta4, "omega3": m.omega3, "omega4": m.omega4,
            "alpha3": m.alpha3, "alpha4": m.alpha4, "coupler": m.coupler, "B": m.B,
            "coupler_velocity": m.coupler_velocity, "coupler_acceleration": m.coupler_acceleration,
            "T12": torque.T12,
        }  # fmt: skip

    base = [8.0, 4.0, 7.0, 6.0, 5.0, 0.5]
    fb = machdyn.FourBar(*base[:4], coupler=(base[4], base[5]))
    s = machdyn.sensitivity(fb, THETA, omega2=10.0, alpha2=3.0, gravity=9.81, load=-2.0, **masses)
    assert s.dimensions == ("r1", "r2", "r3", "r4", "p", "delta") and s.ok.all()
    nominal = solve(base)
    assert np.allclose(s.nominal["T12"], nominal["T12"], rtol=1e-12, atol=1e-9)  # VW = NE
    assert_matches(s, solve, base, wrap=("theta3", "theta4"))


def test_slidercrank_against_central_differences():
    masses = dict(mass=(1.0, 2.0, 3.0), inertia=(0.1, 0.5), cg=(1 + 0.3j, 3 - 0.2j))

    def solve(p):
        sc = machdyn.SliderCrank(*p[:3], point=(p[3], p[4]))
        m = sc.solve(THETA, 10.0, 3.0)
        f = slidercrank_dynamics(sc, THETA, 10.0, 3.0, gravity=9.81, load_force4=-2.0, **masses)
        return {
            "theta3": m.theta3, "d": m.d, "omega3": m.omega3, "d_dot": m.d_dot,
            "alpha3": m.alpha3, "d_ddot": m.d_ddot, "coupler": m.coupler, "T12": f.T12,
            "coupler_acceleration": m.coupler_acceleration,
        }  # fmt: skip

    base = [2.0, 6.0, 0.5, 2.0, 0.3]
    sc = machdyn.SliderCrank(*base[:3], point=(base[3], base[4]))
    s = machdyn.sensitivity(sc, THETA, omega2=10.0, alpha2=3.0, gravity=9.81, load=-2.0, **masses)
    assert s.dimensions == ("crank", "coupler", "offset", "p", "delta")
    # at θ2 = 0 the slider is at a + √(b² − c²): ∂d/∂a = 1, ∂d/∂b = b/√(b² − c²)
    assert s.of("d", "crank")[0] == pytest.approx(1.0, abs=1e-12)
    assert s.of("d", "coupler")[0] == pytest.approx(6.0 / math.sqrt(36.0 - 0.25), rel=1e-12)
    assert_matches(s, solve, base, wrap=("theta3",))


B = complex(7.625, math.sqrt(49 - 3.625**2))
WATT = {"O2": 0j, "O4": 6 + 0j, "O6": 10 + 3j, "A": 1.5 + 0j, "B": 4.75 + 3.7997j,
        "C": 9.3316 + 1.3641j, "D": 7.5444 + 5.494j, "P": 3.125 + 2.8998j}  # fmt: skip


def fourbar_linkage(pts):
    return (
        Linkage(pts).ground("O2", "O4").link("crank", "O2", "A").link("coupler", "A", "B", "P")
        .link("rocker", "O4", "B").drive("crank")
    )  # fmt: skip


def watt(pts):
    return (
        Linkage(pts).ground("O2", "O4", "O6").link("crank", "O2", "A")
        .link("coupler", "A", "B", "P").link("rocker", "O4", "B", "C")
        .link("coupler2", "C", "D").link("output", "O6", "D").drive("crank")
    )  # fmt: skip


def slider_crank(pts):
    return (
        Linkage(pts).ground("O2").link("crank", "O2", "A").link("rod", "A", "B").link("block", "B")
        .slider("block", "ground", "B", 0.0, name="guide").drive("guide")
    )  # fmt: skip


def elbow(pts):
    return (
        Linkage(pts).ground("O2", "O4").link("crank", "O2", "A").link("coupler", "A", "B")
        .link("rocker", "O4", "B").motor("elbow", "A").drive("elbow")
    )  # fmt: skip


@pytest.mark.parametrize(
    ("build", "points", "values", "rate"),
    [
        (fourbar_linkage, {"O2": 0j, "O4": 8 + 0j, "A": 4 + 0j, "B": B, "P": 6 + 3j}, THETA, 10.0),
        (watt, WATT, np.radians(np.arange(0.0, 360.0, 20.0)), 5.0),
        (slider_crank, {"O2": 0j, "A": 2j, "B": 6 + 0.5j}, np.linspace(4.5, 7.0, 6), 1.0),
        (elbow, {"O2": 0j, "O4": 8 + 0j, "A": 4 + 0j, "B": B}, np.radians([45, 55, 65.0]), 1.0),
    ],
    ids=["four-bar", "Watt six-bar", "slider-driven", "motor between links"],
)
def test_linkage_against_re_solving_the_perturbed_drawing(build, points, values, rate):
    names = list(points)
    base = [c for p in names for c in (points[p].real, points[p].imag)]

    def solve(p):
        pts = {n: complex(p[2 * i], p[2 * i + 1]) for i, n in enumerate(names)}
        m = build(pts).solve(values, velocity=rate, acceleration=0.7)
        out = {}
        for k in m.theta:
            out[f"theta.{k}"], out[f"omega.{k}"], out[f"alpha.{k}"] = (
                m.theta[k],
                m.omega[k],
                m.alpha[k],
            )
        for k in m.points:
            out[f"point.{k}"] = m.points[k]
            out[f"velocity.{k}"] = m.point_velocity[k]
            out[f"acceleration.{k}"] = m.point_acceleration[k]
        return out

    s = machdyn.sensitivity(build(points), values, omega2=rate, alpha2=0.7)
    assert s.ok.all()
    assert s.dimensions == tuple(f"{p}.{a}" for p in names for a in ("x", "y"))
    nominal = solve(base)
    for name, value in nominal.items():
        assert np.allclose(s.nominal[name], value, atol=1e-10)
    assert_matches(s, solve, base)


def test_stack_up_bounds_the_re_solved_deviations():
    """Every corner of a small tolerance box, re-solved: within the worst case, near it."""
    fb = machdyn.FourBar(8, 4, 7, 6, coupler=(5, 0.5))
    t = {"r1": 1e-3, "r2": 1e-3, "r3": 2e-3, "r4": 1e-3}
    s = machdyn.sensitivity(fb, THETA, dimensions=list(t))
    worst = s.stack_up(t, "coupler")
    nominal = fb.solve(THETA).coupler
    seen = np.zeros(THETA.size)
    for signs in np.ndindex(2, 2, 2, 2):
        dims = [8 + (2 * signs[0] - 1) * 1e-3, 4 + (2 * signs[1] - 1) * 1e-3,
                7 + (2 * signs[2] - 1) * 2e-3, 6 + (2 * signs[3] - 1) * 1e-3]  # fmt: skip
        moved = machdyn.FourBar(*dims, coupler=(5, 0.5)).solve(THETA).coupler
        seen = np.maximum(seen, np.abs(moved - nominal))
    assert np.all(seen <= worst * (1 + 1e-2))  # the bound, up to second-order terms
    assert np.all(seen >= 0.5 * worst)  # and not loose (|Σ| ≥ … for aligned components)
    assert np.all(s.rss(t, "coupler") <= worst)


def test_toggle_samples_are_flagged():
    fb = machdyn.FourBar(6, 9, 3, 8)  # GRCR: θ2 limited by toggles of links 3 and 4
    rng = fb.input_range(1)
    s = machdyn.sensitivity(fb, [rng.lo, 0.5 * (rng.lo + rng.hi)])
    assert not s.ok[0] and s.ok[1]
    assert np.isnan(s.derivative["theta4"][0]).all() and "toggle" in s.reason[0]


def test_bad_requests():
    fb = machdyn.FourBar(8, 4, 7, 6)
    with pytest.raises(InputError, match="dimension"):
        machdyn.sensitivity(fb, [0.1], dimensions=["r5"])
    s = machdyn.sensitivity(fb, [0.1])
    with pytest.raises(InputError, match="output"):
        s.of("theta9", "r1")
    with pytest.raises(InputError, match="tolerances"):
        s.stack_up({"r1": -1.0}, "theta4")
    with pytest.raises(InputError, match="FourBar"):
        machdyn.sensitivity("fourbar", [0.1])
    rolling = (
        Linkage({"O2": (0, 0), "O3": (5, 0), "P": (2, 0), "Q": (5, 3)}).ground("O2", "O3")
        .link("w2", "O2", "P").link("w3", "O3", "Q").roll("w2", "O2", 2.0, "w3", "O3", 3.0)
        .drive("w2")
    )  # fmt: skip
    with pytest.raises(InputError, match="not differentiated"):
        machdyn.sensitivity(rolling, [0.1])


def test_closed_form_and_implicit_paths_agree():
    # a crank + RRR linkage is differentiated through its closed-form dyads (forward duals);
    # any other by implicit differentiation of its natural-coordinate constraints: two
    # derivations that share no code but the drawing
    from machdyn._linkage_sensitivity import implicit_sensitivity, linkage_sensitivity

    lk = watt(WATT)
    values = np.radians(np.arange(0.0, 360.0, 7.0))
    closed = linkage_sensitivity(lk, values, 3.0, -2.0)
    implicit = implicit_sensitivity(lk, values, 3.0, -2.0)
    assert closed[0] == implicit[0] and set(closed[2]) == set(implicit[2])
    for name, d in implicit[2].items():
        scale = max(1.0, float(np.abs(d).max()))
        assert np.allclose(closed[2][name], d, rtol=0, atol=1e-9 * scale), name
        assert np.allclose(closed[1][name], implicit[1][name], atol=1e-12), name


def test_linkage_at_its_toggle_is_flagged():
    fb = machdyn.FourBar(6, 9, 3, 8)  # GRCR: the RRR dyad (coupler, rocker) aligns at the limits
    rng = fb.input_range(1)
    mid = 0.5 * (rng.lo + rng.hi)
    m = fb.solve([mid], form=1)
    A = 9 * np.exp(1j * mid)
    pts = {"O2": 0j, "O4": 6 + 0j, "A": complex(A), "B": complex(A + 3 * np.exp(1j * m.theta3[0]))}
    lk = (Linkage(pts).ground("O2", "O4").link("crank", "O2", "A").link("coupler", "A", "B")
          .link("rocker", "O4", "B").drive("crank"))  # fmt: skip
    s = machdyn.sensitivity(lk, [rng.lo, mid])
    assert not s.ok[0] and s.ok[1]
    assert np.isnan(s.derivative["theta.rocker"][0]).all()
    assert np.isfinite(s.derivative["theta.rocker"][1]).all()
