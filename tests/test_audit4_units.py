"""Audit 4: units through machine files and ``machdyn run`` (docs/spec.md "Units").

One four-bar with masses, gravity and a load is written three ways — in SI
(metres, kilograms, radians, rad/s), in US units (inch, pound-mass, lbf, lbf·in,
degrees, rpm) and fully united with a different unit on almost every number (no
``[units]`` table) — and run through ``machdyn run --json``.  Every column must
agree after conversion by the exact factors written here (1 in = 0.0254 m,
1 lb = 0.45359237 kg, 1 lbf = 0.45359237 kg × 9.80665 m/s² = 4.4482216152605 N,
1 rpm = 2π/60 rad/s), each column must be labelled in the unit asked, and the
driving torque T12 is checked in SI against the power balance
``T12 ω2 + T4 ω4 = Σ (m a_G·v_G + I_G α ω + m g v_Gy)`` evaluated from positions
found here by circle intersection and differentiated numerically in θ2 (no
machdyn kinematics or forces used).  A gear pair in diametral pitch and the same
pair in module give the same tooth loads, and W_t = T/r_p, the contact ratio by
Norton eq. 9.2/9.7 written here.  Dimensionally wrong quantities are refused by
the command line in one line naming the file line, the key and the kind.
"""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest

from machdyn.cli import main

IN = 0.0254  # m, exact
LB = 0.45359237  # kg, exact
G0 = 9.80665  # m/s^2, exact
LBF = LB * G0  # N
RPM = 2 * math.pi / 60  # rad/s
assert pytest.approx(4.4482216152605, rel=1e-15) == LBF

# the machine in US units: lengths in, masses lb, inertias lb·in², torque lbf·in
R = {"r1": 8.0, "r2": 2.0, "r3": 7.0, "r4": 5.0}
P, DELTA = 4.0, 30.0  # coupler point (in, deg)
LINKS = {  # mass lb, inertia lb·in², cg [x, y] in
    2: (2.2, 7.0, (0.8, 0.2)),
    3: (4.4, 20.0, (3.5, 0.4)),
    4: (3.3, 10.0, (2.4, 0.0)),
}
OMEGA2_RPM, ALPHA2, TORQUE4 = 200.0, 50.0, -150.0  # rpm, rad/s², lbf·in


def _links(fmt_mass, fmt_inertia, fmt_len):
    out = []
    for k, (m, i, (x, y)) in LINKS.items():
        out.append(
            f"[fourbar.f.link{k}]\nmass = {fmt_mass(m)}\ninertia = {fmt_inertia(i)}\n"
            f"cg = [{fmt_len(x)}, {fmt_len(y)}]\n"
        )
    return "".join(out)


def us_file() -> str:
    lengths = "".join(f"{k} = {v!r}\n" for k, v in R.items())
    return (
        'machdyn = 1\ngravity = true\n[units]\nlength = "in"\nmass = "lb"\nforce = "lbf"\n'
        'torque = "lbf*in"\nangle = "deg"\nangular_velocity = "rpm"\n'
        f"[fourbar.f]\n{lengths}coupler = {{ p = {P!r}, delta = {DELTA!r} }}\n"
        "[fourbar.f.motion]\ntheta2 = [0, 360, 15]\n"
        f'omega2 = {OMEGA2_RPM!r}\nalpha2 = "{ALPHA2!r} rad/s^2"\n'
        + _links(repr, repr, repr)
        + f"[fourbar.f.loads]\ntorque4 = {TORQUE4!r}\n"
    )


def si_file() -> str:
    lengths = "".join(f"{k} = {v * IN!r}\n" for k, v in R.items())
    return (
        'machdyn = 1\ngravity = true\n[units]\nlength = "m"\nmass = "kg"\nangle = "rad"\n'
        f"[fourbar.f]\n{lengths}"
        f"coupler = {{ p = {P * IN!r}, delta = {math.radians(DELTA)!r} }}\n"
        f"[fourbar.f.motion]\ntheta2 = [0, {2 * math.pi!r}, {math.pi / 12!r}]\n"
        f"omega2 = {OMEGA2_RPM * RPM!r}\nalpha2 = {ALPHA2!r}\n"
        + _links(lambda m: repr(m * LB), lambda i: repr(i * LB * IN * IN), lambda x: repr(x * IN))
        + f"[fourbar.f.loads]\ntorque4 = {TORQUE4 * LBF * IN!r}\n"
    )


