"""Audit 4: the numbers printed in design reports, read back from the HTML.

The report's text (scripts, styles and SVG removed, tags turned to spaces) is
parsed with regular expressions and every number checked against a value
derived here:

* the notes' HW 6 four-bar (8, 4, 7, 6; coupler p = 5, δ = 30°) with masses,
  gravity and a flywheel: Grashof sums, the toggle angles (links 2 and 3
  extended or folded: law of cosines), the minimum transmission angle (at θ2 = 0,
  law of cosines), the extreme |MA| = |ω2/ω4| and peak |ω4| from this file's
  circle-intersection positions and the notes' ω4 = a ω2 sin(θ2 − θ3)/(c sin(θ4 − θ3)),
  the Berkof–Lowen counterweights (Norton §12.4) by hand, the flywheel's
  I = ΔE/(k ω²), T_avg = 0 (gravity alone does no work over a cycle), and the
  peaks of T12 against ``fourbar_dynamics`` (the library);
* docs/examples/gears.toml through ``machdyn report``: the final exam's pair
  (24/60, P_d = 8, 20°) — pitch/base/addendum radii, length of action and contact
  ratio (Norton eq. 9.2, 9.7), angles of approach and recess, the fewest teeth
  (interference condition written here) —, the compound train (speeds, torques
  by power) and Norton's Example 9-6 planetary train (Willis' formula, ΣT = 0 and
  ΣTω = 0).
"""

from __future__ import annotations

import html
import math
import re
from pathlib import Path

import numpy as np
import pytest

from machdyn import FourBar
from machdyn.cli import main
from machdyn.dynamics import fourbar_dynamics

EXAMPLES = Path(__file__).resolve().parents[1] / "docs" / "examples"
NUM = r"(-?\d+(?:\.\d+)?(?:e[+-]?\d+)?)"


def page_text(path: Path) -> str:
    s = path.read_text(encoding="utf-8")
    for tag in ("script", "style", "svg"):
        s = re.sub(rf"<{tag}\b.*?</{tag}>", " ", s, flags=re.S)
    s = re.sub(r"<[^>]+>", " ", s)
    return re.sub(r"\s+", " ", html.unescape(s))


def grab(text: str, pattern: str, n: int = 1) -> tuple[float, ...] | float:
    """The numbers of the first match of ``pattern`` (NUM marks each number)."""
    m = re.search(pattern.replace("NUM", NUM), text)
    assert m, f"not in the report: {pattern}"
    values = tuple(float(g) for g in m.groups())
    return values[0] if n == 1 else values


def close(printed: float, exact: float, digits: int = 4) -> bool:
    """``printed`` is ``exact`` shown to ``digits`` significant digits (or better)."""
    return abs(printed - exact) <= 0.6 * 10 ** (math.floor(math.log10(abs(exact))) - digits + 1)


R1, R2, R3, R4 = 8.0, 4.0, 7.0, 6.0
MASS, INERTIA, CG = (1.0, 2.0, 1.5), (0.1, 0.5, 0.3), (2.0, 3.5 + 0.5j, 3.0)


@pytest.fixture(scope="module")
def hw6(tmp_path_factory):
    fb = FourBar(R1, R2, R3, R4, coupler=(5, np.radians(30)))
    path = tmp_path_factory.mktemp("report") / "hw6.html"
    fb.report(path, omega2=10.0, mass=MASS, inertia=INERTIA, cg=CG, gravity=9.81, k=0.05)
    return fb, page_text(path)


