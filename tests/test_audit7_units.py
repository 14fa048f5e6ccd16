"""Audit 7: a machine file in inch, lbf and degrees gives the SI file's answers, converted.

The parts earlier audits left out: a cam (translating and oscillating roller),
a flywheel from a torque table and a rotor to balance. Each is written twice,
once in SI with radians where the format allows, once in US customary units
(in, lbf, lbf·s²/in, deg) with the same physical values converted here by the
exact factors 1 in = 0.0254 m and 1 lbf = 4.4482216152605 N; every number the
run prints must agree after the same factors (pint is not used on the
expected side).
"""

from __future__ import annotations

import json
import math

import pytest

from machdyn.cli import main

IN = 0.0254
LBF = 4.4482216152605
BLOB = LBF / IN  # lbf·s²/in in kg


def run_json(tmp_path, name, text, capsys):
    path = tmp_path / name
    path.write_text(text)
    assert main(["run", str(path), "--json"]) in (0, None)
    return json.loads(capsys.readouterr().out)["parts"]


def numbers(part):
    """The summary's numbers by key (lists kept as lists)."""
    return {
        k: v
        for k, v in part["summary"].items()
        if isinstance(v, int | float)
        or (isinstance(v, list) and all(isinstance(x, float) for x in v))
    }


CAM = """machdyn = 1
[units]
{units}
[cam.c]
speed = "{speed}"
step = "{step}"
[cam.c.follower]
{follower}
[[cam.c.segment]]
motion = "rise"
law = "poly345"
lift = {lift}
beta = {b1}
[[cam.c.segment]]
motion = "dwell"
beta = {b2}
[[cam.c.segment]]
motion = "fall"
law = "cycloidal"
lift = {lift}
beta = {b1}
[[cam.c.segment]]
motion = "dwell"
beta = {b2}
"""


@pytest.mark.parametrize("kind", ["roller", "oscillating"])
def test_cam_in_inches_and_degrees_equals_the_si_cam(kind, tmp_path, capsys):
    rp, rf, ecc, c, arm = 3.0, 0.5, 0.4, 4.0, 3.5  # inches
    lift_deg = 20.0
    if kind == "roller":
        us_f = f'type = "roller"\nprime_radius = {rp}\nroller_radius = {rf}\neccentricity = {ecc}'
        si_f = (
            f'type = "roller"\nprime_radius = {rp * IN!r}\nroller_radius = {rf * IN!r}\n'
            f"eccentricity = {ecc * IN!r}"
        )
        us_lift, si_lift = "1.25", repr(1.25 * IN)
    else:
        us_f = (
            f'type = "oscillating"\nprime_radius = {rp}\nroller_radius = {rf}\n'
            f'pivot_distance = {c}\narm_length = {arm}\npivot_side = "left"'
        )
        si_f = (
            f'type = "oscillating"\nprime_radius = {rp * IN!r}\nroller_radius = {rf * IN!r}\n'
            f'pivot_distance = {c * IN!r}\narm_length = {arm * IN!r}\npivot_side = "left"'
        )
        us_lift, si_lift = f'"{lift_deg} deg"', f'"{math.radians(lift_deg)!r} rad"'
    us = CAM.format(
        units='length = "in"\nforce = "lbf"\nangle = "deg"',
        speed="100 rpm",
        step="15 deg",
        follower=us_f,
        lift=us_lift,
        b1=90,
        b2=90,
    )
    si = CAM.format(
        units='length = "m"\nforce = "N"\nangle = "rad"',
        speed=f"{100 * 2 * math.pi / 60!r} rad/s",
        step=f"{math.radians(15)!r} rad",
        follower=si_f,
        lift=si_lift,
        b1=repr(math.pi / 2),
        b2=repr(math.pi / 2),
    )
    a = run_json(tmp_path, "us.toml", us, capsys)["c"]
    b = run_json(tmp_path, "si.toml", si, capsys)["c"]
    na, nb = numbers(a), numbers(b)
    for key, value in na.items():
        si_key = key.replace("[in]", "[m]").replace("[deg]", "[rad]")
        factor = IN if "[in]" in key else (math.pi / 180 if "[deg]" in key else 1.0)
        assert nb[si_key] == pytest.approx(value * factor, rel=1e-9), key
    assert any("[in]" in k for k in na) and any("[deg]" in k for k in na)
    # the profile table: x, y, ρ in inches vs metres; angles in degrees vs radians
    ta, tb = a["tables"]["profile"], b["tables"]["profile"]
    for col_a, col_b in zip(ta["columns"], tb["columns"], strict=True):
        factor = IN if "[in]" in col_a else (math.pi / 180 if "[deg]" in col_a else 1.0)
        ia, ib = ta["columns"].index(col_a), tb["columns"].index(col_b)
        for ra, rb in zip(ta["rows"], tb["rows"], strict=True):
            assert rb[ib] == pytest.approx(ra[ia] * factor, rel=1e-9, abs=1e-12), col_a


FLYWHEEL = """machdyn = 1
[units]
{units}
[flywheel.f]
theta = {theta}
torque = {torque}
omega_avg = "{omega}"
k = 0.02
density = "{density}"
thickness = {thickness}
"""