def mixed_file() -> str:
    """No [units] table: every number carries its own unit (mm, ft, g, oz, rev/min, ...)."""
    return (
        "machdyn = 1\ngravity = true\n"
        f'[fourbar.f]\nr1 = "{R["r1"] * 25.4!r} mm"\nr2 = "{R["r2"] / 12!r} ft"\n'
        f'r3 = "{R["r3"] * 2.54!r} cm"\nr4 = "{R["r4"]!r} in"\n'
        f'coupler = {{ p = "{P * IN!r} m", delta = "{math.radians(DELTA)!r} rad" }}\n'
        '[fourbar.f.motion]\ntheta2 = ["0 deg", "1 rev", "15 deg"]\n'
        f'omega2 = "{OMEGA2_RPM / 60!r} rev/s"\nalpha2 = "{ALPHA2!r} rad/s^2"\n'
        + _links(
            lambda m: f'"{m * 16!r} oz"',
            lambda i: f'"{i * LB * 1000 * 25.4**2!r} g*mm^2"',
            lambda x: f'"{x * 25.4!r} mm"',
        )
        + f'[fourbar.f.loads]\ntorque4 = "{TORQUE4 / 12!r} lbf*ft"\n'
    )


def run_json(tmp_path, capsys, name: str, text: str) -> dict:
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    status = main(["run", str(path), "--json"])
    out, err = capsys.readouterr()
    assert status == 0, err
    return json.loads(out)["parts"]["f"]


def column(table: dict, label: str) -> np.ndarray:
    i = table["columns"].index(label)
    return np.array([row[i] for row in table["rows"]], dtype=float)


# (table, US label, SI label, factor US → SI)
COLUMNS = [
    ("kinematics", "theta2 [deg]", "theta2 [rad]", math.pi / 180),
    ("kinematics", "theta3 [deg]", "theta3 [rad]", math.pi / 180),
    ("kinematics", "theta4 [deg]", "theta4 [rad]", math.pi / 180),
    ("kinematics", "omega3 [rpm]", "omega3 [rad/s]", RPM),
    ("kinematics", "omega4 [rpm]", "omega4 [rad/s]", RPM),
    ("kinematics", "alpha3 [rad/s^2]", "alpha3 [rad/s^2]", 1.0),  # rates never in degrees
    ("kinematics", "alpha4 [rad/s^2]", "alpha4 [rad/s^2]", 1.0),
    ("kinematics", "mu [deg]", "mu [rad]", math.pi / 180),
    ("coupler", "P_x [in]", "P_x [m]", IN),
    ("coupler", "P_y [in]", "P_y [m]", IN),
    ("coupler", "VP_x [in/s]", "VP_x [m/s]", IN),
    ("coupler", "AP_y [in/s^2]", "AP_y [m/s^2]", IN),
    ("forces", "T12 [lbf*in]", "T12 [N*m]", LBF * IN),
    ("forces", "F12_x [lbf]", "F12_x [N]", LBF),
    ("forces", "F32_y [lbf]", "F32_y [N]", LBF),
    ("forces", "F43_x [lbf]", "F43_x [N]", LBF),
    ("forces", "F14_y [lbf]", "F14_y [N]", LBF),
    ("forces", "M_shaking [lbf*in]", "M_shaking [N*m]", LBF * IN),
]


def test_us_units_file_equals_si_file_by_exact_factors(tmp_path, capsys):
    us = run_json(tmp_path, capsys, "us", us_file())
    si = run_json(tmp_path, capsys, "si", si_file())
    for table, us_label, si_label, factor in COLUMNS:
        a = column(us["tables"][table], us_label)
        b = column(si["tables"][table], si_label)
        assert a.size == b.size == 25
        np.testing.assert_allclose(a * factor, b, rtol=1e-12, atol=1e-12 * np.abs(b).max())
    # the summary's angles in the unit asked
    lo, hi = us["summary"]["mu over the sweep (min, max) [deg]"]
    lo_si, hi_si = si["summary"]["mu over the sweep (min, max) [rad]"]
    assert math.radians(lo) == pytest.approx(lo_si, rel=1e-13)
    assert math.radians(hi) == pytest.approx(hi_si, rel=1e-13)


