"""Audit 4: accelerations and jerks of every closed form against time differences.

The input is driven along a cubic in time, ``θ2(t) = θ2 + ω t + α t²/2 + J t³/6``
(so ``ω2(t) = ω + α t + J t²/2``, ``α2(t) = α + J t``, ``jerk2 = J``), and each
model's *own* velocities and accelerations are evaluated at ``t = ±h``.  The
central differences ``(v(h) − v(−h))/2h`` and ``(a(h) − a(−h))/2h`` must give the
acceleration and the jerk at ``t = 0``: this checks the acceleration and jerk
closed forms (FourBar, SliderCrank, InvertedSliderCrank, drawn Linkage) by a path
that never uses their formulas, at seeded random configurations on both circuits.

Step and tolerance: the five-point central difference's truncation error is
``h⁴/30·|x⁽⁵⁾|`` and its round-off ``~ε|x|/h``.  Near a toggle the derivatives
grow like (ω/sin μ)^k: at μ = 16.6° a jerk of 3322 had a truncation error of 83
with h = 1e-2 and 6e-3 with h = 1e-3 (the h⁴ ratio, 1.4e4, confirms it is
truncation, not a wrong formula).  With ``h = 2.5e-4`` s, poses of transmission
angle under 15° skipped and input rates |ω|, |α|, |J| ≤ 3, truncation stays below
~3e-5·|x| and round-off ~1e-11·|x|, so a relative tolerance of 1e-6 on
``1 + Σ|rates|`` holds with a margin of ~30 while a wrong term (of order the
value itself) fails by orders of magnitude.
"""

from __future__ import annotations

import numpy as np
import pytest

from machdyn import FourBar, InvertedSliderCrank, SliderCrank
from machdyn.linkage import Linkage

H = 2.5e-4
RTOL = 1e-6


T = np.array([-2 * H, -H, 0.0, H, 2 * H])


class _At:
    """One sample (index k) of a result's arrays, by attribute."""

    def __init__(self, result, k):
        self._r, self._k = result, k

    def __getattr__(self, name):
        return np.asarray(getattr(self._r, name))[self._k]


def _split(result):
    """The samples at −2h, −h, 0, h, 2h."""
    return tuple(_At(result, k) for k in range(5))


def _input(t2, w, a, j, t):
    return (
        t2 + w * t + a * t * t / 2 + j * t**3 / 6,
        w + a * t + j * t * t / 2,
        a + j * t,
    )


def _close(fd, value, scale, what):
    err = np.abs(np.asarray(fd) - np.asarray(value))
    tol = RTOL * (1.0 + scale)
    assert np.all(err <= tol), f"{what}: fd {fd} vs {value} (err {err}, tol {tol})"


def _central(s, name, key=None):
    """Five-point central difference at t = 0 of attribute ``name`` (``[key]`` of it)."""
    f = [getattr(x, name) for x in s]
    f = [np.asarray(v if key is None else v[key]) for v in f]
    return (f[0] - 8 * f[1] + 8 * f[3] - f[4]) / (12 * H)


@pytest.mark.parametrize("seed", range(3))
def test_fourbar_alpha_and_jerk_equal_time_differences(seed):
    rng = np.random.default_rng(4000 + seed)
    checked = 0
    while checked < 12:
        r = rng.uniform(1, 10, 4)
        if 2 * r.max() >= r.sum():
            continue
        r1, r2, r3, r4 = r
        fb = FourBar(r1, r2, r3, r4, coupler=(rng.uniform(0.5, 5), rng.uniform(-np.pi, np.pi)))
        t2 = rng.uniform(0, 2 * np.pi)
        form = int(rng.integers(1, 3))
        w, a, j = rng.uniform(-3, 3, 3)
        s = fb.solve(*_input(t2, w, a, j, T), form=form, jerk2=j)
        if not np.all(s.ok) or float(np.abs(np.sin(s.mu[1]))) < np.sin(np.radians(15)):
            continue
        s5 = _split(s)
        mid = s5[2]
        for k in (3, 4):
            om, al, je = (float(getattr(mid, f"{q}{k}")) for q in ("omega", "alpha", "jerk"))
            scale = abs(om) + abs(al) + abs(je)
            _close(_central(s5, f"omega{k}"), al, scale, "alpha")
            _close(_central(s5, f"alpha{k}"), je, scale, "jerk")
        scale = abs(mid.coupler_velocity) + abs(mid.coupler_acceleration) + abs(mid.coupler_jerk)
        _close(_central(s5, "coupler_velocity"), mid.coupler_acceleration, scale, "AP")
        _close(_central(s5, "coupler_acceleration"), mid.coupler_jerk, scale, "JP")
        checked += 1


