"""Tolerance analysis of a drawn Linkage (machdyn.tolerance on the family solver).

Checked against what shares no code with the family solver:

* every sample built as its own ``Linkage`` (its drawing constructed here from its
  dimensions with circle intersections written in this file) and solved by
  ``Linkage.solve`` — positions, rates, the worst sample of a run;
* ``Linkage.forces`` (Newton–Euler) for the driver's torque;
* implicit differentiation of the natural-coordinate constraints
  (``_linkage_sensitivity.implicit_sensitivity``) for the linearised prediction of
  drawn-coordinate tolerances;
* the FourBar tolerance (its own closed forms and its implicit sensitivities) on the
  four-bar loop of a Watt six-bar;
* Grashof's condition for the fraction of samples that cannot be assembled.
"""

from __future__ import annotations

import cmath
import math

import numpy as np
import pytest

import machdyn
from machdyn._linkage_family import Family
from machdyn._linkage_sensitivity import implicit_sensitivity
from machdyn.errors import InputError
from machdyn.linkage import Linkage

WATT = {"O2": 0j, "O4": 6 + 0j, "O6": 10 + 3j, "A": 1.5 + 0j, "B": 4.75 + 3.7997j,
        "C": 9.3316 + 1.3641j, "D": 7.5444 + 5.494j, "P": 3.125 + 2.8998j}  # fmt: skip
POSES = np.radians(np.arange(0.0, 360.0, 15.0))


def watt(pts, masses=False):
    m = (lambda k: dict(mass=0.5 + k, inertia=0.02 * (k + 1), cg=0.3 + 0.1j * k)) if masses else (
        lambda k: {})  # fmt: skip
    return (
        Linkage(pts).ground("O2", "O4", "O6").link("crank", "O2", "A", **m(0))
        .link("coupler", "A", "B", "P", **m(1)).link("rocker", "O4", "B", "C", **m(2))
        .link("coupler2", "C", "D", **m(3)).link("output", "O6", "D", **m(4)).drive("crank")
    )  # fmt: skip


def fourbar(pts):
    return (
        Linkage(pts).ground("O2", "O4").link("crank", "O2", "A").link("coupler", "A", "B", "P")
        .link("rocker", "O4", "B").drive("crank")
    )  # fmt: skip


def test_drawn_coordinates_against_the_moved_drawing():
    lk = watt(WATT)
    fam = Family(lk)
    rng = np.random.default_rng(9)
    moved = [{p: z + complex(*rng.uniform(-0.05, 0.05, 2)) for p, z in WATT.items()}
             for _ in range(6)]  # fmt: skip
    rows = np.array([[d[n[:-2]].real if n.endswith(".x") else d[n[:-2]].imag
                      for n in fam.names[: 2 * len(WATT)]] for d in moved])  # fmt: skip
    rows = np.hstack([rows, np.repeat(fam.nominal[None, 2 * len(WATT) :], len(moved), axis=0)])
    st, closes = fam.solve(fam.geometry(rows), [POSES, 1.0, 0.0], 0)
    assert closes.all()
    for k, drawing in enumerate(moved):
        own = watt(drawing).solve(POSES)
        for p in ("P", "D", "C", "B"):
            assert np.allclose(st.pos(fam.owner(p), p)[k], own.points[p], atol=1e-11)


def circles(A, a, C, c, B_drawn):
    """The intersection of |B − A| = a and |B − C| = c on the drawn B's side (by hand)."""
    d = C - A
    L = abs(d)
    x = (a * a - c * c + L * L) / (2 * L)
    y = math.sqrt(a * a - x * x)
    side = 1.0 if ((d.conjugate() * (B_drawn - A)).imag > 0) else -1.0
    return A + d / L * (x + 1j * side * y)


def watt_drawing(dims: dict[str, float]) -> dict[str, complex]:
    """The drawing (crank at 0) of the Watt six-bar with the given dimensions, built by hand."""
    O2 = WATT["O2"]
    O4 = O2 + dims["O2-O4"] * cmath.exp(1j * cmath.phase(WATT["O4"] - WATT["O2"]))
    O6 = O2 + dims["O6.p"] * cmath.exp(1j * (cmath.phase(O4 - O2) + dims["O6.delta"]))
    A = O2 + dims["O2-A"]
    B = circles(A, dims["A-B"], O4, dims["O4-B"], WATT["B"])
    P = A + dims["P.p"] * cmath.exp(1j * (cmath.phase(B - A) + dims["P.delta"]))
    C = O4 + dims["C.p"] * cmath.exp(1j * (cmath.phase(B - O4) + dims["C.delta"]))
    D = circles(C, dims["C-D"], O6, dims["O6-D"], WATT["D"])
    return {"O2": O2, "O4": O4, "O6": O6, "A": A, "B": B, "C": C, "D": D, "P": P}


