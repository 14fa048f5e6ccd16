"""Sensitivity tables of a model given units (issue #11 item 5): columns named with the quotient of
the output's and the dimension's display units, values converted to them by hand factors here."""

from __future__ import annotations

from pathlib import Path

import numpy as np

import machdyn
from machdyn import FourBar
from machdyn.sensitivity import sensitivity

EXAMPLES = Path(__file__).resolve().parents[1] / "docs" / "examples"
DEG_PER_RAD = 180.0 / np.pi


def test_a_millimetre_linkage_labels_and_converts_every_column():
    watt = machdyn.load(EXAMPLES / "watt.toml")  # lengths in mm, angles shown in degrees
    theta = np.radians([10.0, 20.0, 30.0])
    s = sensitivity(watt, theta)
    df = s.to_pandas()
    np.testing.assert_allclose(df["theta [deg]"], [10.0, 20.0, 30.0], rtol=1e-12)
    # an angle per length: radians per mm → degrees per mm
    np.testing.assert_allclose(
        df["dtheta.output/dO2.x [deg/mm]"], DEG_PER_RAD * s.of("theta.output", "O2.x"), rtol=1e-12
    )
    # a point per length: mm per mm, its x and y parts
    dP = s.of("point.P", "B.y")
    np.testing.assert_allclose(df["dpoint.P_x/dB.y [mm/mm]"], dP.real, rtol=1e-12)
    np.testing.assert_allclose(df["dpoint.P_y/dB.y [mm/mm]"], dP.imag, rtol=1e-12)
    # rates keep their own units, a compound one bracketed
    assert "dalpha.output/dO2.x [(rad/s^2)/mm]" in df.columns
    assert "dvelocity.P_x/dO2.x [(mm/s)/mm]" in df.columns
    assert all("[" in c for c in df.columns if c != "ok")


def test_an_inch_four_bar_and_a_unit_free_one():
    hw6 = machdyn.load(EXAMPLES / "hw6.toml")  # Norton-style inches
    s = sensitivity(hw6, [0.3, 0.6])
    df = s.to_pandas()
    np.testing.assert_allclose(df["dtheta4/dr3 [deg/in]"], DEG_PER_RAD * s.of("theta4", "r3"))
    plain = sensitivity(FourBar(8, 4, 7, 6), [0.3]).to_pandas()
    assert list(plain.columns[:3]) == ["theta", "dtheta3/dr1", "dtheta3/dr2"]


def test_centrodes_of_a_millimetre_linkage_carry_units():
    """The coupler's fixed centrode is I13, where the lines O2A and O4B cross (Kennedy),
    intersected here from the solved pins; shown in the file's mm, the crank angle in deg."""
    from machdyn.centrodes import centrodes

    watt = machdyn.load(EXAMPLES / "watt.toml")
    theta = np.radians([10.0, 20.0, 30.0])
    df = centrodes(watt, theta, moving="coupler").to_pandas()
    m = watt.solve(theta)
    O2, O4, A, B = (m.points[n] for n in ("O2", "O4", "A", "B"))
    u, v = A - O2, B - O4  # O2 + s u = O4 + t v
    s = ((O4 - O2).real * v.imag - (O4 - O2).imag * v.real) / (u.real * v.imag - u.imag * v.real)
    I13 = O2 + s * u
    np.testing.assert_allclose(df["parameter [deg]"], [10.0, 20.0, 30.0], rtol=1e-12)
    np.testing.assert_allclose(df["fixed_x [mm]"], I13.real, rtol=1e-9)
    np.testing.assert_allclose(df["fixed_y [mm]"], I13.imag, rtol=1e-9)