def test_flywheel_in_lbf_inch_and_degrees_equals_the_si_flywheel(tmp_path, capsys):
    deg = list(range(0, 361, 15))
    t_lbf_in = [
        400 + 90 * math.sin(math.radians(d)) + 35 * math.sin(math.radians(2 * d)) for d in deg
    ]
    us = FLYWHEEL.format(
        units='length = "in"\nforce = "lbf"\nmass = "lbf*s^2/in"\nangle = "deg"',
        theta=deg,
        torque=t_lbf_in,
        omega="500 rpm",
        density="0.283 lb/in^3",
        thickness=1.5,
    )
    si = FLYWHEEL.format(
        units='length = "m"\nforce = "N"\nmass = "kg"\nangle = "rad"',
        theta=[math.radians(d) for d in deg],
        torque=[t * LBF * IN for t in t_lbf_in],
        omega=f"{500 * 2 * math.pi / 60!r} rad/s",
        density=f"{0.283 * 0.45359237 / IN**3!r} kg/m^3",
        thickness=1.5 * IN,
    )
    a = numbers(run_json(tmp_path, "us.toml", us, capsys)["f"])
    b = numbers(run_json(tmp_path, "si.toml", si, capsys)["f"])
    energy = LBF * IN
    checks = {
        "T_avg": energy,
        "delta_E": energy,
        "I (flywheel inertia)": BLOB * IN**2,
        "disc outer radius": IN,
        "disc mass": BLOB,
    }
    for stem, factor in checks.items():
        ka = next(k for k in a if k.startswith(stem))
        kb = next(k for k in b if k.startswith(stem))
        assert b[kb] == pytest.approx(a[ka] * factor, rel=1e-9), (ka, kb)
    # ΔE by hand: the polyline of 15° samples of 90 sin θ + 35 sin 2θ about T_avg = 400
    assert a[next(k for k in a if k.startswith("T_avg"))] == pytest.approx(400.0, rel=1e-12)


ROTOR = """machdyn = 1
[units]
{units}
[rotor.r]
planes = {planes}
radii = {radii}
speed = "1500 rpm"
[[rotor.r.mass]]
mass = {m1}
radius = {r1}
angle = {a1}
z = {z1}
[[rotor.r.mass]]
mass = {m2}
radius = {r2}
angle = {a2}
z = {z2}
"""


def test_rotor_in_inches_and_pounds_equals_the_si_rotor(tmp_path, capsys):
    us = ROTOR.format(
        units='length = "in"\nforce = "lbf"\nmass = "lbf*s^2/in"\nangle = "deg"',
        planes=[0, 16],
        radii=[4, 4],
        m1=0.002,
        r1=2.5,
        a1=30,
        z1=4,
        m2=0.003,
        r2=2.0,
        a2=150,
        z2=20,
    )
    si = ROTOR.format(
        units='length = "m"\nforce = "N"\nmass = "kg"\nangle = "rad"',
        planes=[0.0, 16 * IN],
        radii=[4 * IN, 4 * IN],
        m1=0.002 * BLOB,
        r1=2.5 * IN,
        a1=math.radians(30),
        z1=4 * IN,
        m2=0.003 * BLOB,
        r2=2.0 * IN,
        a2=math.radians(150),
        z2=20 * IN,
    )
    a = run_json(tmp_path, "us.toml", us, capsys)["r"]
    b = run_json(tmp_path, "si.toml", si, capsys)["r"]
    ta, tb = a["tables"]["corrections"], b["tables"]["corrections"]
    for row_a, row_b in zip(ta["rows"], tb["rows"], strict=True):
        for col, va, vb in zip(ta["columns"], row_a, row_b, strict=True):
            if isinstance(va, str):
                assert va == vb
                continue
            factor = {"z": IN, "mR": BLOB * IN, "angle": math.pi / 180, "mass": BLOB}[
                col.split(" ")[0]
            ]
            assert vb == pytest.approx(va * factor, rel=1e-9, abs=1e-15), col
    # by hand (moments about plane A, then forces): m_B R_B = −Σ m R z / 16 in
    u1 = 0.002 * 2.5 * complex(math.cos(math.radians(30)), math.sin(math.radians(30)))
    u2 = 0.003 * 2.0 * complex(math.cos(math.radians(150)), math.sin(math.radians(150)))
    b_fix = -(u1 * 4 + u2 * 20) / 16
    a_fix = -(u1 + u2) - b_fix
    mr = {row[0]: row[2] for row in ta["rows"]}
    assert mr["A"] == pytest.approx(abs(a_fix), rel=1e-9)
    assert mr["B"] == pytest.approx(abs(b_fix), rel=1e-9)


def test_slider_cranks_in_units_take_the_default_offset():
    """SliderCrank(2 in, 6 in) was refused ("offset: give every length with a unit") because
    the default offset 0 carries none; a plain 0 is zero in any unit."""
    import numpy as np

    from machdyn import InvertedSliderCrank, SliderCrank
    from machdyn.units import registry

    q = registry().Quantity
    sc = SliderCrank(q(2, "in"), q(6, "in"))
    assert sc.length_unit == "inch" and sc.c == 0.0
    t2 = np.radians([0.0, 30.0, 90.0])
    # d = a cos θ2 + √(b² − a² sin² θ2) in inches, written here
    expected = 2 * np.cos(t2) + np.sqrt(36 - 4 * np.sin(t2) ** 2)
    np.testing.assert_allclose(sc.solve(t2).d, expected, rtol=1e-12)
    mixed = SliderCrank(q(2, "in"), q(152.4, "mm"))
    np.testing.assert_allclose(mixed.solve(t2).d, expected, rtol=1e-12)
    isc = InvertedSliderCrank(q(2, "in"), q(6, "in"))
    # b = |A − O4| with no offset
    np.testing.assert_allclose(isc.solve(t2).b, np.abs(2 * np.exp(1j * t2) - 6), rtol=1e-12)
    with pytest.raises(Exception, match="offset"):
        SliderCrank(q(2, "in"), q(6, "in"), 1.0)  # a non-zero plain offset is still refused