def test_nominal_family_is_the_linkage_solver():
    for build, pts, rate in ((watt, WATT, 2.0), (fourbar, WATT, -1.5)):
        pts = {k: pts[k] for k in ("O2", "O4", "A", "B", "P")} if build is fourbar else pts
        lk = build(pts)
        fam = Family(lk)
        values = lk.drawn_inputs[lk.drivers[0]] + np.radians(np.arange(0.0, 40.0, 4.0))
        st, closes = fam.solve(fam.geometry(fam.nominal[None, :]), [values, rate, 0.7], 2)
        m = lk.solve(values, velocity=rate, acceleration=0.7)
        assert closes.all() and m.ok.all()
        for p in pts:
            owner = "ground" if p in lk.ground_points else fam.owner(p)
            assert np.allclose(st.pos(owner, p)[0], m.points[p], atol=1e-12)
            if owner != "ground":
                assert np.allclose(st.vel(owner, p)[0], m.point_velocity[p], atol=1e-11)
                assert np.allclose(st.acc(owner, p)[0], m.point_acceleration[p], atol=1e-10)
        for link in lk.links:
            assert np.allclose(np.angle(st.direction(link)[0] * np.exp(-1j * m.theta[link])), 0,
                               atol=1e-12)  # fmt: skip
            assert np.allclose(st.w[link], m.omega[link], atol=1e-11)


def test_driver_torque_against_newton_euler():
    lk = watt(WATT, masses=True)
    fam = Family(lk)
    m = lk.solve(POSES, velocity=3.0, acceleration=0.0)
    T = lk.forces(m, gravity=9.81).driver["crank"]
    st, _ = fam.solve(fam.geometry(fam.nominal[None, :]), [POSES, 3.0, 0.0], 2)
    assert np.allclose(fam.torque(st, 9.81, 3.0)[0], T, rtol=1e-9, atol=1e-9)


def test_each_sample_against_its_own_linkage_built_by_hand():
    lk = watt(WATT)
    fam = Family(lk)
    rng = np.random.default_rng(4)
    names = ["O2-O4", "O6.p", "O6.delta", "O2-A", "A-B", "P.p", "P.delta",
             "O4-B", "C.p", "C.delta", "C-D", "O6-D"]  # fmt: skip
    rows = np.repeat(fam.nominal[None, :], 12, axis=0)
    for name in names:
        rows[:, fam.names.index(name)] += rng.uniform(-0.05, 0.05, 12)
    st, closes = fam.solve(fam.geometry(rows), [POSES, 1.0, 0.0], 1)
    assert closes.all()
    for k, row in enumerate(rows):
        drawing = watt_drawing({n: row[fam.names.index(n)] for n in names})
        own = watt(drawing).solve(POSES, velocity=1.0)
        assert own.ok.all()
        for p in ("P", "D", "C"):
            assert np.allclose(st.pos(fam.owner(p), p)[k], own.points[p], atol=1e-11)
            assert np.allclose(st.vel(fam.owner(p), p)[k], own.point_velocity[p], atol=1e-10)
        assert np.allclose(np.angle(st.direction("output")[k] * np.exp(-1j * own.theta["output"])),
                           0, atol=1e-11)  # fmt: skip


def test_worst_sample_re_solved_as_its_own_linkage():
    tol = {"O2-A": 0.02, "A-B": 0.02, "P.p": 0.02, "P.delta": 0.01, "C-D": 0.02, "O6-D": 0.02}
    t = machdyn.tolerance(watt(WATT), tol, POSES, samples=3000, seed=5)
    nominal = watt(WATT).solve(POSES)
    fam = Family(watt(WATT))
    for out in ("point.P", "theta.output"):
        s = t.outputs[out]
        dims = dict(zip(fam.names, fam.nominal, strict=True))
        dims.update(zip(t.dimensions, s.worst_dimensions, strict=True))
        own = watt(watt_drawing(dims)).solve(POSES)
        if out == "point.P":
            peak = np.abs(own.points["P"] - nominal.points["P"]).max()
        else:
            peak = np.abs(np.angle(np.exp(1j * (own.theta["output"] - nominal.theta["output"]))))
            peak = peak.max()
        assert peak == pytest.approx(s.worst, rel=1e-5)
        assert s.worst == pytest.approx(float(s.peak.max()), rel=1e-6)