def test_fully_united_mixed_file_computes_in_si(tmp_path, capsys):
    mixed = run_json(tmp_path, capsys, "mixed", mixed_file())
    si = run_json(tmp_path, capsys, "si", si_file())
    for table, _, si_label, _ in COLUMNS:
        t = mixed["tables"][table]
        # a fully united file computes in SI; its labels name the output unit
        label = next(c for c in t["columns"] if c.split(" [")[0] == si_label.split(" [")[0])
        unit = label[label.index("[") + 1 : -1]
        factor = {  # the file's first unit of each kind is its output unit
            "deg": math.pi / 180,
            "rev/s": 2 * math.pi,
            "rad/s^2": 1.0,
            "mm": 1e-3,
            "mm/s": 1e-3,
            "mm/s^2": 1e-3,
            "N": 1.0,
            "lbf*ft": LBF * 12 * IN,
        }[unit]
        b = column(si["tables"][table], si_label)
        np.testing.assert_allclose(
            column(t, label) * factor, b, rtol=1e-11, atol=1e-11 * np.abs(b).max()
        )
    lo, hi = mixed["summary"]["mu over the sweep (min, max) [deg]"]
    lo_si, hi_si = si["summary"]["mu over the sweep (min, max) [rad]"]
    assert math.radians(lo) == pytest.approx(lo_si, rel=1e-12)
    assert math.radians(hi) == pytest.approx(hi_si, rel=1e-12)


def _fourbar_positions(theta2, side):
    """A, B, the three centres of mass and θ2, θ3, θ4 in SI, by circle intersection."""
    r1, r2, r3, r4 = (R[k] * IN for k in ("r1", "r2", "r3", "r4"))
    A = r2 * np.exp(1j * theta2)
    f = np.abs(r1 - A)
    u = (r1 - A) / f
    x = (r3**2 - r4**2 + f**2) / (2 * f)
    B = A + u * (x + 1j * side * np.sqrt(r3**2 - x**2))
    t3, t4 = np.angle(B - A), np.angle(B - r1)
    frames = {2: (0.0, theta2), 3: (A, t3), 4: (r1 + 0j, t4)}
    G = {}
    for k, (origin, th) in frames.items():
        cx, cy = LINKS[k][2]
        G[k] = origin + (cx + 1j * cy) * IN * np.exp(1j * th)
    return B, G, {2: theta2, 3: np.unwrap(t3), 4: np.unwrap(t4)}


PLACED = {  # a placed four-bar (synthesis results): O2 (in) and the ground line's angle (deg)
    "local": None,
    "placed": ((3.0, -2.0), 30.0),
}


