"""Audit 3: ``machdyn.sensitivity`` / ``machdyn.tolerance`` against solves written here.

The expected values come from this file only:

* a four-bar solved by intersecting two circles (A on the crank circle, B at
  r3 from A and r4 from O4) and a slider-crank by ``d = a cos θ + √(b² − (a sin θ − c)²)``;
  derivatives with respect to each dimension by central differences of those;
* the input torque of a four-bar held against gravity as ``T12 = dV/dθ2``
  (virtual work on the potential energy written here);
* the Monte Carlo standard deviation against ``√Σ (∂y/∂p σ_p)²`` from those
  differences, and the worst-case stack-up against a brute-force search of
  the tolerance box's corners re-solved here;
* a Freudenstein function generator (Norton §5.13): ``K1, K2, K3`` from the three
  Chebyshev-spaced precision points solved here, the structural error of the
  resulting four-bar from the circle solve (zero at the precision points,
  changing sign only there).
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

import machdyn
from machdyn.errors import InputError

G = 9.81


def pins(r, theta2, sign):
    """A, B of a four-bar (two circles); ``sign`` chooses the assembly."""
    r1, r2, r3, r4 = r
    A = r2 * np.exp(1j * np.asarray(theta2, dtype=float))
    d = r1 - A
    L = np.abs(d)
    a = (r3**2 - r4**2 + L**2) / (2.0 * L)
    B = A + (a + sign * 1j * np.sqrt(r3**2 - a**2)) * d / L
    return A, B


def outputs(dims, theta2, sign):
    """θ3, θ4 and the coupler point for ``dims = (r1, r2, r3, r4, p, delta)``."""
    r1, r2, r3, r4, p, delta = dims
    A, B = pins((r1, r2, r3, r4), theta2, sign)
    theta3 = np.angle(B - A)
    return {
        "theta3": theta3,
        "theta4": np.angle(B - r1),
        "coupler": A + p * np.exp(1j * (theta3 + delta)),
    }


def library_sign(fb, theta2):
    """Which intersection is the library's form 1 (only the choice is read)."""
    B = complex(np.asarray(fb.solve(theta2, 1.0, 0.0).B))
    return 1.0 if abs(pins(fb.lengths, theta2, 1.0)[1] - B) < 1e-9 else -1.0


def angle_diff(a, b):
    return np.angle(np.exp(1j * (a - b)))


def differences(dims, theta2, sign, h=1e-6):
    """Central differences of every output with respect to every dimension."""
    out = {}
    for k in range(len(dims)):
        up, dn = list(dims), list(dims)
        up[k] += h
        dn[k] -= h
        yu, yd = outputs(up, theta2, sign), outputs(dn, theta2, sign)
        for name in yu:
            diff = yu[name] - yd[name]
            if name.startswith("theta"):
                diff = angle_diff(yu[name], yd[name])
            out[name, k] = diff / (2 * h)
    return out


def random_crank_rocker(rng):
    """A Grashof crank-rocker with the crank shortest (link 2 turns)."""
    while True:
        r1, r3, r4 = rng.uniform(0.6, 1.4, 3)
        r2 = rng.uniform(0.1, 0.45)
        lengths = sorted((r1, r2, r3, r4))
        if lengths[0] + lengths[3] < lengths[1] + lengths[2] - 0.05:
            return r1, r2, r3, r4


# --- derivatives --------------------------------------------------------------------------


def test_four_bar_derivatives_match_differences_of_two_circles():
    rng = np.random.default_rng(303)
    for _ in range(6):
        r = random_crank_rocker(rng)
        p, delta = rng.uniform(0.2, 1.0), rng.uniform(-1.0, 1.0)
        fb = machdyn.FourBar(*r, coupler=(p, delta))
        theta2 = rng.uniform(0, 2 * np.pi, 7)
        s = machdyn.sensitivity(fb, theta2)
        assert s.dimensions == ("r1", "r2", "r3", "r4", "p", "delta")
        dims = (*r, p, delta)
        for t in theta2:
            sign = library_sign(fb, t)
            fd = differences(dims, t, sign)
            k = int(np.flatnonzero(theta2 == t)[0])
            for (name, j), value in fd.items():
                got = s.of(name, s.dimensions[j])[k]
                assert abs(got - value) < 2e-6 * (1 + abs(value)), (name, s.dimensions[j])


