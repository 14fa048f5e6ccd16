"""Property tests over random programs and followers (hypothesis, ci profile)."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from machdyn.cams import CamProgram, TranslatingRoller, pressure_angle, size_roller

LAWS = ["cycloidal", "modified_sine", "modified_trapezoid", "poly345", "poly4567"]

programs = st.builds(
    lambda law, h, rise, fall: CamProgram.double_dwell(h, np.radians(rise), np.radians(fall), law),
    st.sampled_from(LAWS),
    st.floats(0.2, 2.0),
    st.floats(40.0, 140.0),
    st.floats(40.0, 140.0),
)


@given(program=programs, rp=st.floats(2.0, 6.0), eps_share=st.floats(-0.5, 0.5))
def test_pressure_angle_is_the_geometric_angle(program, rp, eps_share):
    eps = eps_share * rp
    cam = TranslatingRoller(rp, 0.0, eps).profile(program, n=8000)
    step = cam.theta[1] - cam.theta[0]
    dz = (np.roll(cam.pitch, -1) - np.roll(cam.pitch, 1)) / (2 * step)
    # Fixed-frame tangent, its outward normal, angle from the follower axis (+y).
    normal = 1j * dz * np.exp(1j * cam.theta)
    np.testing.assert_allclose(cam.pressure_angle, np.angle(normal / 1j), atol=5e-5)


@given(program=programs, eps_share=st.floats(-0.3, 0.3), limit_deg=st.floats(15.0, 40.0))
def test_size_roller_hits_the_limit(program, eps_share, limit_deg):
    m = program.sample(1800)
    eps = eps_share * 2.0
    sized = size_roller(
        m, roller_radius=0.0, eccentricity=eps, max_pressure_angle=np.radians(limit_deg)
    )
    phi = np.abs(pressure_angle(m.s, m.v, sized.prime_radius, eps))
    assert phi.max() == pytest.approx(np.radians(limit_deg), abs=1e-9)


@given(program=programs)
def test_program_round_trip_svaj_integrates(program):
    # ∫v dθ over the turn is 0 (the follower returns) and s is the running integral of v.
    m = program.sample(20000)
    step = 2 * np.pi / 20000
    running = np.concatenate(([0.0], np.cumsum((m.v[1:] + m.v[:-1]) / 2) * step))
    np.testing.assert_allclose(running, m.s, atol=1e-5)