@pytest.mark.parametrize("placement", PLACED)
def test_driving_torque_by_power_balance_from_the_us_file(tmp_path, capsys, placement):
    """T12 by power balance with gravity along the plane's −y. Placed at θ1 = 30° the
    run applied gravity along the four-bar's own −y (normal to O2O4): T12 was that of
    the unplaced linkage (e.g. 22.4 instead of 272.7 N·mm for a 80-40-70-60 mm press),
    and its coupler point and forces were printed in the four-bar's frame."""
    text = us_file()
    turn, o2 = 1.0 + 0j, 0j
    if PLACED[placement]:
        (x, y), theta1 = PLACED[placement]
        text = text.replace(
            "[fourbar.f.motion]", f"O2 = [{x}, {y}]\ntheta1 = {theta1}\n[fourbar.f.motion]"
        )
        turn, o2 = np.exp(1j * math.radians(theta1)), complex(x, y) * IN
    us = run_json(tmp_path, capsys, "us", text)
    theta2 = np.radians(column(us["tables"]["kinematics"], "theta2 [deg]"))
    T12 = column(us["tables"]["forces"], "T12 [lbf*in]") * LBF * IN
    theta4_us = np.radians(column(us["tables"]["kinematics"], "theta4 [deg]"))
    w2, a2 = OMEGA2_RPM * RPM, ALPHA2
    # which assembly the file's form 1 is: the side whose θ4 matches at the first sample
    side = min(
        (1.0, -1.0),
        key=lambda s: abs(
            np.angle(np.exp(1j * (_fourbar_positions(theta2[:1], s)[2][4][0] - theta4_us[0])))
        ),
    )
    h = 1e-3  # rad: five-point differences, truncation ~h⁴ = 1e-12 of the scale
    k = np.arange(-2, 3)
    samples = theta2[:, None] + h * k[None, :]
    _, G, th = _fourbar_positions(samples.ravel(), side)

    def derivs(z):
        z = z.reshape(samples.shape)
        d1 = (z[:, 0] - 8 * z[:, 1] + 8 * z[:, 3] - z[:, 4]) / (12 * h)
        d2 = (-z[:, 0] + 16 * z[:, 1] - 30 * z[:, 2] + 16 * z[:, 3] - z[:, 4]) / (12 * h * h)
        return d1 * w2, d2 * w2 * w2 + d1 * a2  # velocity, acceleration in time

    power = np.zeros_like(theta2)
    for link, (m_lb, i_lb, _) in LINKS.items():
        m, inertia = m_lb * LB, i_lb * LB * IN * IN
        v, a = derivs(G[link])
        w, al = derivs(th[link])
        v_plane = turn * v  # the centre of mass's velocity in the plane: gravity along its −y
        power += m * (a * np.conj(v)).real + inertia * al * w + m * G0 * v_plane.imag
    w4, _ = derivs(th[4])
    T4 = TORQUE4 * LBF * IN
    want = (power - T4 * w4) / w2
    np.testing.assert_allclose(T12, want, rtol=1e-7, atol=1e-7 * np.abs(want).max())
    # the coupler point in the plane: O2 + e^{jθ1} (A + p e^{j(θ3 + δ)}), written here
    t3 = np.radians(column(us["tables"]["kinematics"], "theta3 [deg]"))
    local = R["r2"] * IN * np.exp(1j * theta2) + P * IN * np.exp(1j * (t3 + math.radians(DELTA)))
    P_plane = o2 + turn * local
    coupler = us["tables"]["coupler"]
    np.testing.assert_allclose(column(coupler, "P_x [in]") * IN, P_plane.real, atol=1e-12)
    np.testing.assert_allclose(column(coupler, "P_y [in]") * IN, P_plane.imag, atol=1e-12)
    # the ground's vertical reactions carry the weight and the vertical inertia forces
    forces = us["tables"]["forces"]
    lift = (column(forces, "F12_y [lbf]") + column(forces, "F14_y [lbf]")) * LBF
    inertia_y = sum(m * LB * (turn * derivs(G[k])[1]).imag for k, (m, _, _) in LINKS.items())
    weight = sum(m for m, _, _ in LINKS.values()) * LB * G0
    np.testing.assert_allclose(lift, weight + inertia_y, rtol=1e-7, atol=1e-7 * weight)


def gear_file(pitch: str, torque: str, units: str) -> str:
    return (
        f"machdyn = 1\n{units}[gear_pair.g]\npinion = {{ teeth = 18 }}\ngear = {{ teeth = 54 }}\n"
        f'{pitch}\npressure_angle = "20 deg"\ninput_speed = "1800 rpm"\ntorque = {torque}\n'
    )


def test_gear_pair_in_diametral_pitch_and_in_module(tmp_path, capsys):
    us = gear_file(
        "diametral_pitch = 8",
        "400",
        '[units]\nlength = "in"\nforce = "lbf"\ntorque = "lbf*in"\nangular_velocity = "rpm"\n',
    )
    si = gear_file('module = "3.175 mm"', f'"{400 * LBF * IN!r} N*m"', '[units]\nlength = "mm"\n')
    paths = {}
    for name, text in (("us", us), ("si", si)):
        paths[name] = tmp_path / f"{name}.toml"
        paths[name].write_text(text)
    out = {}
    for name, path in paths.items():
        assert main(["run", str(path), "--json"]) == 0
        out[name] = json.loads(capsys.readouterr().out)["parts"]["g"]["summary"]
    a, b = out["us"], out["si"]
    # Norton: r_p = N/(2 P_d), W_t = T/r_p, W_r = W_t tan φ
    rp = 18 / (2 * 8.0)
    assert a["tangential tooth load W_t [lbf]"] == pytest.approx(400 / rp, rel=1e-13)
    assert a["radial tooth load W_r [lbf]"] == pytest.approx(
        400 / rp * math.tan(math.radians(20)), rel=1e-13
    )
    assert b["tangential tooth load W_t [N]"] == pytest.approx(400 / rp * LBF, rel=1e-12)
    assert a["output speed [rpm]"] == pytest.approx(-600.0, rel=1e-14)
    assert b["output speed [rad/s]"] == pytest.approx(-600.0 * RPM, rel=1e-14)
    # contact ratio, Norton eq. 9.2 (length of action Z) and 9.7 (m_p = Z / p_b)
    phi = math.radians(20)
    r_p, r_g, add = 18 / 16, 54 / 16, 1 / 8.0
    Z = (
        math.sqrt((r_p + add) ** 2 - (r_p * math.cos(phi)) ** 2)
        + math.sqrt((r_g + add) ** 2 - (r_g * math.cos(phi)) ** 2)
        - (r_p + r_g) * math.sin(phi)
    )
    pb = math.pi / 8 * math.cos(phi)
    assert a["length of action [in]"] == pytest.approx(Z, rel=1e-13)
    assert b["length of action [mm]"] == pytest.approx(Z * 25.4, rel=1e-12)
    assert a["base pitch [in]"] == pytest.approx(pb, rel=1e-13)
    assert float(a["contact ratio"].split()[0]) == pytest.approx(Z / pb, abs=5e-5)