def test_four_bar_rate_derivatives_match_differences_of_the_velocity():
    # ω4 = dθ4/dθ2 · ω2 by differences in θ2, then its change with each length
    rng = np.random.default_rng(304)
    r = random_crank_rocker(rng)
    fb = machdyn.FourBar(*r)
    theta2, w2 = np.array([0.4, 2.2, 4.0]), 3.0
    s = machdyn.sensitivity(fb, theta2, omega2=w2)
    sign = library_sign(fb, 0.4)

    def omega4(dims, t, h=1e-5):
        up = outputs((*dims, 0.0, 0.0), t + h, sign)["theta4"]
        dn = outputs((*dims, 0.0, 0.0), t - h, sign)["theta4"]
        return angle_diff(up, dn) / (2 * h) * w2

    for j, name in enumerate(("r1", "r2", "r3", "r4")):
        h = 1e-4
        up, dn = list(r), list(r)
        up[j] += h
        dn[j] -= h
        expected = (omega4(up, theta2) - omega4(dn, theta2)) / (2 * h)
        np.testing.assert_allclose(s.of("omega4", name), expected, rtol=1e-4, atol=1e-6)


def test_slider_crank_derivatives_match_differences_of_the_closed_form():
    rng = np.random.default_rng(305)
    for _ in range(5):
        a, b, c = rng.uniform(0.5, 1.5), rng.uniform(3.0, 5.0), rng.uniform(-0.4, 0.4)
        sc = machdyn.SliderCrank(a, b, offset=c)
        theta2 = rng.uniform(0, 2 * np.pi, 9)
        s = machdyn.sensitivity(sc, theta2)

        def d(a_, b_, c_, t=theta2):
            return a_ * np.cos(t) + np.sqrt(b_**2 - (a_ * np.sin(t) - c_) ** 2)

        h = 1e-6
        expected = {
            "crank": (d(a + h, b, c) - d(a - h, b, c)) / (2 * h),
            "coupler": (d(a, b + h, c) - d(a, b - h, c)) / (2 * h),
            "offset": (d(a, b, c + h) - d(a, b, c - h)) / (2 * h),
        }
        for name, value in expected.items():
            np.testing.assert_allclose(s.of("d", name), value, rtol=1e-7, atol=1e-8)


def test_input_torque_against_gravity_derivative_matches_virtual_work_differences():
    # at rest (ω2 = α2 = 0) T12 = dV/dθ2, V = Σ m g y_G; then ∂T12/∂r by differences
    r = (0.08, 0.03, 0.07, 0.06)
    m, IG, cg = (0.2, 0.3, 0.25), (3e-5, 1.2e-4, 7.5e-5), (0.015, 0.035, 0.03)
    fb = machdyn.FourBar(*r)
    theta2 = np.array([0.5, 1.7, 3.3, 5.0])
    s = machdyn.sensitivity(fb, theta2, omega2=0.0, mass=m, inertia=IG, cg=cg, gravity=G)
    sign = library_sign(fb, 0.5)

    def potential(rr, t):
        A, B = pins(rr, t, sign)
        G2 = cg[0] * A / rr[1]
        G3 = A + cg[1] * (B - A) / rr[2]
        G4 = rr[0] + cg[2] * (B - rr[0]) / rr[3]
        return G * (m[0] * G2.imag + m[1] * G3.imag + m[2] * G4.imag)

    def torque(rr, h=1e-5):
        return (potential(rr, theta2 + h) - potential(rr, theta2 - h)) / (2 * h)

    np.testing.assert_allclose(s.nominal["T12"], torque(r), rtol=1e-8)
    for j, name in enumerate(("r1", "r2", "r3", "r4")):
        h = 1e-5
        up, dn = list(r), list(r)
        up[j] += h
        dn[j] -= h
        expected = (torque(up) - torque(dn)) / (2 * h)
        np.testing.assert_allclose(s.of("T12", name), expected, rtol=1e-4, atol=1e-5)


# --- Monte Carlo and stack-up --------------------------------------------------------------


