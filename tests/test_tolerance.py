"""Monte Carlo tolerance analysis (machdyn.tolerance), against things that share no code with it.

* the linearised prediction: for small tolerances the Monte Carlo standard deviation of
  every output approaches ``√Σ (∂y/∂p σ_p)²`` from the sensitivities (implicit
  differentiation) — and the sensitivities are themselves checked against central
  differences in test_sensitivity.py;
* brute force: the worst sample's dimensions, re-solved by the model's own solver
  (``FourBar.solve``, ``SliderCrank.solve``, Newton–Euler ``FourBar.dynamics``), give
  the worst deviation reported;
* the fraction of samples that cannot be assembled against an independent Monte Carlo
  written here with Grashof's condition (a crank-rocker turns fully iff ``s + l ≤ p + q``
  with the crank shortest);
* a one-dimension uniform tolerance, whose envelope is ``|∂y/∂p| t`` to second order.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import machdyn
from machdyn import FourBar, SliderCrank
from machdyn.errors import InputError

HW6 = FourBar(8.0, 4.0, 7.0, 6.0, coupler=(3.0, 0.5))  # the notes' HW 6 crank-rocker
ALL = {"r1": 0.004, "r2": 0.004, "r3": 0.004, "r4": 0.004, "p": 0.004, "delta": 0.001}


def _peak_deviation(theta4: np.ndarray, nominal: np.ndarray) -> float:
    return float(np.max(np.abs(np.angle(np.exp(1j * (theta4 - nominal))))))


@pytest.mark.parametrize("distribution", ["normal", "uniform"])
def test_monte_carlo_spread_approaches_the_linearised_prediction(distribution):
    t = machdyn.tolerance(HW6, ALL, samples=20_000, distribution=distribution, seed=3)
    assert t.failed == 0 and not t.warnings
    # the standard deviations by hand: ±t at 3σ (normal) or t/√3 (uniform)
    sigma = np.array(list(ALL.values())) / (3.0 if distribution == "normal" else math.sqrt(3.0))
    assert np.allclose(t.sigma, sigma)
    s = machdyn.sensitivity(HW6, t.theta)
    for name in ("theta3", "theta4", "coupler"):
        spread = t.outputs[name]
        d = s.derivative[name]  # columns r1 … r4, p, delta: the tolerance's order
        predicted = np.sqrt(np.sum(np.abs(d * sigma) ** 2, axis=1))
        # the relative standard error of a standard deviation from N samples is 1/√(2N) = 0.5 %
        assert np.allclose(spread.std, predicted, rtol=0.025), name
        assert np.allclose(spread.linear_std, predicted, rtol=1e-12)
        assert np.all(np.abs(spread.mean) < 5 * predicted / math.sqrt(20_000) + 1e-3 * predicted)
        worst_case = np.sum(np.abs(d) * np.array(list(ALL.values())), axis=1)
        assert np.allclose(spread.worst_case, worst_case)
        if distribution == "uniform":  # within ±t: inside the first-order worst case
            bound = 1.01 * worst_case  # (second-order terms are ~1e-3 of it)
            assert np.all(np.abs(spread.high) <= bound) and np.all(np.abs(spread.low) <= bound)
        assert spread.peak.shape == (20_000,) and spread.peak.dtype == np.float32


def test_worst_sample_re_solved_by_the_models_own_solver():
    t = machdyn.tolerance(HW6, ALL, samples=5000, seed=1)
    theta = t.theta
    nominal = HW6.solve(theta)
    for name in ("theta4", "coupler"):
        spread = t.outputs[name]
        r1, r2, r3, r4, p, delta = spread.worst_dimensions
        m = FourBar(r1, r2, r3, r4, coupler=(p, delta)).solve(theta)
        assert bool(np.all(m.ok))
        if name == "theta4":
            brute = _peak_deviation(m.theta4, nominal.theta4)
        else:
            brute = float(np.max(np.abs(m.coupler - nominal.coupler)))
        assert spread.worst == pytest.approx(brute, rel=1e-5)  # stored as float32
        assert spread.worst == pytest.approx(float(spread.peak.max()))


def test_peak_torque_spread_against_newton_euler_re_solved():
    fb = FourBar(0.08, 0.04, 0.07, 0.06)
    masses = dict(mass=(0.2, 0.3, 0.25), inertia=(3e-5, 1.2e-4, 7.5e-5), cg=(0.02, 0.035, 0.03))
    tol = {"r2": 2e-4, "r3": 2e-4, "r4": 1e-4}
    theta = np.radians(np.arange(0.0, 360.0, 2.0))
    t = machdyn.tolerance(fb, tol, theta, samples=3000, omega2=30.0, gravity=9.81, **masses)
    spread = t.outputs["T12"]
    nominal = fb.dynamics(theta, 30.0, gravity=9.81, **masses).T12
    assert np.allclose(spread.nominal, nominal, rtol=1e-9, atol=1e-12)
    r2, r3, r4 = spread.worst_dimensions
    worst = FourBar(0.08, r2, r3, r4).dynamics(theta, 30.0, gravity=9.81, **masses).T12
    assert spread.worst == pytest.approx(np.max(np.abs(worst - nominal)), rel=1e-5)
    s = machdyn.sensitivity(fb, theta, omega2=30.0, gravity=9.81, dimensions=list(tol), **masses)
    predicted = np.sqrt(np.sum((s.derivative["T12"] * t.sigma) ** 2, axis=1))
    assert np.allclose(spread.std, predicted, rtol=0.05)


def test_slider_crank_stroke_error_by_hand():
    """A crank of length a + e: d = (a+e) cos θ2 + √(b² − (a+e)² sin² θ2) (no offset)."""
    a, b, e = 50.0, 200.0, 0.1
    theta = np.radians(np.arange(0.0, 360.0, 5.0))
    t = machdyn.tolerance(SliderCrank(a, b), {"crank": (e, "uniform")}, theta, samples=4000)
    spread = t.outputs["d"]

    def d(crank):
        return crank * np.cos(theta) + np.sqrt(b * b - (crank * np.sin(theta)) ** 2)

    # the extreme samples lie within 1e-3 e of ±e: the envelope is Δd(±e), by hand
    assert np.allclose(spread.high, np.maximum(d(a + e), d(a - e)) - d(a), atol=2e-3 * e)
    assert np.allclose(spread.low, np.minimum(d(a + e), d(a - e)) - d(a), atol=2e-3 * e)
    worst = spread.worst_dimensions[0]
    m = SliderCrank(worst, b).solve(theta)
    assert spread.worst == pytest.approx(np.max(np.abs(m.d - d(a))), rel=1e-5)
    assert t.distributions == ("uniform",)


def test_offset_slider_crank_coupler_point_against_its_solver():
    sc = SliderCrank(2.0, 6.0, 1.0, point=(3.0, 0.4))
    tol = {"crank": 0.01, "coupler": 0.01, "offset": 0.02, "p": 0.01, "delta": 0.005}
    t = machdyn.tolerance(sc, tol, samples=3000, form=2)
    theta = t.theta
    nominal = sc.solve(theta, form=2)
    spread = t.outputs["coupler"]
    assert np.allclose(spread.nominal, nominal.coupler)
    a, b, c, p, delta = spread.worst_dimensions
    m = SliderCrank(a, b, c, point=(p, delta)).solve(theta, form=2)
    assert spread.worst == pytest.approx(np.max(np.abs(m.coupler - nominal.coupler)), rel=1e-5)
    s = machdyn.sensitivity(sc, theta, form=2)
    predicted = np.sqrt(np.sum(np.abs(s.derivative["coupler"] * t.sigma) ** 2, axis=1))
    assert np.allclose(spread.std, predicted, rtol=0.06)


def test_unassemblable_samples_are_counted_not_averaged_away():
    # 10-4-8-6 sits at Grashof's limit (4 + 10 = 8 + 6): about half the samples cannot turn
    fb = FourBar(10.0, 4.0, 8.0, 6.0)
    tol = {"r1": 0.3, "r2": 0.3, "r3": 0.3, "r4": 0.3}
    theta = np.radians(np.arange(1.0, 360.0, 2.0))  # off the toggle at θ2 = 0
    t = machdyn.tolerance(fb, tol, theta, samples=20_000, seed=7)
    # an independent Monte Carlo with Grashof's condition: the crank shortest and s + l ≤ p + q
    rng = np.random.default_rng(11)
    r = np.array(fb.lengths) + 0.1 * rng.standard_normal((200_000, 4))
    shortest, longest = r.min(axis=1), r.max(axis=1)
    others = r.sum(axis=1) - shortest - longest
    turns = (r[:, 1] == shortest) & (shortest + longest <= others)
    expected = 1.0 - turns.mean()
    assert t.failed_fraction == pytest.approx(expected, abs=0.015)
    assert t.outputs["theta4"].peak.size == t.samples - t.failed
    assert t.warnings and str(t.failed) in t.warnings[0].replace(",", "")
    # a rocker swept to 1e-4 rad of both its limits: moving r4 narrows the range at one end
    # or the other (the diagonal O4A must lie between |r3 − r4| and r3 + r4)
    rocker = FourBar(6.0, 9.0, 3.0, 8.0)
    lo, hi = rocker.input_range().lo, rocker.input_range().hi
    sweep = np.linspace(lo + 1e-4, hi - 1e-4, 50)
    mostly = machdyn.tolerance(rocker, {"r4": 0.01}, sweep, samples=4000)
    assert mostly.failed_fraction > 0.8 and "most samples" in mostly.warnings[0]
    assert "unassembled" in repr(mostly)


def test_chunks_are_independent_of_where_they_run():
    one = machdyn.tolerance(HW6, ALL, samples=3000, chunk=1000, seed=5)
    again = machdyn.tolerance(HW6, ALL, samples=3000, chunk=1000, seed=5)
    assert np.array_equal(one.outputs["coupler"].peak, again.outputs["coupler"].peak)
    other = machdyn.tolerance(HW6, ALL, samples=3000, chunk=1000, seed=6)
    assert not np.array_equal(one.outputs["coupler"].peak, other.outputs["coupler"].peak)


@pytest.mark.slow
def test_the_same_run_on_a_dask_local_cluster():
    local = machdyn.tolerance(HW6, ALL, samples=4000, chunk=1000, seed=2)
    dask = machdyn.tolerance(HW6, ALL, samples=4000, chunk=1000, seed=2, scheduler="local",
                             workers=1)  # fmt: skip
    for name, spread in local.outputs.items():
        other = dask.outputs[name]
        assert np.array_equal(spread.peak, other.peak)
        assert np.allclose(spread.std, other.std, rtol=1e-12)
        assert np.array_equal(spread.high, other.high)


def test_bad_input_names_the_field():
    with pytest.raises(InputError, match=r"tolerances\[r2\]"):
        machdyn.tolerance(HW6, {"r2": -0.1})
    with pytest.raises(InputError, match=r"tolerances\[r2\].*larger"):
        machdyn.tolerance(HW6, {"r2": 100.0})
    with pytest.raises(InputError, match="unknown dimension"):
        machdyn.tolerance(HW6, {"r9": 0.1})
    with pytest.raises(InputError, match="tolerances"):
        machdyn.tolerance(HW6, {})
    with pytest.raises(InputError, match=r"tolerances\[r2\]"):
        machdyn.tolerance(HW6, {"r2": (0.1, "triangular")})
    with pytest.raises(InputError, match="T12 needs mass"):
        machdyn.tolerance(FourBar(8, 4, 7, 6), {"r2": 0.1}, outputs=["T12"])
    with pytest.raises(InputError, match="theta2"):
        machdyn.tolerance(FourBar(6, 9, 3, 8), {"r2": 0.1}, [0.0, 3.0])  # outside its range
    with pytest.raises(InputError, match="samples"):
        machdyn.tolerance(HW6, {"r2": 0.1}, samples=0)
    with pytest.raises(InputError, match="model"):
        machdyn.tolerance("8 4 7 6", {"r2": 0.1})
    with pytest.raises(InputError, match="scheduler"):
        machdyn.tolerance(HW6, {"r2": 0.1}, samples=10, scheduler="nowhere")


def test_a_rocker_defaults_to_its_range_inside_the_toggles():
    rocker = FourBar(6.0, 9.0, 3.0, 8.0)  # GRCR
    t = machdyn.tolerance(rocker, {"r3": 0.001}, samples=500)
    lo, hi = rocker.input_range().lo, rocker.input_range().hi
    assert t.theta.size == 360 and lo < t.theta.min() and t.theta.max() < hi
