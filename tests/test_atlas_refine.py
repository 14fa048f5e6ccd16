"""The atlas path synthesis's refinement: its derivatives and its convergence, both backends.

The coupler point and its Jacobian are checked against central differences and
(compiled) against the NumPy reference; refinements from perturbed known
linkages must slide back onto points computed here by circle intersection.
"""

from __future__ import annotations

import numpy as np
import pytest
from tests.closed_forms import circle_meet

from machdyn import jit
from machdyn.synthesis.refine import coupler_and_jacobian, refine


def _placed_point(x, theta, side):
    """Coupler point of design x at crank angles theta by circle intersection (no machdyn)."""
    r1, r2, r3, r4, p, delta, ox, oy, theta1 = x
    a = r2 * np.exp(1j * np.asarray(theta))
    b = circle_meet(a, r3, complex(r1), r4, side)
    return complex(ox, oy) + np.exp(1j * theta1) * (a + p * np.exp(1j * delta) * (b - a) / r3)


def _evaluate(x, theta, branch):
    from machdyn.synthesis.refine import _evaluator

    return _evaluator(None)(x, theta, branch)


DESIGNS = [
    np.array([5.0, 2.0, 5.0, 4.0, 3.0, 0.6, 1.0, 2.0, 0.3]),
    np.array([2.0, 0.5, 2.2, 1.6, 0.7, -2.4, -0.5, 0.1, 2.9]),
    np.array([40.0, 1.35, 47.0, 50.0, 12.0, 1.1, 3.0, -4.0, -0.8]),
]


@pytest.mark.parametrize("x", DESIGNS)
@pytest.mark.parametrize("branch", [1.0, -1.0])
def test_coupler_jacobian_matches_central_differences_and_numpy(backend, x, branch):
    th = np.linspace(0.1, 2 * np.pi, 9, endpoint=False)
    br = np.full(th.size, branch)
    G, J, jt, excess = _evaluate(x, th, br)
    assert np.all(excess < 0)
    # the point itself: circle intersection on the assembly that reproduces the first one
    side = min((1.0, -1.0), key=lambda s: abs(_placed_point(x, th[:1], s)[0] - G[0]))
    np.testing.assert_allclose(G, _placed_point(x, th, side), rtol=0, atol=1e-12 * np.abs(x).max())
    h = 1e-6
    fd = np.array([(_evaluate(x + h * e, th, br)[0] - _evaluate(x - h * e, th, br)[0]) / (2 * h)
                   for e in np.eye(9)]).T  # fmt: skip
    np.testing.assert_allclose(J, fd, rtol=0, atol=2e-7 * np.abs(J).max())
    fdt = (_evaluate(x, th + h, br)[0] - _evaluate(x, th - h, br)[0]) / (2 * h)
    np.testing.assert_allclose(jt, fdt, rtol=0, atol=2e-7 * np.abs(jt).max())
    if jit.active():  # the compiled kernel against the NumPy reference, to rounding
        ref = coupler_and_jacobian(x, th, br)
        for got, want in zip((G, J, jt, excess), ref, strict=True):
            np.testing.assert_allclose(got, want, rtol=0, atol=1e-12 * (1 + np.abs(want).max()))


@pytest.mark.parametrize("x", DESIGNS)
@pytest.mark.parametrize("timed", [False, True])
@pytest.mark.parametrize("solver", ["trf", "lm"])
def test_refine_slides_a_perturbed_linkage_back_onto_its_points(backend, x, timed, solver):
    rng = np.random.default_rng(2)
    th = np.sort(rng.uniform(0, 2 * np.pi, 10))
    side = 1.0
    targets = _placed_point(x, th, side)
    G = _evaluate(x, th, np.ones(th.size))[0]
    br = np.full(th.size, 1.0 if np.allclose(G, targets) else -1.0)  # machdyn's sign for it
    size = np.max(np.abs(targets - targets.mean()))
    x0 = x * (1 + 0.02 * rng.standard_normal(9))
    options = dict(timing=th - th[0]) if timed else {}
    r = refine(x0, th + 0.03, br, targets, crank=False, max_nfev=400, solver=solver, **options)
    assert r.rms <= 1e-7 * size  # (the long-link design's valley is narrow: 3e-8 by trf)
    # the refined design's own points, by circle intersection, are on the targets
    got = _placed_point(r.x, r.theta, side if br[0] == 1.0 else -side)
    got_other = _placed_point(r.x, r.theta, -side if br[0] == 1.0 else side)
    err = min(np.max(np.abs(got - targets)), np.max(np.abs(got_other - targets)))
    assert err <= 1e-7 * size


