"""Tests of machdyn.shaking: four-bar shaking-force balance (Berkof–Lowen).

Independent check: after adding the counterweights, the shaking force computed
by the Newton–Euler solver (machdyn.dynamics, a different code path) is zero
over a full cycle, and the total centre of mass, computed here from the
positions alone, does not move.
"""

from __future__ import annotations

import numpy as np
import pytest

from machdyn.dynamics import fourbar_dynamics
from machdyn.errors import InputError
from machdyn.fourbar import FourBar
from machdyn.shaking import Counterweights, fourbar_counterweights


def total_centre(fb, motion, mass, cg):
    r1, r2, _, _ = fb.lengths
    e2, e3, e4 = (np.exp(1j * t) for t in (motion.theta2, motion.theta3, motion.theta4))
    rG = (cg[0] * e2, r2 * e2 + cg[1] * e3, r1 + cg[2] * e4)
    return sum(m * r for m, r in zip(mass, rG, strict=True)) / sum(mass)


@pytest.mark.parametrize(
    ("lengths", "mass", "inertia", "cg"),
    [
        ((8, 4, 7, 6), (1.0, 2.0, 1.5), (0.2, 1.0, 0.5), (2.0, 3.5 + 0.5j, 3.0)),
        ((6, 2, 7, 9), (0.5, 3.0, 2.0), (0.05, 2.0, 1.2), (1.0 - 0.2j, 2.0 - 1.0j, 4.0 + 1j)),
    ],
)
def test_balanced_fourbar_has_no_shaking_force(lengths, mass, inertia, cg):
    fb = FourBar(*lengths)
    theta2 = np.linspace(0, 2 * np.pi, 181)
    before = fourbar_dynamics(fb, theta2, 20.0, 5.0, mass=mass, inertia=inertia, cg=cg)
    cw = fourbar_counterweights(fb, mass, cg)
    m, i, c = cw.apply(mass, inertia, cg, counterweight_mass=(1.5, 2.5))
    after = fourbar_dynamics(fb, theta2, 20.0, 5.0, mass=m, inertia=i, cg=c)
    scale = np.max(np.abs(before.shaking_force))
    assert scale > 1.0  # it was unbalanced
    np.testing.assert_allclose(after.shaking_force, 0.0, atol=1e-11 * scale)
    # the centre of mass of the whole linkage does not move
    centre = total_centre(fb, after.motion, m, c)
    np.testing.assert_allclose(centre, centre[0], atol=1e-12 * max(lengths))


def test_counterweight_formula_by_hand():
    """Uniform links: crank 1 kg (c2 = 2), coupler 2 kg (c3 = 3.5 of 7), rocker 1 kg (c4 = 3).
    m2 c2 + mR2 = −m3 r2 (1 − c3/r3) = −2·4·0.5 = −4 → mR2 = −6;
    m4 c4 + mR4 = −m3 c3 r4 / r3 = −2·3.5·6/7 = −6 → mR4 = −9."""
    cw = fourbar_counterweights(FourBar(8, 4, 7, 6), (1, 2, 1), (2, 3.5, 3))
    assert cw.mR2 == pytest.approx(-6.0) and cw.mR4 == pytest.approx(-9.0)


def test_apply_keeps_mass_moment_and_uses_parallel_axis():
    cw = Counterweights(-6.0 + 1j, -9.0)
    m, i, c = cw.apply((1, 2, 1), (0.3, 1.0, 0.4), (2, 3.5, 3), (3.0, 3.0))
    assert m == (4.0, 2.0, 4.0)
    assert m[0] * c[0] == pytest.approx(1 * 2 - 6 + 1j)
    # link 4: 1 kg at 3 and 3 kg at −3 → centre −1.5, I = 0.4 + 1·4.5² + 3·1.5²
    assert c[2] == pytest.approx(-1.5)
    assert i[2] == pytest.approx(0.4 + 4.5**2 + 3 * 1.5**2)


def test_bad_input():
    fb = FourBar(8, 4, 7, 6)
    with pytest.raises(InputError):
        fourbar_counterweights(fb, (1, 2), (0, 0, 0))
    with pytest.raises(InputError):
        fourbar_counterweights(fb, (1, -2, 1), (0, 0, 0))
    with pytest.raises(InputError):
        Counterweights(1, 1).apply((1, 1, 1), (1, 1, 1), (0, 0, 0), (0.0, 1.0))
