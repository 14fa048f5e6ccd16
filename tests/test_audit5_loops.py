"""Audit 5: LoopSystem jerks against time differences of its accelerations, random chains.

Random closed chains are drawn here from a random pose (so the assembly is known
exactly): four-bars, offset slider-cranks driven at the crank or at the slider,
inverted slider-cranks with an offset slide (a constraint θ3p = θ3 + π/2 and a
variable length in the same loop), and Watt six-bars (two loops, a ternary rocker
by a constraint). The input moves as ``q(t) = q0 + ω t + α t²/2 + J t³/6``; the system
is solved at five times around t = 0 with ``velocity``, ``acceleration`` and ``jerk``
of the input at each, and every variable's and point's jerk at t = 0 is compared with
the five-point central difference of the accelerations in time (and the accelerations
with that of the velocities). The tolerance is ten times Richardson's estimate of the
difference's own error (steps h and h/2) plus 1e-8 of the largest value, so a chain
near a toggle (rates growing like 1/sin μ) is measured as strictly as its differences
allow, never loosely by a fixed margin.
"""

from __future__ import annotations

import numpy as np
import pytest

from machdyn.loops import LoopSystem


def _fourbar(rng):
    O4 = rng.uniform(2.0, 6.0)
    th2 = rng.uniform(0, 2 * np.pi)
    A = rng.uniform(0.5, 3.0) * np.exp(1j * th2)
    B = complex(*rng.uniform(-4.0, 6.0, 2))
    delta = rng.uniform(-np.pi, np.pi)
    s = (
        LoopSystem()
        .vector("R1", O4, 0.0)
        .vector("R2", abs(A), "theta2")
        .vector("R3", abs(B - A), "theta3")
        .vector("R4", abs(B - O4), "theta4")
        .vector("R3p", rng.uniform(0.5, 3.0), "theta3p")
        .constraint("theta3p = theta3 + delta", delta=delta)
        .loop("R2 + R3 - R4 - R1")
        .point("P = R2 + R3p")
        .inputs("theta2")
    )
    guess = {"theta3": np.angle(B - A), "theta4": np.angle(B - O4)}
    guess["theta3p"] = guess["theta3"] + delta
    return s, "theta2", th2, guess


def _slider(rng, at_slider=False):
    th2 = rng.uniform(0, 2 * np.pi)
    A = rng.uniform(0.5, 2.0) * np.exp(1j * th2)
    c = rng.uniform(-1.0, 1.0)
    d = rng.uniform(2.5, 6.0)
    B = d + 1j * c
    s = (
        LoopSystem()
        .vector("R2", abs(A), "theta2")
        .vector("R3", abs(B - A), "theta3")
        .vector("R4", "d", 0.0)
        .vector("Rc", abs(c), np.pi / 2 if c > 0 else -np.pi / 2)
        .loop("R2 + R3 - R4 - Rc")
        .point("Q = R2 + R3")
        .inputs("d" if at_slider else "theta2")
    )
    if at_slider:
        return s, "d", d, {"theta2": th2, "theta3": np.angle(B - A)}
    return s, "theta2", th2, {"theta3": np.angle(B - A), "d": d}


def _inverted(rng):
    d0 = rng.uniform(1.5, 4.0)
    th3 = rng.uniform(0, 2 * np.pi)
    b, c = rng.uniform(1.0, 4.0), rng.uniform(-1.0, 1.0)
    A = d0 + b * np.exp(1j * th3) + c * 1j * np.exp(1j * th3)
    q = np.pi / 2 if c > 0 else -np.pi / 2
    s = (
        LoopSystem()
        .vector("R1", d0, 0.0)
        .vector("R2", abs(A), "theta2")
        .vector("R3", "b", "theta3")
        .vector("Rc", abs(c), "theta3p")
        .constraint("theta3p = theta3 + q", q=q)
        .loop("R2 - R3 - Rc - R1")
        .point("T = R1 + R3")  # the slide line's point under the pin
        .inputs("theta2")
    )
    return s, "theta2", float(np.angle(A)), {"theta3": th3, "b": b, "theta3p": th3 + q}