@pytest.mark.parametrize("timed", [False, True])
def test_levenberg_marquardt_keeps_the_bounds_and_descends(backend, timed):
    """Points of a long-link linkage, lengths bounded below its own: the optimum is on the bound.

    (In such a bounded valley trf gets further in 400 steps: the synthesis screens
    timed starts with the LM's cheap steps and polishes the best with trf.)
    """
    x = DESIGNS[2]
    th = np.linspace(0.2, 2 * np.pi, 12, endpoint=False)
    targets = _evaluate(x, th, np.ones(th.size))[0]
    options = dict(timing=th - th[0]) if timed else {}
    kw = dict(crank=False, max_length=45.0, pivot_box=(-10, -10, 10, 10), **options)
    x0 = x.copy()
    x0[[0, 2, 3]] = 44.0  # r1, r3, r4 start inside the bound
    start = refine(x0, th, np.ones(th.size), targets, max_nfev=1, solver="lm", **kw).rms
    last = start
    for nfev in (12, 40, 400):
        r = refine(x0, th, np.ones(th.size), targets, max_nfev=nfev, solver="lm", **kw)
        assert np.all(r.x[:5] <= 45.0) and np.all(r.x[:4] > 0) and r.x[4] >= 0
        assert -10 <= r.x[6] <= 10 and -10 <= r.x[7] <= 10
        assert r.rms <= last  # more steps never end higher (only improving steps are taken)
        last = r.rms
    assert last < 0.05 * start


@pytest.mark.parametrize("x", DESIGNS)
@pytest.mark.parametrize("timed", [False, True])
def test_compiled_levenberg_marquardt_takes_the_numpy_loops_steps(x, timed):
    """The LM's compiled loop (``_atlas_kernels.lm_refine``) against the NumPy loop.

    A few steps from the same start, with the bounds, the crank rows and a held
    pivot: the same design to rounding (the two evaluators differ in their last
    bits, which a few steps amplify by the problem's conditioning).
    """
    if not jit.load():
        pytest.skip(f"compiled kernels unavailable: {jit.reason()}")
    rng = np.random.default_rng(5)
    th = np.sort(rng.uniform(0, 2 * np.pi, 9))
    targets = _placed_point(x, th, 1.0) + 0.01 * np.abs(x[:4]).max() * rng.standard_normal(9)
    x0 = x * (1 + 0.03 * rng.standard_normal(9))
    kw = dict(crank=True, mu_min=0.3, max_length=1.02 * np.abs(x[:5]).max(),
              fixed={6: x[6], 7: x[7]}, timing=th - th[0] if timed else None)  # fmt: skip
    for nfev in (2, 4):
        got = refine(x0, th + 0.02, np.ones(9), targets, max_nfev=nfev, solver="lm",
                     compiled=True, **kw)  # fmt: skip
        want = refine(x0, th + 0.02, np.ones(9), targets, max_nfev=nfev, solver="lm",
                      compiled=False, **kw)  # fmt: skip
        np.testing.assert_allclose(got.x, want.x, rtol=1e-8, atol=1e-9)
        np.testing.assert_allclose(got.theta, want.theta, rtol=0, atol=1e-8)
        assert got.rms == pytest.approx(want.rms, rel=1e-8)
        assert got.success == want.success


@pytest.mark.parametrize("compiled", [False, True])
def test_a_tied_length_keeps_the_change_point(compiled):
    """``tie``: r1 held at r3 + r4 − r2 (Grashof's change point) while the rest refine.

    Targets of a change-point linkage (1 + 4 = 3 + 2), by circle intersection; a start
    perturbed along the change point slides back, and every iterate keeps r1 on it.
    """
    if compiled and not jit.load():
        pytest.skip(f"compiled kernels unavailable: {jit.reason()}")
    x = np.array([4.0, 1.0, 3.0, 2.0, 1.5, 0.4, 0.3, -0.2, 0.5])
    th = np.linspace(0.3, 2 * np.pi, 10, endpoint=False)
    G = _evaluate(x, th, np.ones(th.size))[0]
    side = 1.0 if abs(_placed_point(x, th[:1], 1.0)[0] - G[0]) < 1e-9 else -1.0
    targets = _placed_point(x, th, side)
    x0 = x * (1 + 0.01 * np.random.default_rng(3).standard_normal(9))
    x0[0] = x0[2] + x0[3] - x0[1]
    c = np.array([0.0, -1.0, 1.0, 1.0])
    r = refine(x0, th, np.ones(th.size), targets, timing=th - th[0], max_nfev=100, solver="lm",
               tie=(0, c), compiled=compiled)  # fmt: skip
    assert r.x[0] == pytest.approx(r.x[2] + r.x[3] - r.x[1], abs=1e-12)
    assert r.rms <= 1e-9 * np.max(np.abs(targets - targets.mean()))
    np.testing.assert_allclose(r.x, x, rtol=0, atol=1e-7)