WRONG = [  # (replace, with, key in the message, kind expected, kind given)
    ("r3 = 7.0", 'r3 = "7 N"', "[fourbar.f] r3", "a length", "a force"),
    ("mass = 4.4", 'mass = "4.4 in"', "[fourbar.f.link3] mass", "a mass", "a length"),
    ("torque4 = -150.0", 'torque4 = "-150 lbf"', "torque4", "a torque", "a force"),
    ("omega2 = 200.0", 'omega2 = "200 in/s"', "omega2", "an angular velocity", "a velocity"),
    ('alpha2 = "50.0 rad/s^2"', 'alpha2 = "50 rad/s"', "alpha2", "an angular acceleration", ""),
    ("inertia = 20.0", 'inertia = "20 lb*in"', "inertia", "an inertia", ""),
    ("p = 4.0", 'p = "4 rad"', "p", "a length", "an angle"),
    ('length = "in"', 'length = "lbf"', "[units] length", "a length", "a force"),
]


@pytest.mark.parametrize(("old", "new", "key", "want", "got"), WRONG)
def test_a_quantity_of_the_wrong_kind_is_one_line_naming_the_key(
    tmp_path, capsys, old, new, key, want, got
):
    text = us_file()
    assert old in text
    path = tmp_path / "bad.toml"
    path.write_text(text.replace(old, new, 1))
    status = main(["run", str(path)])
    out, err = capsys.readouterr()
    assert status == 1 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err
    line = lines[0]
    assert re.match(r"machdyn: error: .*bad\.toml:\d+: ", line), line
    assert key in line and f"expected {want}" in line and got in line, line
    # the line number is the key's line in the file
    lineno = int(line.split("bad.toml:")[1].split(":")[0])
    assert new.split(" =")[0].strip() in path.read_text().splitlines()[lineno - 1]


def test_rev_is_a_unit_as_the_docs_and_the_frequency_hint_say(tmp_path, capsys):
    """docs/spec.md lists `rev` among the units, and a turning speed given in Hz is
    refused with "write a turning speed in rev/s, rad/s or rpm" — but pint has no
    `rev` (only `revolution`), so '1 rev' and '3.3 rev/s' were 'unknown unit'.
    (machdyn remembers pint's answers on disk: the registry itself is asked first.)"""
    from machdyn.units import registry

    assert registry().Quantity("1 rev/s").to("rpm").magnitude == pytest.approx(60.0, rel=1e-15)
    text = us_file().replace("omega2 = 200.0", 'omega2 = "3.3 rev/s"')
    text = text.replace("theta2 = [0, 360, 15]", 'theta2 = [0, "1 rev", 15]')
    us = run_json(tmp_path, capsys, "rev", text)
    theta2 = column(us["tables"]["kinematics"], "theta2 [deg]")
    assert theta2[-1] == pytest.approx(360.0, rel=1e-15) and theta2.size == 25
    ref = run_json(tmp_path, capsys, "rpm", us_file().replace("omega2 = 200.0", "omega2 = 198.0"))
    for label in ("omega3 [rpm]", "omega4 [rpm]"):
        a, b = column(us["tables"]["kinematics"], label), column(ref["tables"]["kinematics"], label)
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12 * np.abs(b).max())
    bad = tmp_path / "hz.toml"
    bad.write_text(us_file().replace("omega2 = 200.0", 'omega2 = "3.3 Hz"'))
    assert main(["run", str(bad)]) == 1
    assert "rev/s" in capsys.readouterr().err


# ---------------------------------------------------------------------------
# Every kind of quantity with bare numbers: the same parts in US units and in SI
# ---------------------------------------------------------------------------