def test_monte_carlo_spread_matches_the_first_order_prediction_written_here():
    r = (8.0, 3.0, 7.0, 6.0)
    fb = machdyn.FourBar(*r)
    tol = {"r1": 2e-3, "r2": 1e-3, "r3": 3e-3, "r4": 1.5e-3}  # ±t at 3σ
    theta2 = np.radians(np.arange(0.0, 360.0, 30.0))
    mc = machdyn.tolerance(fb, tol, theta2, samples=40_000, seed=7)
    assert mc.failed == 0
    sign = library_sign(fb, 0.0)
    sigma = np.array(list(tol.values())) / 3.0
    for name in ("theta3", "theta4"):
        grads = np.array([differences((*r, 0.0, 0.0), theta2, sign)[name, j] for j in range(4)])
        predicted = np.sqrt(((grads * sigma[:, None]) ** 2).sum(axis=0))
        # sampling error of a standard deviation from 40 000 draws: 1/√(2N) = 0.35 %
        np.testing.assert_allclose(mc.outputs[name].std, predicted, rtol=0.02)
        np.testing.assert_allclose(mc.outputs[name].linear_std, predicted, rtol=1e-5)
        np.testing.assert_allclose(mc.outputs[name].mean, 0.0, atol=0.02 * predicted.max())
    # uniform within ±t: σ = t/√3
    mc = machdyn.tolerance(fb, tol, theta2, samples=40_000, seed=8, distribution="uniform")
    grads = np.array([differences((*r, 0.0, 0.0), theta2, sign)["theta4", j] for j in range(4)])
    predicted = np.sqrt(((grads * (sigma * 3 / math.sqrt(3))[:, None]) ** 2).sum(axis=0))
    np.testing.assert_allclose(mc.outputs["theta4"].std, predicted, rtol=0.02)
    # the envelope of a uniform box never exceeds its corners' worst case
    assert np.all(np.abs(mc.outputs["theta4"].high) <= mc.outputs["theta4"].worst_case * 1.001)


def test_worst_case_stack_up_is_the_worst_corner_of_the_tolerance_box():
    rng = np.random.default_rng(306)
    r = random_crank_rocker(rng)
    fb = machdyn.FourBar(*r)
    theta2 = rng.uniform(0, 2 * np.pi, 11)
    t = np.array([1e-5, 2e-5, 1.5e-5, 1e-5])
    s = machdyn.sensitivity(fb, theta2)
    sign = library_sign(fb, float(theta2[0]))
    nominal = outputs((*r, 0.0, 0.0), theta2, sign)["theta4"]
    corners = []
    for signs in itertools.product((-1.0, 1.0), repeat=4):
        moved = np.array(r) + np.array(signs) * t
        corners.append(np.abs(angle_diff(outputs((*moved, 0, 0), theta2, sign)["theta4"], nominal)))
    brute = np.max(corners, axis=0)
    stack = s.stack_up(dict(zip(("r1", "r2", "r3", "r4"), t, strict=True)), "theta4")
    # first order: equal to the corner search up to second-order terms (t ~ 1e-5)
    np.testing.assert_allclose(stack, brute, rtol=1e-3)
    mc = machdyn.tolerance(fb, dict(zip(("r1", "r2", "r3", "r4"), t, strict=True)), theta2,
                           samples=2000, seed=3)  # fmt: skip
    np.testing.assert_allclose(mc.outputs["theta4"].worst_case, brute, rtol=1e-3)


def test_slider_crank_stroke_tolerance_predicts_the_corner_search():
    a, b, c = 1.0, 4.0, 0.2
    sc = machdyn.SliderCrank(a, b, offset=c)
    theta2 = np.radians(np.arange(0.0, 360.0, 15.0))
    tol = {"crank": 1e-4, "coupler": 2e-4, "offset": 1e-4}
    mc = machdyn.tolerance(sc, tol, theta2, samples=20_000, seed=11, outputs=["d"])

    def d(a_, b_, c_):
        return a_ * np.cos(theta2) + np.sqrt(b_**2 - (a_ * np.sin(theta2) - c_) ** 2)

    nominal = d(a, b, c)
    corners = [
        np.abs(d(a + sa * 1e-4, b + sb * 2e-4, c + sc_ * 1e-4) - nominal)
        for sa, sb, sc_ in itertools.product((-1, 1), repeat=3)
    ]
    np.testing.assert_allclose(mc.outputs["d"].worst_case, np.max(corners, axis=0), rtol=1e-3)
    np.testing.assert_allclose(mc.outputs["d"].nominal, nominal, rtol=1e-12)


# --- Freudenstein function generator ---------------------------------------------------------