def test_fourbar_report_geometry_by_the_law_of_cosines(hw6):
    _, text = hw6
    s_l, p_q = grab(text, r"s \+ l = NUM model units vs p \+ q = NUM", 2)
    assert (s_l, p_q) == (min(R1, R2, R3, R4) + max(R1, R2, R3, R4), 13.0)
    # toggles of links 2 and 3: O2B = r2 ± r3 in the triangle O2 B O4
    for kind, o2b, sign in (("extended", R2 + R3, 1), ("folded", R3 - R2, -1)):
        beta = math.degrees(math.acos((o2b**2 + R1**2 - R4**2) / (2 * o2b * R1)))
        first = beta if sign > 0 else 180 - beta
        for angle in (first, 360 - first):
            assert re.search(rf"{angle:.3f} 2 and 3 {kind}", text), (kind, angle)
    # μ at θ2 = 0 (the closest approach of A to O4): the least for this crank-rocker
    f = R1 - R2
    mu_min = math.degrees(math.acos((R3**2 + R4**2 - f**2) / (2 * R3 * R4)))
    mu, at = grab(text, r"minimum transmission angle μ NUM° at θ2 = NUM°", 2)
    assert mu == pytest.approx(mu_min, abs=6e-4) and at == 0.0
    assert "design limit 40° (NOT met)" in text


def _omega4_by_hand(theta2):
    """ω4/ω2 of form 1 (B above O2O4 here) from circle intersection and the notes' ratio."""
    A = R2 * np.exp(1j * theta2)
    d = np.abs(R1 - A)
    x = (R3**2 - R4**2 + d**2) / (2 * d)
    B = A + (R1 - A) / d * (x + 1j * np.sqrt(R3**2 - x**2))
    t3, t4 = np.angle(B - A), np.angle(B - R1)
    return R2 * np.sin(theta2 - t3) / (R4 * np.sin(t4 - t3))


def test_fourbar_report_mechanical_advantage_and_speeds_by_hand(hw6):
    fb, text = hw6
    theta2 = np.radians(np.arange(360.0))
    assert fb.solve(theta2[:1]).B[0].imag > 0  # form 1 is the upper assembly here
    ratio = _omega4_by_hand(theta2)
    ma = np.abs(1 / ratio)
    lo, at_lo = grab(text, r"\|MA\| smallest \(r_in = r_out\) NUM at θ2 = NUM°", 2)
    hi, at_hi = grab(text, r"\|MA\| largest NUM at θ2 = NUM°", 2)
    assert close(lo, ma.min()) and at_lo == np.argmin(ma)
    assert close(hi, ma.max()) and at_hi == np.argmax(ma)
    w4, at = grab(text, r"peak \|omega4\| NUM rad/s at θ2 = NUM°", 2)
    assert close(w4, 10 * np.abs(ratio).max()) and at == np.argmax(np.abs(ratio))


def test_fourbar_report_forces_flywheel_and_counterweights(hw6):
    fb, text = hw6
    theta2 = np.radians(np.arange(360.0))
    f = fourbar_dynamics(fb, theta2, 10.0, 0.0, mass=MASS, inertia=INERTIA, cg=CG, gravity=9.81)
    t_max, at_max = grab(text, r"T12 largest NUM torque units at θ2 = NUM°", 2)
    t_min, at_min = grab(text, r"T12 smallest NUM torque units at θ2 = NUM°", 2)
    assert close(t_max, f.T12.max()) and at_max == np.argmax(f.T12)
    assert close(t_min, f.T12.min()) and at_min == np.argmin(f.T12)
    fs = grab(text, r"peak \|shaking force\| NUM force units")
    assert close(fs, np.abs(f.shaking_force).max())
    # gravity alone does no work over a cycle: the average driving torque is zero
    t_avg = grab(text, r"average torque NUM torque units")
    assert abs(t_avg) < 1e-9 * np.abs(f.T12).max()
    delta_e = grab(text, r"energy to swing ΔE NUM energy units")
    inertia = grab(text, r"flywheel inertia I = ΔE/\(k ω²\) NUM inertia units")
    assert close(inertia, delta_e / (0.05 * 10.0**2), 3)
    # Berkof–Lowen: m2 c2 + mR2 = −m3 r2 (1 − c3/r3), m4 c4 + mR4 = −m3 c3 r4/r3
    mR2 = -MASS[1] * R2 * (1 - CG[1] / R3) - MASS[0] * CG[0]
    mR4 = -MASS[1] * CG[1] * R4 / R3 - MASS[2] * CG[2]
    for link, mR in ((2, mR2), (4, mR4)):
        size, angle = grab(
            text,
            rf"counterweight m·R on link {link} NUM mass·length units at NUM° \(link frame\)",
            2,
        )
        assert close(size, abs(mR)) and angle == pytest.approx(math.degrees(np.angle(mR)), abs=6e-3)
    # after the balance only the weight is left (counterweights of the links' own masses)
    after = grab(text, r"peak \|shaking force\| after NUM force units")
    weight = (sum(MASS) + MASS[0] + MASS[2]) * 9.81
    assert close(after, weight)