def _watt(rng):
    s, name, th2, guess = _fourbar(rng)
    # a second loop on the rocker O4-B-C: C at a fixed angle from O4B, dyad C-D-O6
    O4 = s._vectors["R1"].length
    r4 = s._vectors["R4"].length
    th4 = guess["theta4"]
    beta, r4c = rng.uniform(-np.pi, np.pi), rng.uniform(0.5, 3.0)
    C = O4 + r4c * np.exp(1j * (th4 + beta))
    O6 = complex(*rng.uniform(-3.0, 7.0, 2))
    D = complex(*rng.uniform(-4.0, 8.0, 2))
    s = (
        s.vector("R4c", r4c, "theta4c")
        .constraint("theta4c = theta4 + beta", beta=beta)
        .vector("R5", abs(D - C), "theta5")
        .vector("R6", abs(D - O6), "theta6")
        .vector("R16", abs(O6 - O4), float(np.angle(O6 - O4)))
        .loop("R4c + R5 - R6 - R16")
        .point("D = R1 + R4c + R5")
    )
    assert r4 > 0
    guess |= {"theta4c": th4 + beta, "theta5": np.angle(D - C), "theta6": np.angle(D - O6)}
    return s, name, th2, guess


KINDS = {
    "fourbar": _fourbar,
    "slider": _slider,
    "slider at the block": lambda rng: _slider(rng, at_slider=True),
    "inverted": _inverted,
    "watt": _watt,
}


def _solve_around(s, name, q0, guess, w, a, J, h, sweep=False):
    t = h * np.arange(-2.0, 3.0)
    q = q0 + w * t + a * t**2 / 2 + J * t**3 / 6
    m = s.solve(
        {name: q},
        guess,
        velocity={name: w + a * t + J * t**2 / 2},
        acceleration={name: a + J * t},
        jerk={name: np.full(t.shape, J)},
        continuation=sweep,  # False: each time alone; True: a sweep (its own kernels)
    )
    return m


def _d5(f, h):
    """Five-point central first derivative at the middle of five samples."""
    return (f[0] - 8 * f[1] + 8 * f[3] - f[4]) / (12 * h)


def _compare(getter, m1, m2, h, what):
    """d/dt of ``getter(level)`` (by differences, steps h and h/2) vs ``getter(level + 1)``."""
    for key in getter(m1, 0):
        f1, f2 = getter(m1, 0)[key], getter(m2, 0)[key]
        exact = getter(m1, 1)[key][2]
        D1, D2 = _d5(f1, h), _d5(f2, h / 2)
        est = abs(D1 - D2)
        scale = max(np.max(np.abs(getter(m1, 1)[key])), 1.0)
        assert abs(exact - D2) <= 10 * est + 1e-8 * scale, (what, key, exact, D2, est)