def test_function_generator_structural_error_from_freudenstein_written_here():
    from machdyn.synthesis.function import function_generator

    x0, xf = 1.0, 2.0
    th2r, th4r = np.radians((45.0, 105.0)), np.radians((135.0, 225.0))
    g = function_generator(np.log10, (x0, xf), th2r, th4r)
    # Chebyshev spacing of three points (Norton eq. 5.16)
    j = np.arange(1, 4)
    xp = 0.5 * (x0 + xf) - 0.5 * (xf - x0) * np.cos((2 * j - 1) * np.pi / 6)
    np.testing.assert_allclose(np.sort(g.x_precision), xp, rtol=1e-12)
    y0, yf = math.log10(x0), math.log10(xf)

    def th2_of(x):
        return th2r[0] + (x - x0) / (xf - x0) * (th2r[1] - th2r[0])

    def th4_of(y):
        return th4r[0] + (y - y0) / (yf - y0) * (th4r[1] - th4r[0])

    # K1 cos θ4 − K2 cos θ2 + K3 = cos(θ2 − θ4)
    t2, t4 = th2_of(xp), th4_of(np.log10(xp))
    K = np.linalg.solve(np.column_stack([np.cos(t4), -np.cos(t2), np.ones(3)]), np.cos(t2 - t4))
    d = 1.0
    a, c = d / K[0], d / K[1]
    b = math.sqrt(a * a + c * c + d * d - 2 * a * c * K[2])
    np.testing.assert_allclose(g.k, K, rtol=1e-10)
    np.testing.assert_allclose(
        sorted(g.fourbar.lengths), sorted((d, abs(a), b, abs(c))), rtol=1e-10
    )
    # generated output of the signed-length linkage: B from A = a e^{jθ2} at b, from O4 at c
    x = np.linspace(x0, xf, 401)
    se = g.structural_error(x=x)  # x plus the precision points

    def generated_error(xs, sign):
        A = a * np.exp(1j * th2_of(xs))
        u = d - A
        L = np.abs(u)
        along = (b * b - c * c + L * L) / (2 * L)
        B = A + (along + sign * 1j * np.sqrt(b * b - along**2)) * u / L
        out = np.angle((B - d) / c)  # θ4 of the (signed) output link
        return angle_diff(out, th4_of(np.log10(xs))) / (th4r[1] - th4r[0]) * (yf - y0)

    y_err = min((generated_error(se.x, s) for s in (1.0, -1.0)), key=lambda e: np.abs(e).max())
    np.testing.assert_allclose(se.error, y_err, atol=1e-10)
    assert np.abs(y_err).max() < 1e-3  # log10 on [1, 2] to 0.1 % of a decade
    # zero at the precision points, and the sign changes only there
    assert np.all(np.abs(g.structural_error(x=xp).error) < 1e-12)
    fine = min((generated_error(x, s) for s in (1.0, -1.0)), key=lambda e: np.abs(e).max())
    changes = 0.5 * (x[1:] + x[:-1])[np.diff(np.sign(fine)) != 0]
    assert len(changes) == 3
    assert np.all(np.abs(changes - xp) < 0.01)
    # Chebyshev spacing beats precision points at the ends and middle of the range
    uniform = function_generator(np.log10, (x0, xf), th2r, th4r, spacing="uniform")
    assert g.structural_error(x=x).max_abs < uniform.structural_error(x=x).max_abs


# --- bad input ----------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("call", "field"),
    [
        (lambda fb: machdyn.tolerance(fb, {"r5": 1e-3}), "tolerances"),
        (lambda fb: machdyn.tolerance(fb, {"r1": -1e-3}), "r1"),
        (lambda fb: machdyn.tolerance(fb, {"r1": float("nan")}), "r1"),
        (lambda fb: machdyn.tolerance(fb, {"r1": 1e-3}, samples=0), "samples"),
        (lambda fb: machdyn.tolerance(fb, {"r1": 1e-3}, distribution="cauchy"), "distribution"),
        (lambda fb: machdyn.tolerance(fb, {"r1": 1e-3}, outputs=["omega9"]), "outputs"),
        (lambda fb: machdyn.sensitivity(fb, [0.1], dimensions=["length"]), "dimensions"),
        (lambda fb: machdyn.sensitivity(fb, [float("inf")]), "theta2"),
    ],
)
def test_bad_input_names_the_field(call, field):
    fb = machdyn.FourBar(8.0, 3.0, 7.0, 6.0)
    with pytest.raises(InputError) as info:
        call(fb)
    assert field in info.value.field or field in str(info.value)