@pytest.fixture(scope="module")
def gears_page(tmp_path_factory):
    path = tmp_path_factory.mktemp("report") / "gears.html"
    assert main(["report", str(EXAMPLES / "gears.toml"), "-o", str(path)]) == 0
    return page_text(path)


def test_gear_pair_report_by_nortons_formulas(gears_page, capsys):
    capsys.readouterr()
    text = gears_page
    Np, Ng, Pd, phi = 24, 60, 8.0, math.radians(20)
    rp, rg, add, ded = Np / (2 * Pd), Ng / (2 * Pd), 1 / Pd, 1.25 / Pd
    rbp, rbg = rp * math.cos(phi), rg * math.cos(phi)
    assert grab(text, r"pitch radius r NUM in NUM in", 2) == (rp, rg)
    base = grab(text, r"base radius r_b NUM in NUM in", 2)
    assert close(base[0], rbp, 6) and close(base[1], rbg, 6)
    assert grab(text, r"addendum radius r_a NUM in NUM in", 2) == (rp + add, rg + add)
    assert grab(text, r"root radius NUM in NUM in", 2) == (rp - ded, rg - ded)
    C = rp + rg
    assert grab(text, r"centre distance C' NUM in") == C
    approach = math.sqrt((rg + add) ** 2 - rbg**2) - rg * math.sin(phi)
    recess = math.sqrt((rp + add) ** 2 - rbp**2) - rp * math.sin(phi)
    Z = approach + recess
    pb = 2 * math.pi * rbp / Np
    assert close(grab(text, r"length of action Z NUM in"), Z, 6)
    a, r = grab(text, r"path of approach, recess NUM in, NUM in", 2)
    assert close(a, approach, 6) and close(r, recess, 6)
    assert close(grab(text, r"base pitch p_b NUM in"), pb, 6)
    assert close(grab(text, r"contact ratio m_p = Z / p_b NUM"), Z / pb, 6)
    ap, ag = grab(text, r"angles of approach \(pinion, gear\) NUM°, NUM°", 2)
    assert close(ap, math.degrees(approach / rbp), 6) and close(ag, math.degrees(approach / rbg), 6)
    assert grab(text, r"gear speed ω_g NUM rpm") == -1800 * Np / Ng

    # fewest pinion teeth with no interference: the mate's tip circle must stay inside
    # the pinion's interference point, r_a² ≤ r_b² + (C sin φ)² (all in module units)
    def clear(n_p, n_g):
        r_p, r_g = n_p / 2, n_g / 2
        return (r_g + 1) ** 2 <= (r_g * math.cos(phi)) ** 2 + ((r_p + r_g) * math.sin(phi)) ** 2

    fewest_with_60 = next(n for n in range(5, 60) if clear(n, 60))
    fewest_equal = next(n for n in range(5, 60) if clear(n, n))
    fewest_rack = math.ceil(2 / math.sin(phi) ** 2)  # Norton eq. 9.4b: 2k / sin²φ
    assert grab(text, r"fewest pinion teeth with this 60-tooth gear NUM") == fewest_with_60 == 16
    assert grab(text, r"fewest teeth of two equal gears NUM") == fewest_equal == 13
    assert grab(text, r"fewest pinion teeth against a rack NUM") == fewest_rack == 18


