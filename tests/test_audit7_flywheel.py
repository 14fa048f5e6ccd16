"""Audit 7: flywheel sizing against a torque curve whose energy is known in closed form.

The notes (flywheels, Table 11-1 method; Norton sec. 11.11):
``ΔE = E_max − E_min`` of ``E(θ) = ∫ (T12 − T_avg) dθ``, ``I = ΔE / (k ω_avg²)``,
and the flywheel runs fastest where the load has taken least energy. Here the
torque is a random Fourier series, so ``T_avg`` is its constant term and
``E(θ)`` is the series integrated term by term; its extremes are found on a
grid 100 times finer than the samples given to machdyn (an independent
quadrature: the exact integral, not a trapezoid sum of the same samples).
"""

from __future__ import annotations

import numpy as np
import pytest

from machdyn.flywheel import size_flywheel


def fourier(rng, period):
    terms = int(rng.integers(1, 6))
    a, b = rng.normal(size=terms), rng.normal(size=terms)
    mean = float(rng.uniform(-5, 5))
    k = np.arange(1, terms + 1)[:, None] * 2 * np.pi / period

    def torque(x):
        return mean + np.sum(a[:, None] * np.cos(k * x) + b[:, None] * np.sin(k * x), axis=0)

    def energy(x):  # ∫ (T − T_avg) dθ from an arbitrary origin
        return np.sum((a[:, None] * np.sin(k * x) - b[:, None] * np.cos(k * x)) / k, axis=0)

    return mean, torque, energy


def same_angle(a, b, period):
    gap = abs((a - b + period / 2) % period - period / 2)
    return gap < 0.02 * period


@pytest.mark.parametrize("seed", range(6))
def test_energy_fluctuation_inertia_and_speed_extremes(seed):
    rng = np.random.default_rng(seed)
    for _ in range(10):
        period = float(rng.choice([2 * np.pi, 4 * np.pi]))  # a 4-stroke cycle is 4π
        mean, torque, energy = fourier(rng, period)
        start = float(rng.uniform(-3, 3))
        n = int(rng.integers(720, 2000))
        theta = start + np.sort(rng.uniform(0.0, period, n))  # uneven spacing
        theta[0] = start
        omega_avg = float(rng.uniform(5, 200))
        k = float(rng.uniform(0.005, 0.1))
        fw = size_flywheel(theta, torque(theta), omega_avg, k, period=period)

        fine = np.linspace(start, start + period, 100 * n + 1)
        e = energy(fine)
        delta_e = e.max() - e.min()
        assert fw.torque_avg == pytest.approx(mean, abs=2e-3 * (1 + abs(mean)))
        assert fw.delta_e == pytest.approx(delta_e, rel=1e-2)
        assert fw.inertia == pytest.approx(delta_e / (k * omega_avg**2), rel=1e-2)

        # ω is highest where the load has drawn least energy, lowest where most.
        assert same_angle(fw.theta_omega_max, fine[np.argmin(e)], period)
        assert same_angle(fw.theta_omega_min, fine[np.argmax(e)], period)

        # The speed curve obeys ½ I (ω² − ω_ref²) = −(E − E_ref) and averages ω_avg in time.
        w = fw.omega
        e_at = energy(fw.theta[: w.size])
        lhs = 0.5 * fw.inertia * (w**2 - w[0] ** 2)
        np.testing.assert_allclose(lhs, -(e_at - e_at[0]), atol=2e-2 * delta_e)
        t = np.concatenate(([0.0], np.cumsum(np.diff(fw.theta[: w.size]) * 2 / (w[1:] + w[:-1]))))
        assert (fw.theta[w.size - 1] - fw.theta[0]) / t[-1] == pytest.approx(omega_avg, rel=2e-3)
        # The fluctuation achieved: (ω_max − ω_min)/ω_avg ≈ k (exactly k to first order).
        assert fw.k_achieved == pytest.approx(k, rel=0.05 + 2 * k)


def test_notes_relation_i_is_delta_e_over_k_omega_squared():
    """A single harmonic T = T0 + A sin θ: E = −A cos θ, ΔE = 2A, I = 2A/(k ω²)."""
    theta = np.radians(np.arange(0.0, 360.0, 0.25))
    fw = size_flywheel(theta, 40.0 + 7.0 * np.sin(theta), omega_avg=30.0, k=0.02)
    assert fw.delta_e == pytest.approx(14.0, rel=1e-5)
    assert fw.inertia == pytest.approx(14.0 / (0.02 * 900.0), rel=1e-5)
    # The load takes energy fastest at θ = 90°: ω is lowest at the end of the positive lobe
    # (θ = 180°) and highest at its start (θ = 0).
    assert np.degrees(fw.theta_omega_min) % 360 == pytest.approx(180.0, abs=0.5)
    assert np.degrees(fw.theta_omega_max) % 360 == pytest.approx(0.0, abs=0.5) or np.degrees(
        fw.theta_omega_max
    ) % 360 == pytest.approx(360.0, abs=0.5)
