"""Audit 7: shaking force and moment of a four-bar and a slider-crank by Newton–Euler here.

With no gravity and no external loads, the ground feels the reaction of the
whole moving system's momentum change (Norton sec. 11.x):
``F_s = −Σ m a_G`` and, about O2, ``M_s = −Σ (I_G α + r_G × m a_G)``.
The accelerations of the centres of mass and the links' angular accelerations
are central time differences (Richardson-extrapolated) of positions computed
here by circle intersection along θ2(t) = θ2 + ω t + α t²/2, so nothing on the
expected side comes from machdyn. Single- and two-plane balance of random
rotors are checked by the sums they must cancel.
"""

from __future__ import annotations

import numpy as np
import pytest

from machdyn import FourBar, SliderCrank
from machdyn.balancing import static_balance, two_plane


def second_difference(f, h=1e-3):
    """d²/dt² at 0 of f(t) = (points, angles): 5-point stencil, Richardson-extrapolated.

    The angles are unwrapped across the stencil (np.angle jumps at ±π).
    """

    def stencil(h):
        points, angles = zip(*(f(k * h) for k in (-2, -1, 0, 1, 2)), strict=True)
        angles = np.unwrap(np.array(angles), axis=0)
        out = []
        for v in (np.array(points), angles):
            out.append((-v[0] + 16 * v[1] - 30 * v[2] + 16 * v[3] - v[4]) / (12 * h * h))
        return out

    (p1, a1), (p2, a2) = stencil(h), stencil(h / 2)
    return (4 * p2 - p1) / 3, (4 * a2 - a1) / 3


def fourbar_bodies(r, t2, cgs):
    """Centres of mass (complex) and link angles of links 2, 3, 4, form 1 (φ12 > 0)."""
    r1, r2, r3, r4 = r
    A = r2 * np.exp(1j * t2)
    u = r1 - A
    d = abs(u)
    cos_a = (r3 * r3 + d * d - r4 * r4) / (2 * r3 * d)
    for s in (1, -1):
        B = A + r3 * u / d * np.exp(1j * s * np.arccos(cos_a))
        t3, t4 = np.angle(B - A), np.angle(B - r1)
        if np.sin(t4 - t3) > 0:
            break
    angles = np.array([t2, t3, t4])
    origins = [0j, A, r1 + 0j]
    g = np.array([o + c * np.exp(1j * t) for o, c, t in zip(origins, cgs, angles, strict=True)])
    return g, angles


@pytest.mark.parametrize("seed", range(3))
def test_fourbar_shaking_force_and_moment_by_momentum_change(seed):
    rng = np.random.default_rng(seed)
    done = 0
    while done < 10:
        r = np.array([rng.uniform(2, 3), rng.uniform(0.3, 0.8), *rng.uniform(1.5, 2.5, 2)])
        if (r.min() + r.max() >= r.sum() - r.min() - r.max()) or r.argmin() != 1:
            continue  # keep to crank-rockers/double cranks with link 2 the shortest
        fb = FourBar(*r)
        mass = rng.uniform(0.5, 3.0, 3)
        inertia = rng.uniform(0.01, 0.5, 3)
        cgs = [complex(*rng.uniform(-0.5, 1.0, 2)) * length for length in r[1:]]
        t2, w, al = rng.uniform(0, 2 * np.pi), rng.uniform(-8, 8), rng.uniform(-20, 20)
        f = fb.dynamics(t2, w, al, mass=tuple(mass), inertia=tuple(inertia), cg=tuple(cgs))
        if not bool(f.ok):
            continue

        def at(dt, t2=t2, w=w, al=al, r=r, cgs=cgs):
            return fourbar_bodies(r, t2 + w * dt + al * dt * dt / 2, cgs)

        g = at(0.0)[0]
        a_g, alpha = second_difference(at)
        force = -np.sum(mass * a_g)
        moment = -np.sum(inertia * alpha + mass * (np.conj(g) * a_g).imag)
        scale = np.sum(mass * np.abs(a_g)) + 1.0
        assert complex(f.shaking_force) == pytest.approx(force, abs=1e-6 * scale)
        assert float(f.shaking_moment) == pytest.approx(moment, abs=1e-6 * scale * r.max())
        done += 1


@pytest.mark.parametrize("seed", range(3))
def test_slider_crank_shaking_force_and_moment_by_momentum_change(seed):
    rng = np.random.default_rng(10 + seed)
    for _ in range(10):
        a = rng.uniform(0.3, 1.0)
        b = rng.uniform(2.0, 4.0)
        c = rng.uniform(-0.5, 0.5)
        sc = SliderCrank(a, b, c)
        m2, m3, m4 = rng.uniform(0.5, 3.0, 3)
        i2, i3 = rng.uniform(0.01, 0.5, 2)
        c2 = complex(*rng.uniform(-0.5, 1.0, 2)) * a
        c3 = complex(*rng.uniform(-0.2, 1.0, 2)) * b
        t2, w, al = rng.uniform(0, 2 * np.pi), rng.uniform(-8, 8), rng.uniform(-20, 20)
        f = sc.dynamics(t2, w, al, mass=(m2, m3, m4), inertia=(i2, i3), cg=(c2, c3))

        def at(dt, t2=t2, w=w, al=al, a=a, b=b, c=c, c2=c2, c3=c3):
            th = t2 + w * dt + al * dt * dt / 2
            A = a * np.exp(1j * th)
            d = A.real + np.sqrt(b * b - (A.imag - c) ** 2)  # form 1: slider on +x of A
            B = d + 1j * c
            t3 = np.angle(B - A)  # link 3 frame: origin A, x toward B
            g = np.array([c2 * np.exp(1j * th), A + c3 * np.exp(1j * t3), B])
            return g, np.array([th, t3])

        g = at(0.0)[0]
        a_g, alpha = second_difference(at)
        mass = np.array([m2, m3, m4])
        force = -np.sum(mass * a_g)
        moment = -(i2 * alpha[0] + i3 * alpha[1] + np.sum(mass * (np.conj(g) * a_g).imag))
        scale = np.sum(mass * np.abs(a_g)) + 1.0
        assert complex(f.shaking_force) == pytest.approx(force, abs=1e-6 * scale)
        assert float(f.shaking_moment) == pytest.approx(moment, abs=1e-6 * scale * (a + b))


@pytest.mark.parametrize("seed", range(3))
def test_single_and_two_plane_corrections_cancel_force_and_moment(seed):
    rng = np.random.default_rng(20 + seed)
    for _ in range(20):
        n = int(rng.integers(1, 6))
        mr = rng.uniform(0.1, 2.0, n) * np.exp(1j * rng.uniform(0, 2 * np.pi, n))
        z = rng.uniform(-1.0, 3.0, n)
        fix = static_balance(mr)
        assert abs(np.sum(mr) + fix.mR) < 1e-12 * np.sum(np.abs(mr))
        za, zb = sorted(rng.uniform(-2.0, 4.0, 2))
        if zb - za < 0.1:
            continue
        ma, mb = two_plane(mr, z, za, zb)
        # Σ of the force and of the moment about any axial point vanish with the corrections.
        total = np.sum(mr) + ma + mb
        assert abs(total) < 1e-12 * np.sum(np.abs(mr))
        for about in (0.0, za, zb, 1.7):
            moment = np.sum(mr * (z - about)) + ma * (za - about) + mb * (zb - about)
            assert abs(moment) < 1e-11 * np.sum(np.abs(mr)) * (1 + abs(about) + np.max(np.abs(z)))