def test_cli_tolerance_bad_file_is_one_line(tmp_path, capsys):
    from machdyn.cli import main

    bad = tmp_path / "bad.toml"
    bad.write_text(
        "machdyn = 1\n[fourbar.f]\nr1 = 8.0\nr2 = 3.0\nr3 = 7.0\nr4 = 6.0\n"
        "[fourbar.f.tolerance]\nr9 = 0.01\n"
    )
    status = main(["tolerance", str(bad)])
    out, err = capsys.readouterr()
    assert status != 0
    text = (out + err).strip()
    assert "Traceback" not in text and "r9" in text
    assert len(text.splitlines()) <= 2


def drawn_fourbar_outputs(pts, theta):
    """θ of the rocker and the coupler point P of a drawn four-bar, from its drawn points."""
    O2, O4, A0, B0, P0 = (pts[k] for k in ("O2", "O4", "A", "B", "P"))
    r2, r3, r4 = abs(A0 - O2), abs(B0 - A0), abs(B0 - O4)
    rho = (P0 - A0) / (B0 - A0)  # P in the coupler's frame (A, toward B)
    side = np.sign(((B0 - A0) / (O4 - A0)).imag)  # the drawn assembly
    A = O2 + r2 * np.exp(1j * theta)
    d = O4 - A
    L = np.abs(d)
    along = (r3**2 - r4**2 + L**2) / (2 * L)
    B = A + (along + side * 1j * np.sqrt(r3**2 - along**2)) * d / L
    return {"theta.rocker": np.angle(B - O4), "point.P": A + rho * (B - A)}


def test_drawn_linkage_derivatives_match_differences_of_the_drawing():
    from machdyn.linkage import Linkage

    rng = np.random.default_rng(307)
    pts = {"O2": 0j, "O4": 8 + 0.5j, "A": 2.5 + 1.0j, "P": 5 + 4j}
    pts["B"] = 7.0 + 5.5j
    lk = (
        Linkage(pts)
        .ground("O2", "O4")
        .link("crank", "O2", "A")
        .link("coupler", "A", "B", "P")
        .link("rocker", "O4", "B")
        .drive("crank")
    )
    theta = rng.uniform(0, 2 * np.pi, 6)
    s = machdyn.sensitivity(lk, theta)
    h = 1e-6
    for dim in s.dimensions:
        name, axis = dim.split(".")
        step = h if axis == "x" else 1j * h
        up, dn = dict(pts), dict(pts)
        up[name] += step
        dn[name] -= step
        yu, yd = drawn_fourbar_outputs(up, theta), drawn_fourbar_outputs(dn, theta)
        expect = angle_diff(yu["theta.rocker"], yd["theta.rocker"]) / (2 * h)
        np.testing.assert_allclose(s.of("theta.rocker", dim), expect, rtol=1e-6, atol=1e-7)
        expect = (yu["point.P"] - yd["point.P"]) / (2 * h)
        np.testing.assert_allclose(s.of("point.P", dim), expect, rtol=1e-6, atol=1e-7)


def test_drawn_four_bar_length_tolerances_match_the_two_circle_prediction():
    from machdyn.linkage import Linkage

    r = (8.0, 3.0, 7.0, 6.0)
    A0 = 3 * np.exp(0.5j)
    B0 = complex(pins(r, 0.5, 1.0)[1])
    lk = (
        Linkage({"O2": 0j, "O4": 8 + 0j, "A": A0, "B": B0})
        .ground("O2", "O4")
        .link("crank", "O2", "A")
        .link("coupler", "A", "B")
        .link("rocker", "O4", "B")
        .drive("crank")
    )
    names = ("O2-O4", "O2-A", "A-B", "O4-B")  # r1, r2, r3, r4
    t = np.array([2e-3, 1e-3, 3e-3, 1.5e-3])
    theta2 = np.radians(np.arange(0.0, 360.0, 30.0))
    mc = machdyn.tolerance(lk, dict(zip(names, t, strict=True)), theta2, samples=40_000, seed=9)
    assert mc.failed == 0
    fd = differences((*r, 0.0, 0.0), theta2, 1.0)
    grads = np.array([fd["theta4", j] for j in range(4)])
    predicted = np.sqrt(((grads * (t / 3)[:, None]) ** 2).sum(axis=0))
    spread = mc.outputs["theta.rocker"]
    np.testing.assert_allclose(spread.linear_std, predicted, rtol=1e-5)
    np.testing.assert_allclose(spread.std, predicted, rtol=0.02)
    np.testing.assert_allclose(
        spread.worst_case, (np.abs(grads) * t[:, None]).sum(axis=0), rtol=1e-5
    )
    assert np.all(np.abs(mc.outputs["theta.crank"].std) < 1e-12)  # the input is not toleranced