KIND_SI = {  # one US unit of each kind in SI, written here (bare numbers of the US file)
    "length": IN,
    "mass": LB,
    "force": LBF,
    "torque": LBF * IN,
    "angle": math.pi / 180,
    "angular_velocity": RPM,
    "inertia": LB * IN * IN,
    "stiffness": LBF / IN,  # force/length
    "damping": LBF / IN,  # force·time/length
    "torsional": LBF * IN,  # torque/rad: rates never in degrees
    "torsional_damping": LBF * IN,  # torque·time/rad
    "angular_acceleration": 1.0,  # rad/s²: never degrees
}
# an odd coherent system: mm, g, ms (its force unit g·mm/ms² is 1 N), outputs in kN, N·m
ODD_SI = {
    "length": 1e-3,
    "mass": 1e-3,
    "force": 1e3,
    "torque": 1.0,
    "angle": math.pi / 180,
    "angular_velocity": RPM,
    "inertia": 1e-3 * 1e-6,
    "stiffness": 1e3 / 1e-3,
    "damping": 1e3 * 1e-3 / 1e-3,
    "torsional": 1.0,
    "torsional_damping": 1e-3,
    "angular_acceleration": 1e6,  # rad/ms²
}
ONE_SI = dict.fromkeys(KIND_SI, 1.0)
UNIT_SI = {"in": IN, "lbf": LBF, "lb": LB, "s": 1.0, "deg": math.pi / 180, "rad": 1.0}
UNIT_SI |= {"rpm": RPM, "N": 1.0, "m": 1.0, "kg": 1.0, "mm": 1e-3, "g": 1e-3, "ms": 1e-3, "kN": 1e3}
US_TABLE = (
    '[units]\nlength = "in"\nmass = "lb"\nforce = "lbf"\ntorque = "lbf*in"\nangle = "deg"\n'
    'angular_velocity = "rpm"\n'
)
SI_TABLE = '[units]\nlength = "m"\nmass = "kg"\nforce = "N"\nangle = "rad"\n'
ODD_TABLE = (
    '[units]\nlength = "mm"\nmass = "g"\ntime = "ms"\nforce = "kN"\ntorque = "N*m"\n'
    'angle = "deg"\nangular_velocity = "rpm"\n'
)


def unit_factor(unit: str) -> float:
    """SI value of one ``unit`` (``lbf*in``, ``in/s^2``, ``lb*in``) from UNIT_SI."""
    num, *den = unit.split("/")
    f = 1.0
    for part, sign in [(num, 1)] + [(d, -1) for d in den]:
        for tok in part.split("*"):
            name, _, p = tok.partition("^")
            f *= UNIT_SI[name] ** (sign * (int(p) if p else 1))
    return f


def quantity(system: dict):
    """Writes a value given in US units as a bare number of ``system`` (SI per unit)."""

    def q(value, kind):
        if isinstance(value, list):
            return "[" + ", ".join(q(v, kind) for v in value) + "]"
        return repr(float(value) * KIND_SI[kind] / system[kind])

    return q


def slider_cranks(q) -> str:
    return f"""
[slider_crank.e]
crank = {q(2, "length")}
coupler = {q(8, "length")}
offset = {q(0.4, "length")}
[slider_crank.e.motion]
theta2 = [0, {q(360, "angle")}, {q(30, "angle")}]
omega2 = {q(3000, "angular_velocity")}
alpha2 = {q(40, "angular_acceleration")}
[slider_crank.e.link2]
mass = {q(2.2, "mass")}
inertia = {q(4, "inertia")}
cg = {q(0.8, "length")}
[slider_crank.e.link3]
mass = {q(4.4, "mass")}
inertia = {q(18, "inertia")}
cg = {q([4, 0.2], "length")}
[slider_crank.e.link4]
mass = {q(3.3, "mass")}
[slider_crank.e.loads]
force4 = {q(-450, "force")}
friction = "viscous"
beta = {q(0.3, "damping")}
torques = {{ link3 = {q(12, "torque")} }}
[inverted_slider_crank.i]
crank = {q(4, "length")}
ground = {q(12, "length")}
offset = {q(1, "length")}
[inverted_slider_crank.i.motion]
theta2 = [0, {q(360, "angle")}, {q(45, "angle")}]
omega2 = {q(60, "angular_velocity")}
[inverted_slider_crank.i.link2]
mass = {q(2.0, "mass")}
inertia = {q(5, "inertia")}
cg = {q(2, "length")}
[inverted_slider_crank.i.link3]
mass = {q(1.0, "mass")}
inertia = {q(1, "inertia")}
[inverted_slider_crank.i.link4]
mass = {q(6.0, "mass")}
inertia = {q(80, "inertia")}
cg = {q([6, 0.5], "length")}
[inverted_slider_crank.i.loads]
torque4 = {q(-100, "torque")}
friction = "viscous"
beta = {q(0.5, "damping")}
"""