def test_gear_trains_report_speeds_and_torques_by_hand(gears_page):
    text = gears_page
    # compound train 18:54, 20:60 at 1800 rpm, unit input torque
    shafts = r"input 18 NUM rpm .*? 1 N·in 2 54 \+ 20 NUM rpm .*? NUM N·in output 60 NUM rpm"
    m = re.search((shafts + r" .*? NUM N·in").replace("NUM", NUM), text)
    assert m, "shaft table"
    w_in, w2, t2, w_out, t_out = (float(g) for g in m.groups())
    assert (w_in, w2, w_out) == (1800.0, -1800 * 18 / 54, 1800 * 18 / 54 * 20 / 60)
    # T = P/ω with the power T_in ω_in carried through
    assert t2 == pytest.approx(w_in / w2) and t_out == pytest.approx(w_in / w_out)
    # Norton Example 9-6: sun 40, planet 20, ring 80; arm −200 rpm, sun +100 rpm
    R = -40 / 80
    w_ring = -200 + R * (100 - (-200))
    w_planet = -200 + (-40 / 20) * (100 - (-200))
    assert grab(text, r"ring -200 rpm NUM rpm NUM rpm", 2) == (R * 300, w_ring)
    assert grab(text, r"planet -200 rpm NUM rpm NUM rpm", 2) == (-2 * 300, w_planet)
    # torques: T_F = −R T_L, T_A = −(1 − R) T_L for a unit sun torque; ΣT = 0, ΣTω = 0
    t_sun = grab(text, r"sun \(given\) NUM N·in NUM")
    t_ring, t_arm = grab(text, r"ring NUM N·in NUM arm NUM N·in", 3)[::2]
    assert t_sun == 1.0 and t_ring == pytest.approx(-t_sun / R)
    assert t_arm == pytest.approx(-(1 - R) * t_ring)
    assert t_sun * 100 + t_ring * w_ring + t_arm * -200 == pytest.approx(0, abs=1e-9)


def test_placed_fourbar_report_applies_gravity_along_the_plane(tmp_path, capsys):
    """A four-bar placed at θ1 = 90° (its ground line vertical) under gravity: its report's
    T12 extremes equal those of the same linkage drawn with its ground line along +x
    and gravity along +x of that frame, i.e. a point load m g (−j e^{−jθ1}) = −m g at
    each centre of mass, here computed by ``fourbar_dynamics`` with those loads."""
    fb = FourBar(R1, R2, R3, R4)
    text = (
        'machdyn = 1\ngravity = true\n[units]\nlength = "m"\nmass = "kg"\n'
        f"[fourbar.f]\nr1 = {R1}\nr2 = {R2}\nr3 = {R3}\nr4 = {R4}\ntheta1 = 90\n"
        '[fourbar.f.motion]\ntheta2 = [0, 359, 1]\nomega2 = "2 rad/s"\n'
        + "".join(
            f"[fourbar.f.link{k}]\nmass = {m}\ninertia = {i}\ncg = [{c.real}, {c.imag}]\n"
            for k, m, i, c in zip((2, 3, 4), MASS, INERTIA, (complex(c) for c in CG), strict=True)
        )
    )
    path = tmp_path / "placed.toml"
    path.write_text(text)
    assert main(["report", str(path), "-o", str(tmp_path / "p.html")]) == 0
    capsys.readouterr()
    page = page_text(tmp_path / "p.html")
    theta2 = np.radians(np.arange(360.0))
    weights = [
        (k, complex(c), -9.80665 * m + 0j) for k, m, c in zip((2, 3, 4), MASS, CG, strict=True)
    ]
    f = fourbar_dynamics(
        fb, theta2, 2.0, 0.0, mass=MASS, inertia=INERTIA, cg=CG, external_forces=weights
    )
    t_max, at_max = grab(page, r"T12 largest NUM N·m at θ2 = NUM°", 2)
    assert close(t_max, f.T12.max()) and at_max == np.argmax(f.T12)