@pytest.mark.parametrize("kind", list(KINDS))
@pytest.mark.parametrize("seed", range(8))
def test_loop_jerks_equal_time_differences_of_accelerations(kind, seed):
    rng = np.random.default_rng(5000 + 97 * seed + len(kind))
    h = 2e-3
    for _ in range(20):  # a chain drawn at the edge of its range may not close at t = ±2h
        s, name, q0, guess = KINDS[kind](rng)
        w, a, J = rng.uniform(-4, 4), rng.uniform(-10, 10), rng.uniform(-50, 50)
        m1 = _solve_around(s, name, q0, guess, w, a, J, h, sweep=bool(seed % 2))
        m2 = _solve_around(s, name, q0, guess, w, a, J, h / 2, sweep=bool(seed % 2))
        if m1.ok.all() and m2.ok.all():
            break
    assert m1.ok.all() and m2.ok.all(), (m1.reason, m2.reason)
    # the pose at t = 0 is the drawn one (the assembly the test built)
    for var, value in guess.items():
        assert (
            abs(np.angle(np.exp(1j * (m1.positions[var][2] - value)))) < 1e-9
            or abs(m1.positions[var][2] - value) < 1e-9
        ), (var, m1.positions[var][2], value)
    levels = ("positions", "velocity", "acceleration", "jerk")
    pts = ("points", "point_velocity", "point_acceleration", "point_jerk")

    def var(level):
        return lambda m, k: {v: np.ravel(getattr(m, levels[level + k])[v]) for v in guess}

    def point(level):
        return lambda m, k: {p: np.ravel(getattr(m, pts[level + k])[p]) for p in m.points}

    _compare(var(2), m1, m2, h, "jerk")  # jerk vs d(acceleration)/dt
    _compare(var(1), m1, m2, h, "acceleration")
    _compare(point(2), m1, m2, h, "point jerk")
    _compare(point(1), m1, m2, h, "point acceleration")


@pytest.mark.parametrize("seed", range(4))
def test_fivebar_with_two_moving_inputs_jerks(seed):
    """A five-bar driven at both cranks, each with its own ω, α and jerk."""
    rng = np.random.default_rng(7100 + seed)
    for _ in range(20):
        O5 = rng.uniform(3.0, 6.0)
        t2, t5 = rng.uniform(0, 2 * np.pi, 2)
        A = rng.uniform(1.0, 2.5) * np.exp(1j * t2)
        D = O5 + rng.uniform(1.0, 2.5) * np.exp(1j * t5)
        B = complex(*rng.uniform(-2.0, 7.0, 2))
        s = (
            LoopSystem()
            .vector("R1", O5, 0.0)
            .vector("R2", abs(A), "theta2")
            .vector("R3", abs(B - A), "theta3")
            .vector("R4", abs(B - D), "theta4")
            .vector("R5", abs(D - O5), "theta5")
            .loop("R2 + R3 - R4 - R5 - R1")
            .point("B = R2 + R3")
            .inputs("theta2", "theta5")
        )
        guess = {"theta3": np.angle(B - A), "theta4": np.angle(B - D)}
        motion = [(t2, *rng.uniform(-3, 3, 1), *rng.uniform(-9, 9, 1), *rng.uniform(-40, 40, 1))]
        motion.append(
            (t5, *rng.uniform(-3, 3, 1), *rng.uniform(-9, 9, 1), *rng.uniform(-40, 40, 1))
        )

        def solve(h, motion=motion, s=s, guess=guess):
            t = h * np.arange(-2.0, 3.0)
            names = ("theta2", "theta5")
            q = {
                n: q0 + w * t + a * t**2 / 2 + J * t**3 / 6
                for n, (q0, w, a, J) in zip(names, motion, strict=True)
            }
            return s.solve(
                q,
                guess,
                velocity={
                    n: w + a * t + J * t**2 / 2
                    for n, (_, w, a, J) in zip(names, motion, strict=True)
                },
                acceleration={n: a + J * t for n, (_, _, a, J) in zip(names, motion, strict=True)},
                jerk={n: np.full(t.shape, J) for n, (*_, J) in zip(names, motion, strict=True)},
                continuation=bool(seed % 2),
            )

        h = 2e-3
        m1, m2 = solve(h), solve(h / 2)
        if m1.ok.all() and m2.ok.all():
            break
    assert m1.ok.all() and m2.ok.all()

    def var(level):
        levels = ("positions", "velocity", "acceleration", "jerk")
        return lambda m, k: {v: np.ravel(getattr(m, levels[level + k])[v]) for v in guess}

    def point(level):
        levels = ("points", "point_velocity", "point_acceleration", "point_jerk")
        return lambda m, k: {"B": np.ravel(getattr(m, levels[level + k])["B"])}

    _compare(var(2), m1, m2, h, "jerk")
    _compare(point(2), m1, m2, h, "point jerk")