def drawn_linkage(q) -> str:
    pts = {"A": [1, 1.5], "B": [6, 4], "O4": [7, 0], "P": [3, 4], "E": [11, 1], "S": [2, -3]}
    points = "".join(f"{k} = {q(v, 'length')}\n" for k, v in pts.items())
    return f"""
[linkage.m]
ground = ["O2", "O4", "S"]
drive = ["crank"]
report = ["P", "E"]
[linkage.m.points]
O2 = [0, 0]
{points}[linkage.m.links.crank]
points = ["O2", "A"]
mass = {q(2, "mass")}
inertia = {q(3, "inertia")}
cg = {q(0.9, "length")}
[linkage.m.links.coupler]
points = ["A", "B", "P"]
mass = {q(4, "mass")}
inertia = {q(20, "inertia")}
cg = "P"
[linkage.m.links.rocker]
points = ["O4", "B"]
mass = {q(3, "mass")}
inertia = {q(15, "inertia")}
cg = {q([2, 0.3], "length")}
[linkage.m.links.rod]
points = ["B", "E"]
mass = {q(1, "mass")}
inertia = {q(5, "inertia")}
cg = {q(2.5, "length")}
[linkage.m.links.block]
points = ["E"]
mass = {q(1.5, "mass")}
inertia = {q(0.5, "inertia")}
[linkage.m.sliders.guide]
block = "block"
on = "ground"
at = "E"
direction = {q(10, "angle")}
[linkage.m.springs.gas]
start = "S"
end = "P"
stiffness = {q(30, "stiffness")}
free_length = {q(5, "length")}
damping = {q(0.8, "damping")}
preload = {q(-20, "force")}
[linkage.m.torsion_springs.hinge]
at = "O4"
stiffness = {q(40, "torsional")}
free_angle = {q(15, "angle")}
damping = {q(2, "torsional_damping")}
[[linkage.m.forces]]
link = "coupler"
at = "P"
force = [{q(10, "force")}, {q(-25, "force")}]
[linkage.m.torques]
rocker = {q(-60, "torque")}
[linkage.m.friction.guide]
viscous = {q(0.4, "damping")}
[linkage.m.motion.crank]
sweep = [{q(56.31, "angle")}, {q(100, "angle")}, {q(5, "angle")}]
velocity = {q(120, "angular_velocity")}
acceleration = {q(3, "angular_acceleration")}
"""


def cam_and_rotor(q) -> str:
    segments = [("rise", "cycloidal", 0.5, 90), ("dwell", None, 0, 90)]
    segments += [("fall", "modified_sine", 0.5, 120), ("dwell", None, 0, 60)]
    seg = ""
    for motion, law, lift, beta in segments:
        seg += f'[[cam.c.segment]]\nmotion = "{motion}"\nbeta = {q(beta, "angle")}\n'
        if law:
            seg += f'law = "{law}"\nlift = {q(lift, "length")}\n'
    return f"""
[cam.c]
speed = {q(300, "angular_velocity")}
points = 720
step = {q(30, "angle")}
max_pressure_angle = {q(30, "angle")}
[cam.c.follower]
type = "roller"
prime_radius = {q(1.5, "length")}
roller_radius = {q(0.25, "length")}
eccentricity = {q(0.1, "length")}
{seg}[rotor.r]
planes = {q([0, 16], "length")}
radii = {q([2, 2], "length")}
speed = {q(1500, "angular_velocity")}
bearings = {q([-2, 18], "length")}
[[rotor.r.mass]]
mass = {q(0.5, "mass")}
radius = {q(2.5, "length")}
angle = {q(30, "angle")}
z = {q(4, "length")}
[[rotor.r.mass]]
mass = {q(0.7, "mass")}
radius = {q(2, "length")}
angle = {q(150, "angle")}
z = {q(9, "length")}
"""


def _in_si(label: str, values) -> np.ndarray:
    unit = label[label.rindex("[") + 1 : -1]
    return np.asarray(values, dtype=float) * unit_factor(unit)