def test_linearised_prediction_of_coordinates_is_the_implicit_sensitivity():
    lk = watt(WATT)
    tol = {"B.x": 0.01, "B.y": 0.02, "O6.x": 0.01, "P.y": 0.01, "C.x": 0.005}
    outputs = ["point.P", "theta.output"]
    t = machdyn.tolerance(lk, tol, POSES, samples=20_000, seed=1, outputs=outputs)
    # implicit differentiation of the natural-coordinate constraints (no closed forms)
    dims, _, derivative, _ = implicit_sensitivity(lk, POSES, 1.0, 0.0)
    t_p = np.array([tol.get(d, 0.0) for d in dims])
    for out in ("point.P", "theta.output"):
        scaled = np.abs(derivative[out] * t_p)
        rss, stack = np.sqrt(np.sum(scaled**2, axis=1)), np.sum(scaled, axis=1)
        assert np.allclose(t.outputs[out].linear_std * 3.0, rss, rtol=1e-5, atol=1e-9)
        assert np.allclose(t.outputs[out].worst_case, stack, rtol=1e-5, atol=1e-9)
        # the Monte Carlo approaches the prediction for small tolerances
        mc, lin = t.outputs[out].std, t.outputs[out].linear_std
        assert np.allclose(mc, lin, rtol=0.04, atol=0.02 * lin.max())


def test_linearised_torque_against_newton_euler_of_re_drawn_linkages():
    # ∂T/∂p by central differences of Linkage.forces on drawings built here at p ± h
    lk = watt(WATT, masses=True)
    fam = Family(lk)
    nominal = dict(zip(fam.names, fam.nominal, strict=True))
    tol = {"O2-A": 0.01, "C-D": 0.02, "P.delta": 0.005, "O6.p": 0.01}
    t = machdyn.tolerance(lk, tol, POSES, samples=200, outputs=["torque.crank"], omega2=3.0,
                          gravity=9.81, distribution="uniform")  # fmt: skip
    stack = np.zeros(POSES.size)
    for name, tp in tol.items():
        h = 1e-6
        ends = []
        for sign in (1.0, -1.0):
            moved = watt(watt_drawing({**nominal, name: nominal[name] + sign * h}), masses=True)
            m = moved.solve(POSES, velocity=3.0, acceleration=0.0)
            ends.append(moved.forces(m, gravity=9.81).driver["crank"])
        stack += np.abs((ends[0] - ends[1]) / (2 * h)) * tp
    assert np.allclose(t.outputs["torque.crank"].worst_case, stack, rtol=1e-5, atol=1e-9)


def test_watt_four_bar_loop_agrees_with_fourbar_tolerance():
    lk = watt(WATT)
    A, B, P = WATT["A"], WATT["B"], WATT["P"]
    r3 = abs(B - A)
    delta = cmath.phase((P - A) / (B - A))
    for form in (1, 2):
        fb = machdyn.FourBar(6.0, 1.5, r3, abs(B - WATT["O4"]), coupler=(abs(P - A), delta))
        if abs(fb.solve([0.0], form=form).theta4[0] - cmath.phase(B - WATT["O4"])) < 1e-9:
            break
    pairs = {"r1": "O2-O4", "r2": "O2-A", "r3": "A-B", "r4": "O4-B", "p": "P.p", "delta": "P.delta"}
    tol = {"r1": 0.01, "r2": 0.01, "r3": 0.01, "r4": 0.01, "p": 0.01, "delta": 0.004}
    outputs = ["theta.rocker", "theta.coupler", "point.P"]
    mapped = {pairs[k]: v for k, v in tol.items()}
    ours = machdyn.tolerance(lk, mapped, POSES, samples=40_000, seed=7, outputs=outputs)
    theirs = machdyn.tolerance(fb, tol, POSES, samples=40_000, seed=8, form=form)
    for mine, other in (("theta.rocker", "theta4"), ("theta.coupler", "theta3"),
                        ("point.P", "coupler")):  # fmt: skip
        a, b = ours.outputs[mine], theirs.outputs[other]
        assert np.allclose(a.linear_std, b.linear_std, rtol=1e-5)  # implicit vs central differences
        assert np.allclose(a.worst_case, b.worst_case, rtol=1e-5)
        assert np.allclose(a.std, b.std, rtol=0.03, atol=0.01 * b.std.max())  # two Monte Carlos