@pytest.mark.parametrize("seed", range(2))
def test_slidercrank_alpha_and_jerk_equal_time_differences(seed):
    rng = np.random.default_rng(4100 + seed)
    checked = 0
    while checked < 12:
        a_, b_ = rng.uniform(0.5, 3), rng.uniform(3.5, 9)
        c_ = rng.uniform(-0.8, 0.8) * (b_ - a_)
        sc = SliderCrank(a_, b_, c_, point=(rng.uniform(0.5, 3), rng.uniform(-1, 1)))
        t2 = rng.uniform(0, 2 * np.pi)
        form = int(rng.integers(1, 3))
        w, al, j = rng.uniform(-3, 3, 3)
        s = sc.solve(*_input(t2, w, al, j, T), form=form, jerk2=j)
        if not np.all(s.ok):
            continue
        s5 = _split(s)
        mid = s5[2]
        scale = abs(mid.omega3) + abs(mid.alpha3) + abs(mid.jerk3)
        _close(_central(s5, "omega3"), mid.alpha3, scale, "alpha3")
        _close(_central(s5, "alpha3"), mid.jerk3, scale, "jerk3")
        scale = abs(mid.d_dot) + abs(mid.d_ddot) + abs(mid.d_dddot)
        _close(_central(s5, "d_dot"), mid.d_ddot, scale, "d_ddot")
        _close(_central(s5, "d_ddot"), mid.d_dddot, scale, "d_dddot")
        # the point on the rod: acceleration from its velocity
        scale = abs(mid.coupler_velocity) + abs(mid.coupler_acceleration)
        _close(_central(s5, "coupler_velocity"), mid.coupler_acceleration, scale, "AP")
        checked += 1


@pytest.mark.parametrize("form", [1, 2])
def test_inverted_slidercrank_alpha_and_jerk_equal_time_differences(form):
    rng = np.random.default_rng(4200 + form)
    checked = 0
    while checked < 12:
        a_, d_ = rng.uniform(0.5, 5, 2)
        c_ = rng.uniform(-0.7, 0.7) * min(a_, d_)
        isc = InvertedSliderCrank(a_, d_, c_)
        t2 = rng.uniform(0, 2 * np.pi)
        w, al, j = rng.uniform(-3, 3, 3)
        s = isc.solve(*_input(t2, w, al, j, T), form=form, jerk2=j)
        if not np.all(s.ok):
            continue
        s5 = _split(s)
        mid = s5[2]
        if float(np.abs(mid.b)) < 0.2 * max(a_, d_):  # the block near O4: fast slot swing
            continue
        scale = abs(mid.omega4) + abs(mid.alpha4) + abs(mid.jerk4)
        _close(_central(s5, "omega4"), mid.alpha4, scale, "alpha4")
        _close(_central(s5, "alpha4"), mid.jerk4, scale, "jerk4")
        scale = abs(mid.b_dot) + abs(mid.b_ddot) + abs(mid.b_dddot)
        _close(_central(s5, "b_dot"), mid.b_ddot, scale, "b_ddot")
        _close(_central(s5, "b_ddot"), mid.b_dddot, scale, "b_dddot")
        checked += 1


def _stephenson_slider():
    """A four-bar O2-A-B-O4 driving a slider block C on the ground through rod B-C."""
    pts = {"O2": 0j, "A": 2 + 1j, "O4": 8 + 0j, "B": 7.0 + 5.0j, "C": 13.0 + 2.0j, "P": 4 + 4j}
    return (
        Linkage(pts)
        .ground("O2", "O4")
        .link("crank", "O2", "A")
        .link("coupler", "A", "B", "P", mass=2.0, inertia=0.3, cg="P")
        .link("rocker", "O4", "B")
        .link("rod", "B", "C", mass=1.0, inertia=0.2, cg=2.0)
        .link("block", "C", mass=0.5, inertia=0.01)
        .slider("block", "ground", "C", 0.0)
        .drive("crank")
    )


def test_drawn_linkage_accelerations_and_jerks_equal_time_differences():
    lk = _stephenson_slider()
    rng = np.random.default_rng(4300)
    start = float(np.angle(2 + 1j))
    t2 = start + rng.uniform(-0.3, 0.3, 6)
    w, al, j = 2.0, -1.5, 3.0
    ms = [lk.solve(*_input(t2, w, al, j, t), jerk=j) for t in T]
    mid = ms[2]
    assert all(np.all(x.ok) for x in ms)
    for link in mid.omega:
        scale = np.abs(mid.omega[link]) + np.abs(mid.alpha[link]) + np.abs(mid.jerk[link])
        _close(_central(ms, "omega", link), mid.alpha[link], scale, f"alpha {link}")
        _close(_central(ms, "alpha", link), mid.jerk[link], scale, f"jerk {link}")
    for name in mid.points:
        V, A, J = mid.point_velocity[name], mid.point_acceleration[name], mid.point_jerk[name]
        scale = np.abs(V) + np.abs(A) + np.abs(J)
        _close(_central(ms, "point_velocity", name), A, scale, f"A {name}")
        _close(_central(ms, "point_acceleration", name), J, scale, name)
    for link in mid.cg:
        A, J = mid.cg_acceleration[link], mid.cg_jerk[link]
        scale = np.abs(mid.cg_velocity[link]) + np.abs(A) + np.abs(J)
        _close(_central(ms, "cg_velocity", link), A, scale, f"aG {link}")
        _close(_central(ms, "cg_acceleration", link), J, scale, f"jG {link}")