@pytest.mark.parametrize("parts", [slider_cranks, drawn_linkage, cam_and_rotor])
@pytest.mark.parametrize(("table", "system"), [(US_TABLE, KIND_SI), (ODD_TABLE, ODD_SI)])
def test_every_kind_of_bare_number_in_us_units_equals_si(tmp_path, capsys, parts, table, system):
    """Stiffness (force/length), damping (force·time/length), torsional stiffness and
    damping (per radian even in a degree file), inertia, preload, friction, loads, cam
    lift and speed, rotor masses: every labelled output of the US file (and of a file in
    mm, g, ms with outputs in kN), converted by the factors written here, equals the SI
    file's."""
    out = {}
    for name, units, factors in (("us", table, system), ("si", SI_TABLE, ONE_SI)):
        path = tmp_path / f"{name}.toml"
        path.write_text("machdyn = 1\ngravity = true\n" + units + parts(quantity(factors)))
        assert main(["run", str(path), "--json"]) == 0
        out[name] = json.loads(capsys.readouterr().out)["parts"]
    compared = 0
    for part, us in out["us"].items():
        si = out["si"][part]
        for tname, ta in us["tables"].items():
            tb = si["tables"][tname]
            for ca, cb in zip(ta["columns"], tb["columns"], strict=True):
                assert ca.split(" [")[0] == cb.split(" [")[0]
                if "[" not in ca:
                    continue
                a = _in_si(ca, [r[ta["columns"].index(ca)] for r in ta["rows"]])
                b = _in_si(cb, [r[tb["columns"].index(cb)] for r in tb["rows"]])
                np.testing.assert_allclose(
                    a, b, rtol=1e-10, atol=1e-12 * np.abs(b).max(), err_msg=ca
                )
                compared += 1
        for (ka, va), (kb, vb) in zip(us["summary"].items(), si["summary"].items(), strict=True):
            if "[" in ka and not isinstance(va, str):
                # round-off (bearing loads after a perfect balance) compared absolutely
                np.testing.assert_allclose(_in_si(ka, va), _in_si(kb, vb), rtol=1e-10, atol=1e-12)
                compared += 1
    assert compared >= 20


def test_slider_crank_point_on_the_rod_is_tabulated(tmp_path, capsys):
    """docs/spec.md: slider_crank `point = { p, delta }` "a point on the rod" — the
    model computed it but `machdyn run` printed no table of it (the four-bar prints
    its coupler point). P = A + p e^{j(arg(B − A) + δ)}, written here."""
    a, b, c, p, delta = 2.0, 8.0, 0.4, 3.0, 20.0
    text = (
        "machdyn = 1\n" + US_TABLE + f"[slider_crank.e]\ncrank = {a}\ncoupler = {b}\n"
        f"offset = {c}\npoint = {{ p = {p}, delta = {delta} }}\n"
        '[slider_crank.e.motion]\ntheta2 = [0, 360, 30]\nomega2 = "10 rad/s"\n'
    )
    path = tmp_path / "sc.toml"
    path.write_text(text)
    assert main(["run", str(path), "--json"]) == 0
    table = json.loads(capsys.readouterr().out)["parts"]["e"]["tables"]["point"]
    theta2 = np.radians(column(table, "theta2 [deg]"))
    A = a * np.exp(1j * theta2)
    B = A.real + np.sqrt(b * b - (c - A.imag) ** 2) + 1j * c
    P = A + p * np.exp(1j * (np.angle(B - A) + math.radians(delta)))
    np.testing.assert_allclose(column(table, "P_x [in]"), P.real, atol=1e-12)
    np.testing.assert_allclose(column(table, "P_y [in]"), P.imag, atol=1e-12)
    # its velocity: dP/dθ2 · ω2 by central differences of the closed form (h = 1e-6)
    h = 1e-6

    def point(t):
        A = a * np.exp(1j * t)
        B = A.real + np.sqrt(b * b - (c - A.imag) ** 2) + 1j * c
        return A + p * np.exp(1j * (np.angle(B - A) + math.radians(delta)))

    V = (point(theta2 + h) - point(theta2 - h)) / (2 * h) * 10.0
    np.testing.assert_allclose(column(table, "VP_x [in/s]"), V.real, atol=1e-6)
    np.testing.assert_allclose(column(table, "VP_y [in/s]"), V.imag, atol=1e-6)