def test_unassembled_fraction_by_group_against_grashof():
    # a four-bar crank-rocker: the crank turns fully iff r2 + r1 ≤ r3 + r4 and |r3 − r4| ≤ r1 − r2
    pts = {"O2": 0j, "O4": 6 + 0j, "A": 1.5 + 0j, "B": WATT["B"]}
    lk = (Linkage(pts).ground("O2", "O4").link("crank", "O2", "A").link("coupler", "A", "B")
          .link("rocker", "O4", "B").drive("crank"))  # fmt: skip
    r3, r4 = abs(pts["B"] - pts["A"]), abs(pts["B"] - pts["O4"])
    t = machdyn.tolerance(lk, {"O2-A": (2.0, "uniform")}, samples=20_000, seed=2)
    r2 = 1.5 + np.random.default_rng(0).uniform(-2.0, 2.0, 400_000)
    turns = (r2 > 0) & (r2 + 6.0 <= r3 + r4) & (abs(r3 - r4) <= 6.0 - r2)
    expected = 1.0 - turns.mean()
    assert t.failed_fraction == pytest.approx(expected, abs=0.01)
    assert sum(t.failures.values()) == t.failed
    assert set(t.failures) == {"RRR dyad (coupler, rocker) does not close", "a length ≤ 0"}
    assert t.failures["a length ≤ 0"] / t.samples == pytest.approx(0.125, abs=0.01)  # r2 ≤ 0
    assert any("cannot be assembled" in w for w in t.warnings)


def test_bad_requests_name_the_field():
    lk = watt(WATT)
    with pytest.raises(InputError, match=r"unknown dimension 'r2'.*O2-A.*P\.delta"):
        machdyn.tolerance(lk, {"r2": 0.1})
    with pytest.raises(InputError, match=r"tolerances\[A-B\]"):
        machdyn.tolerance(lk, {"A-B": -0.1})
    with pytest.raises(InputError, match="unknown output"):
        machdyn.tolerance(lk, {"A-B": 0.1}, outputs=["theta4"])
    with pytest.raises(InputError, match="mass"):
        machdyn.tolerance(lk, {"A-B": 0.1}, mass=(1, 2, 3))
    with pytest.raises(InputError, match="omega2"):
        machdyn.tolerance(lk, {"A-B": 0.1}, outputs=["torque.crank"], omega2=0.0)
    slot = (Linkage({"O2": 0j, "A": 2 + 0j, "Y": 5 + 0j}).ground("O2")  # a Scotch yoke
            .link("crank", "O2", "A").link("yoke", "Y")
            .slider("yoke", "ground", "Y", 0.0, through="O2", name="guide")
            .slot("A", "crank", "yoke", np.pi / 2).drive("crank"))  # fmt: skip
    with pytest.raises(InputError, match=r"not solved in closed form"):
        machdyn.tolerance(slot, {"O2-A": 0.01})
    rocker = watt({**WATT, "A": 4.0 + 0j})  # the crank cannot turn: say where, not NaN
    with pytest.raises(InputError, match="theta2"):
        machdyn.tolerance(rocker, {"O2-A": 0.01}, samples=10)


@pytest.mark.slow
def test_the_same_linkage_run_on_a_dask_local_cluster():
    tol = {"O2-A": 0.02, "A-B": 0.02, "P.delta": 0.01, "C-D": 0.02}
    options = dict(samples=3000, chunk=1000, seed=4, outputs=["point.P", "theta.output"])
    local = machdyn.tolerance(watt(WATT), tol, POSES, **options)
    dask = machdyn.tolerance(watt(WATT), tol, POSES, scheduler="local", workers=1, **options)
    for name, spread in local.outputs.items():
        other = dask.outputs[name]
        assert np.array_equal(spread.peak, other.peak)
        assert np.allclose(spread.std, other.std, rtol=1e-12)
        assert np.array_equal(spread.high, other.high)
