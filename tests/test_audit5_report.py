"""Audit 5: the report and ``run`` of a general linkage with masses and loads, in mm and g.

A Watt six-bar (crank O2-A, coupler A-B-P, ternary rocker O4-B-C, second
coupler C-D, output O6-D) with a mass, an inertia and an offset centre of mass
on every link, gravity, a point load at the coupler point P and a torque on
the output, written in mm, g, N and N·mm. Every number is derived here
independently of the library:

* positions by circle intersections (each dyad on its drawn side), velocities
  and accelerations by five-point differences in θ;
* the driver torque by the power balance
  ``T ω2 = Σ(m v_G·a_G + I_G ω α) + Σ m g v_Gy − F·v_P − T_out ω_out`` (SI);
* every pin force by a Newton–Euler solve of the five links written here
  (15 equations: ΣF = m a_G and ΣM_G = I_G α per link);
* the shaking force and moment (about the origin) by the momentum balance
  ``F_s = ΣF_ext − Σ m a_G``, ``M_s = ΣM_ext − Σ(m G × a_G + I_G α)``.

Found by this file: the report of a machine file's linkage left out the file's
``[[forces]]``, ``torques`` and ``friction`` (``machdyn run`` had them): the
driver torque's extremes printed 94.35 / −89.5 N·mm where the loads give
350.5 / −252.1 N·mm.
"""

from __future__ import annotations

import html
import json
import math
import re

import numpy as np
import pytest

from machdyn.cli import main

G0 = 9.80665
W2 = 30.0  # rad/s
PTS = {
    "O2": 0j,
    "O4": 60 + 0j,
    "O6": 100 + 30j,
    "A": 15 + 0j,
    "B": 47.5 + 37.997j,
    "C": 93.316 + 13.641j,
    "D": 75.444 + 54.94j,
    "P": 31.25 + 28.998j,
}
# link: (points, mass g, inertia g·mm², cg as written in the file, cg in the link frame)
LINKS = {
    "crank": (("O2", "A"), 50.0, 2000.0, "[5.0, 1.0]", 5 + 1j),
    "coupler": (("A", "B", "P"), 120.0, 30000.0, "[20.0, 8.0]", 20 + 8j),
    "rocker": (("O4", "B", "C"), 90.0, 25000.0, '"C"', None),
    "coupler2": (("C", "D"), 60.0, 12000.0, "20.0", 20 + 0j),
    "output": (("O6", "D"), 70.0, 15000.0, None, 0j),
}
F_P = 3.0 - 5.0j  # N, at P on the coupler
T_OUT = -200.0  # N·mm on the output


def machine_file(loads: bool = True) -> str:
    lines = [
        "machdyn = 1",
        'title = "Watt with masses"',
        "gravity = true",
        "[units]",
        'length = "mm"',
        'mass = "g"',
        'force = "N"',
        'torque = "N*mm"',
        "[linkage.watt]",
        'ground = ["O2", "O4", "O6"]',
        'drive = ["crank"]',
        'report = ["P", "D"]',
        "[linkage.watt.points]",
        *(f"{k} = [{z.real!r}, {z.imag!r}]" for k, z in PTS.items()),
    ]
    for name, (points, m, inertia, cg, _) in LINKS.items():
        lines += [
            f"[linkage.watt.links.{name}]",
            f"points = {json.dumps(list(points))}",
            f"mass = {m}",
            f"inertia = {inertia}",
        ]
        if cg is not None:
            lines.append(f"cg = {cg}")
    if loads:
        lines += [
            "[[linkage.watt.forces]]",
            'link = "coupler"',
            'at = "P"',
            f"force = [{F_P.real}, {F_P.imag}]",
            "[linkage.watt.torques]",
            f'output = "{T_OUT} N*mm"',
        ]
    lines += [
        "[linkage.watt.motion.crank]",
        "sweep = [0, 350, 10]",
        f'velocity = "{W2} rad/s"',
    ]
    return "\n".join(lines) + "\n"


# --- the Watt six-bar written here -------------------------------------------------------


def _meet(c1, r1, c2, r2, side):
    """The intersection of two circles on ``side`` (+1: left of c1 → c2)."""
    d = c2 - c1
    L = np.abs(d)
    a = (r1**2 - r2**2 + L**2) / (2 * L)
    return c1 + (a + side * 1j * np.sqrt(r1**2 - a**2)) * d / L


def _side(c1, c2, p):
    return float(np.sign(((p - c1) * np.conj(c2 - c1)).imag))


def _in_frame(p, q, z):
    return (z - p) * abs(q - p) / (q - p)


R_AB, R_O4B = abs(PTS["B"] - PTS["A"]), abs(PTS["B"] - PTS["O4"])
R_CD, R_O6D = abs(PTS["D"] - PTS["C"]), abs(PTS["D"] - PTS["O6"])
S1, S2 = _side(PTS["A"], PTS["O4"], PTS["B"]), _side(PTS["C"], PTS["O6"], PTS["D"])
P_LOCAL = _in_frame(PTS["A"], PTS["B"], PTS["P"])
C_LOCAL = _in_frame(PTS["O4"], PTS["B"], PTS["C"])


def pose(t):
    """Joint positions, centres of mass (mm) and link angles at crank angle t."""
    O2, O4, O6 = (np.full(np.shape(t), PTS[k]) for k in ("O2", "O4", "O6"))
    A = abs(PTS["A"]) * np.exp(1j * t)
    B = _meet(A, R_AB, O4, R_O4B, S1)
    P = A + P_LOCAL * (B - A) / R_AB
    C = O4 + C_LOCAL * (B - O4) / R_O4B
    D = _meet(C, R_CD, O6, R_O6D, S2)
    frame = {"crank": (O2, A), "coupler": (A, B), "rocker": (O4, B), "coupler2": (C, D)}
    frame["output"] = (O6, D)
    pts = {"O2": O2, "O4": O4, "O6": O6, "A": A, "B": B, "C": C, "D": D, "P": P}
    for name, (_, _, _, _, local) in LINKS.items():
        p, q = frame[name]
        pts["G_" + name] = C if local is None else p + local * (q - p) / np.abs(q - p)
    angles = {name: np.angle(q - p) for name, (p, q) in frame.items()}
    return pts, angles


def rates(t, h=1e-3):
    """Position, velocity and acceleration (per second, mm) of every point and link angle."""
    poses = [pose(t + k * h) for k in (-2, -1, 0, 1, 2)]
    out = {}
    for i in (0, 1):
        for key in poses[2][i]:
            z = [p[i][key] for p in poses]
            if i:
                z = list(np.unwrap(np.array(z), axis=0))
            v = (z[0] - 8 * z[1] + 8 * z[3] - z[4]) / (12 * h) * W2
            a = (-z[0] + 16 * z[1] - 30 * z[2] + 16 * z[3] - z[4]) / (12 * h * h) * W2**2
            out[key] = (z[2], v, a)
    return out


def newton_euler(t):
    """T12 (N·mm), the pin forces (N) and the shaking force (N) and moment (N·mm).

    SI inside. Unknowns: the force on each link's side of every pin (the second
    link named from the first), and the driver torque; per link ΣF = m a_G and
    ΣM about G = I α.
    """
    r = rates(t)
    mm = 1e-3
    pins = [  # (on, by, point): the unknown is the force on `on` from `by`
        ("crank", "ground", "O2"),
        ("coupler", "crank", "A"),
        ("rocker", "coupler", "B"),
        ("rocker", "ground", "O4"),
        ("coupler2", "rocker", "C"),
        ("output", "coupler2", "D"),
        ("output", "ground", "O6"),
    ]
    names = list(LINKS)
    n = np.size(t)
    M = np.zeros((n, 15, 15))
    rhs = np.zeros((n, 15))
    for k, name in enumerate(names):
        _, m, inertia, _, _ = LINKS[name]
        m, inertia = m * 1e-3, inertia * 1e-9
        G, _, aG = (x * mm for x in r["G_" + name])
        rhs[:, 3 * k] = m * aG.real
        rhs[:, 3 * k + 1] = m * aG.imag + m * G0
        rhs[:, 3 * k + 2] = inertia * r[name][2]
        loads = []
        if name == "coupler":
            loads.append((F_P, r["P"][0] * mm))
        for F, X in loads:
            rhs[:, 3 * k] -= F.real
            rhs[:, 3 * k + 1] -= F.imag
            rhs[:, 3 * k + 2] -= ((X - G) * np.conj(F)).imag * -1
        if name == "output":
            rhs[:, 3 * k + 2] -= T_OUT * 1e-3
        for j, (on, by, point) in enumerate(pins):
            X = r[point][0] * mm
            for link, sign in ((on, 1.0), (by, -1.0)):
                if link != name:
                    continue
                arm = X - G
                M[:, 3 * k, 2 * j] += sign
                M[:, 3 * k + 1, 2 * j + 1] += sign
                M[:, 3 * k + 2, 2 * j] += sign * -arm.imag  # r × F = rx Fy − ry Fx
                M[:, 3 * k + 2, 2 * j + 1] += sign * arm.real
        if name == "crank":
            M[:, 3 * k + 2, 14] = 1.0
    x = np.linalg.solve(M, rhs[..., None])[..., 0]
    forces = {(by, on): x[:, 2 * j] + 1j * x[:, 2 * j + 1] for j, (on, by, _) in enumerate(pins)}
    # momentum balance of the machine: shaking force/moment on the frame, about the origin
    Fs = np.zeros(n, complex) + F_P
    Ms = ((r["P"][0] * mm) * np.conj(F_P)).imag * -1 + T_OUT * 1e-3
    for name, (_, m, inertia, _, _) in LINKS.items():
        m, inertia = m * 1e-3, inertia * 1e-9
        G, _, aG = (z * mm for z in r["G_" + name])
        Fs = Fs - m * aG - 1j * m * G0
        Ms = Ms - m * G0 * G.real - m * (np.conj(G) * aG).imag - inertia * r[name][2]
    return x[:, 14] * 1e3, forces, Fs, Ms * 1e3


def power_balance_torque(t):
    """T12 (N·mm) by T ω2 = dKE/dt + dV/dt − P_loads, independent of any joint force."""
    r = rates(t)
    mm = 1e-3
    power = 0.0
    for name, (_, m, inertia, _, _) in LINKS.items():
        _, v, a = (z * mm for z in r["G_" + name])
        power = power + m * 1e-3 * ((np.conj(v) * a).real + G0 * v.imag)
        power = power + inertia * 1e-9 * r[name][1] * r[name][2]
    power = power - (np.conj(F_P) * r["P"][1] * mm).real - T_OUT * 1e-3 * r["output"][1]
    return power / W2 * 1e3


# --- reading the outputs -----------------------------------------------------------------


def page_text(path) -> str:
    s = path.read_text(encoding="utf-8")
    for tag in ("script", "style", "svg"):
        s = re.sub(rf"<{tag}\b.*?</{tag}>", " ", s, flags=re.S)
    s = re.sub(r"<[^>]+>", " ", s)
    return re.sub(r"\s+", " ", html.unescape(s))


NUM = r"(-?\d+(?:\.\d+)?(?:e[+-]?\d+)?)"


def grab(text: str, pattern: str) -> tuple[float, ...]:
    m = re.search(pattern.replace("NUM", NUM), text)
    assert m, f"not in the report: {pattern}"
    return tuple(float(g) for g in m.groups())


def shown(printed: float, exact: float, digits: int = 4) -> bool:
    """``printed`` is ``exact`` to the ``digits`` significant digits the report shows."""
    return abs(printed - exact) <= 0.6 * 10 ** (math.floor(math.log10(abs(exact))) - digits + 1)


@pytest.fixture(scope="module")
def watt(tmp_path_factory):
    folder = tmp_path_factory.mktemp("watt")
    path = folder / "watt.toml"
    path.write_text(machine_file(), encoding="utf-8")
    return folder, path


def test_independent_references_agree(watt):
    """The two derivations written here agree (power balance vs Newton–Euler)."""
    t = np.radians(np.arange(0.0, 360.0, 7.0))
    T, _, _, _ = newton_euler(t)
    np.testing.assert_allclose(T, power_balance_torque(t), rtol=0, atol=1e-6 * np.abs(T).max())


def test_run_prints_the_newton_euler_torque_and_pin_forces(watt, capsys):
    _, path = watt
    assert main(["run", str(path), "--json"]) == 0
    table = json.loads(capsys.readouterr().out)["parts"]["watt"]["tables"]["forces"]
    cols = table["columns"]
    rows = [dict(zip(cols, row, strict=True)) for row in table["rows"]]
    t = np.radians([row["theta_crank [deg]"] for row in rows])
    T, pins, _, _ = newton_euler(t)
    col = np.array([row["T_crank [N*mm]"] for row in rows])
    np.testing.assert_allclose(col, T, rtol=0, atol=1e-6 * np.abs(T).max())
    for (by, on), F in pins.items():
        fx = np.array([row[f"F_{by}_{on}_x [N]"] for row in rows])
        fy = np.array([row[f"F_{by}_{on}_y [N]"] for row in rows])
        np.testing.assert_allclose(fx + 1j * fy, F, rtol=0, atol=1e-6 * np.abs(F).max())


def test_report_prints_the_loaded_driver_torque_pin_forces_and_shaking(watt):
    folder, path = watt
    out = folder / "watt.html"
    assert main(["report", str(path), "-o", str(out)]) == 0
    text = page_text(out)
    x = np.linspace(0.0, np.radians(350.0), 360)  # the report's 360 poses over the sweep
    T, pins, Fs, Ms = newton_euler(x)
    for label, j in (("largest", int(np.argmax(T))), ("smallest", int(np.argmin(T)))):
        value, where = grab(text, rf"driver crank torque, {label} NUM N·mm at θ crank = NUM°")
        assert shown(value, T[j]), (label, value, T[j])
        assert abs(where - np.degrees(x[j])) < 0.06
    for (by, on), F in pins.items():
        (value, _) = grab(text, rf"peak \|F {by}→{on}\| NUM N at θ crank = NUM°")
        assert shown(value, np.abs(F).max()), (by, on, value, np.abs(F).max())
    (value, _) = grab(text, r"peak \|shaking force\| NUM N at θ crank = NUM°")
    assert shown(value, np.abs(Fs).max())
    (value, _) = grab(text, r"peak \|shaking moment\| NUM N·mm at θ crank = NUM°")
    assert shown(value, np.abs(Ms).max())
    # and its self-checks still pass with the loads in them
    for key in ("power balance", "equilibrium of each link", "momentum: shaking force and moment"):
        (value,) = grab(text, rf"{key} NUM ")
        assert value < 1e-8, key


SLIDER = """
machdyn = 1
title = "slider with friction"
gravity = true
[units]
length = "mm"
mass = "g"
force = "N"
torque = "N*mm"
[linkage.sc]
ground = ["O2"]
drive = ["crank"]
[linkage.sc.points]
O2 = [0.0, 0.0]
A = [0.0, 20.0]
B = [60.0, 5.0]
[linkage.sc.links.crank]
points = ["O2", "A"]
mass = 30
inertia = 1000
[linkage.sc.links.rod]
points = ["A", "B"]
mass = 50
inertia = 8000
cg = 25
[linkage.sc.links.block]
points = ["B"]
mass = 80
[linkage.sc.sliders.guide]
block = "block"
on = "ground"
at = "B"
direction = [1, 0]
[linkage.sc.friction.guide]
coulomb = 0.2
viscous = "0.5 N*s/m"
[[linkage.sc.forces]]
link = "block"
at = [3.0, 2.0]
force = [-4.0, 1.0]
[[linkage.sc.forces]]
link = "rod"
at = [10.0, 5.0]
force = [1.0, 2.0]
[linkage.sc.torques]
rod = "15 N*mm"
[linkage.sc.motion.crank]
sweep = [0, 350, 10]
velocity = "20 rad/s"
"""


def test_report_self_checks_hold_with_friction_and_loads_in_link_frames(tmp_path):
    """The report's power balance counts the loads' power and the friction's slip power
    (points given in a link's frame, on a two-point rod and a one-point block)."""
    path = tmp_path / "slider.toml"
    path.write_text(SLIDER, encoding="utf-8")
    assert main(["report", str(path), "-o", str(tmp_path / "s.html")]) == 0
    text = page_text(tmp_path / "s.html")
    for key in ("power balance", "equilibrium of each link", "momentum: shaking force and moment"):
        (value,) = grab(text, rf"{key} NUM ")
        assert value < 1e-8, key
    assert "driver crank torque, largest" in text


def test_studio_report_export_has_the_file_loads(watt):
    """The studio's Export → report prints the loaded driver torque too (its own sweep)."""
    import tomllib

    from machdyn.studio.document import normalise
    from machdyn.studio.exports import export

    _, path = watt
    doc = normalise(tomllib.loads(path.read_text(encoding="utf-8")))
    page = export(doc, "report").data.decode("utf-8")
    out = path.with_suffix(".studio.html")
    out.write_text(page, encoding="utf-8")
    text = page_text(out)
    value, where = grab(text, r"driver crank torque, largest NUM N·mm at θ crank = NUM°")
    T = newton_euler(np.radians([where]))[0][0]
    assert shown(value, T), (value, T)  # printed at the pose it names
    assert value > 300.0  # the loaded peak (350.6 N·mm near 323°); without the loads 94.35


# --- slider-crank and inverted slider-crank parts with point loads and torques -------------

SLIDER_PART = """
machdyn = 1
gravity = true
[units]
length = "mm"
[slider_crank.s]
crank = 30.0
coupler = 100.0
offset = 10.0
[slider_crank.s.motion]
theta2 = [0, 359, 1]
omega2 = "20 rad/s"
[slider_crank.s.link2]
mass = "0.2 kg"
inertia = "300 kg*mm^2"
cg = 10.0
[slider_crank.s.link3]
mass = "0.4 kg"
inertia = "2000 kg*mm^2"
cg = [40.0, 3.0]
[slider_crank.s.link4]
mass = "0.5 kg"
[slider_crank.s.loads]
force4 = "-20 N"
torques = { link3 = "300 N*mm" }
[[slider_crank.s.loads.force]]
link = 3
at = [60.0, 5.0]
force = [5.0, -30.0]
"""

INVERTED_PART = """
machdyn = 1
gravity = true
[units]
length = "mm"
[inverted_slider_crank.i]
crank = 30.0
ground = 80.0
offset = 5.0
[inverted_slider_crank.i.motion]
theta2 = [0, 359, 1]
omega2 = "15 rad/s"
[inverted_slider_crank.i.link2]
mass = "0.2 kg"
inertia = "300 kg*mm^2"
cg = 10.0
[inverted_slider_crank.i.link3]
mass = "0.1 kg"
inertia = "50 kg*mm^2"
[inverted_slider_crank.i.link4]
mass = "0.6 kg"
inertia = "5000 kg*mm^2"
cg = [50.0, 0.0]
[inverted_slider_crank.i.loads]
torque4 = "-400 N*mm"
torques = { link2 = "100 N*mm" }
[[inverted_slider_crank.i.loads.force]]
link = 4
at = [90.0, 4.0]
force = [0.0, -12.0]
"""


def _d5(z, h, w):
    v = (z[0] - 8 * z[1] + 8 * z[3] - z[4]) / (12 * h) * w
    a = (-z[0] + 16 * z[1] - 30 * z[2] + 16 * z[3] - z[4]) / (12 * h * h) * w * w
    return v, a


def _power_torque(pose, bodies, loads, w, th):
    """T12 by the power balance (SI in, N·mm out): ``pose(t)`` gives the points (mm) and
    angles each body and load needs; velocities by five-point differences in θ2."""
    h = 1e-3
    poses = [pose(th + k * h) for k in (-2, -1, 0, 1, 2)]
    power = 0.0
    for G, angle, m, inertia in bodies:
        v, a = _d5([p[G] * 1e-3 for p in poses], h, w)
        power = power + m * ((np.conj(v) * a).real + G0 * v.imag)
        if inertia:
            om, al = _d5(np.unwrap(np.array([p[angle] for p in poses]), axis=0), h, w)
            power = power + inertia * om * al
    for X, F in loads:  # a force F (N) at point X, or a torque F (N·m) on angle X
        if isinstance(F, complex):
            v, _ = _d5([p[X] * 1e-3 for p in poses], h, w)
            power = power - (np.conj(F) * v).real
        else:
            om, _ = _d5(np.unwrap(np.array([p[X] for p in poses]), axis=0), h, w)
            power = power - F * om
    return power / w * 1e3


def _slider_pose(t):
    a, b, c = 30.0, 100.0, 10.0
    A = a * np.exp(1j * t)
    B = a * np.cos(t) + np.sqrt(b**2 - (c - a * np.sin(t)) ** 2) + 1j * c
    e3 = (B - A) / b
    return {"G2": 10 * np.exp(1j * t), "G3": A + (40 + 3j) * e3, "B": B,
            "X": A + (60 + 5j) * e3, "t2": t, "t3": np.angle(e3)}  # fmt: skip


def _inverted_pose(t):
    a, d, c = 30.0, 80.0, 5.0
    A = a * np.exp(1j * t)
    r = A - d
    b = np.sqrt(np.abs(r) ** 2 - c**2)
    e4 = r / (b + 1j * c)  # A = O4 + (b + jc) e4
    return {"G2": 10 * np.exp(1j * t), "G3": A, "G4": d + 50 * e4, "X": d + (90 + 4j) * e4,
            "t2": t, "t4": np.angle(e4)}  # fmt: skip


CASES = {
    "slider_crank": (
        SLIDER_PART, "s", 20.0, _slider_pose,
        [("G2", "t2", 0.2, 300e-6), ("G3", "t3", 0.4, 2000e-6), ("B", None, 0.5, 0.0)],
        [("X", 5 - 30j), ("t3", 0.3), ("B", -20 + 0j)],
    ),
    "inverted_slider_crank": (
        INVERTED_PART, "i", 15.0, _inverted_pose,
        [("G2", "t2", 0.2, 300e-6), ("G3", "t4", 0.1, 50e-6), ("G4", "t4", 0.6, 5000e-6)],
        [("X", -12j), ("t2", 0.1), ("t4", -0.4)],
    ),
}  # fmt: skip


@pytest.mark.parametrize("kind", list(CASES))
def test_report_of_slider_parts_has_their_point_loads_and_torques(kind, tmp_path, capsys):
    """The reports of slider_crank and inverted_slider_crank parts dropped the file's
    [[loads.force]] and loads.torques (run had them): a slider-crank's T12 extremes printed
    724.3 / −656.7 N·mm where the loads give 723.6 / −728.1 (shaking force 31.8 vs 49.6 N)."""
    text, name, w, pose, bodies, loads = CASES[kind]
    path = tmp_path / f"{name}.toml"
    path.write_text(text, encoding="utf-8")
    assert main(["run", str(path), "--json"]) == 0
    table = json.loads(capsys.readouterr().out)["parts"][name]["tables"]["forces"]
    cols = table["columns"]
    T_run = np.array([row[cols.index("T12 [N*mm]")] for row in table["rows"]], float)
    th = np.radians(np.arange(0.0, 360.0, 1.0))
    T = _power_torque(pose, bodies, loads, w, th)
    np.testing.assert_allclose(T_run, T, rtol=0, atol=1e-6 * np.abs(T).max())
    out = tmp_path / f"{name}.html"
    assert main(["report", str(path), "-o", str(out)]) == 0
    page = page_text(out)
    for label, j in (("largest", int(np.argmax(T))), ("smallest", int(np.argmin(T)))):
        value, where = grab(page, rf"T12 {label} NUM N·mm at θ2 = NUM°")
        assert shown(value, T[j]) and abs(where - np.degrees(th[j])) < 0.06, (label, value)
    for key in ("power balance", "equilibrium of each link", "momentum: shaking force and moment"):
        (value,) = grab(page, rf"{key} NUM ")
        assert value < 1e-8, key


def test_studio_columns_are_the_newton_euler_ones(watt):
    """The studio's plotted driver torque and pin forces of the loaded Watt six-bar."""
    import tomllib

    from machdyn.studio.analysis import analyse
    from machdyn.studio.document import normalise

    _, path = watt
    doc = normalise(tomllib.loads(path.read_text(encoding="utf-8")))
    out = analyse(doc, samples=72)
    assert all(out["ok"]) and out["has_forces"]
    col = out["columns"]
    t = np.radians(np.asarray(col["theta_crank [deg]"], float))
    T, pins, _, _ = newton_euler(t)
    # the studio sends 7 significant digits of each column's largest value
    np.testing.assert_allclose(col["T_crank [N*mm]"], T, rtol=0, atol=2e-6 * np.abs(T).max())
    F = pins["ground", "crank"]
    np.testing.assert_allclose(col["F_ground_crank_x [N]"], F.real, atol=2e-6 * np.abs(F).max())
    np.testing.assert_allclose(col["F_ground_crank_y [N]"], F.imag, atol=2e-6 * np.abs(F).max())


GRCR = """
machdyn = 1
[fourbar.g]
r1 = 6.0
r2 = 7.0
r3 = 2.0
r4 = 8.0
form = 1
branch = {branch}
[fourbar.g.motion]
theta2 = {{ values = [{values}] }}
[fourbar.g.link2]
mass = 1.0
cg = 3.0
[fourbar.g.link3]
mass = 0.5
[fourbar.g.link4]
mass = 1.0
cg = 4.0
"""


@pytest.mark.parametrize("branch", [1, -1])
def test_report_of_a_grcr_takes_the_files_branch(branch, tmp_path, capsys):
    """A GRCR (6, 7, 2, 8) part with ``branch = -1`` (what synthesis writes for one half of
    its circuit) was reported on branch +1: T12 extremes 2115 / −2687 printed where the
    file's branch gives 1097 / −4646. T12 here by the power balance on the assembly run
    prints (its θ3 picks the circle intersection), positions by circle intersections."""
    r1, r2, r3, r4 = 6.0, 7.0, 2.0, 8.0
    lo = np.arccos((r1**2 + r2**2 - (r4 - r3) ** 2) / (2 * r1 * r2))  # links 3, 4 folded
    hi = np.arccos((r1**2 + r2**2 - (r4 + r3) ** 2) / (2 * r1 * r2))  # extended
    margin = 0.02 * (hi - lo)  # the report's sweep: the rocker's range less 2 % at each end
    th = np.linspace(lo + margin, hi - margin, 360)
    values = ", ".join(f"{v!r}" for v in np.degrees(th).tolist())
    path = tmp_path / "grcr.toml"
    path.write_text(GRCR.format(branch=branch, values=values), encoding="utf-8")
    assert main(["run", str(path), "--json"]) == 0
    tables = json.loads(capsys.readouterr().out)["parts"]["g"]["tables"]
    kin, frc = tables["kinematics"], tables["forces"]
    th3 = np.radians([row[kin["columns"].index("theta3 [deg]")] for row in kin["rows"]])
    T_run = np.array([row[frc["columns"].index("T12 [F*L]")] for row in frc["rows"]], float)

    def pose(t, near):
        A = r2 * np.exp(1j * t)
        d = r1 - A
        L = np.abs(d)
        a = (r3**2 - r4**2 + L**2) / (2 * L)
        both = [A + (a + s * 1j * np.sqrt(r3**2 - a**2)) * d / L for s in (1, -1)]
        B = np.where(np.abs(both[0] - near) < np.abs(both[1] - near), both[0], both[1])
        return [3 * A / r2, A, r1 + 4 * (B - r1) / r4], B

    B0 = r2 * np.exp(1j * th) + r3 * np.exp(1j * th3)
    h = 1e-4
    z = [pose(th + k * h, B0)[0] for k in (-2, -1, 0, 1, 2)]
    T = 0.0
    for i, m in enumerate((1.0, 0.5, 1.0)):
        zi = [p[i] for p in z]
        v = (zi[0] - 8 * zi[1] + 8 * zi[3] - zi[4]) / (12 * h)
        a = (-zi[0] + 16 * zi[1] - 30 * zi[2] + 16 * zi[3] - zi[4]) / (12 * h * h)
        T = T + m * (np.conj(v) * a).real  # ω2 = 1
    np.testing.assert_allclose(T_run, T, rtol=0, atol=1e-5 * np.abs(T).max())
    out = tmp_path / "grcr.html"
    assert main(["report", str(path), "-o", str(out)]) == 0
    page = page_text(out)
    for label, j in (("largest", int(np.argmax(T))), ("smallest", int(np.argmin(T)))):
        value, where = grab(page, rf"T12 {label} NUM torque units at θ2 = NUM°")
        assert shown(value, T[j]) and abs(where - np.degrees(th[j])) < 0.06, (label, value, T[j])


def test_tolerance_of_a_grcr_takes_the_files_branch(tmp_path, capsys):
    """``machdyn tolerance`` of the GRCR with ``branch = -1`` analysed branch +1: its
    theta3_nominal is now run's θ3, which closes the loop on the file's assembly."""
    th = np.radians([60.0, 70.0, 80.0, 90.0])
    text = GRCR.format(branch=-1, values=", ".join(f"{v!r}" for v in np.degrees(th).tolist()))
    path = tmp_path / "grcr.toml"
    path.write_text(text + "[fourbar.g.tolerance]\nr2 = 0.01\nsamples = 50\n", encoding="utf-8")
    assert main(["run", str(path), "--json"]) == 0
    kin = json.loads(capsys.readouterr().out)["parts"]["g"]["tables"]["kinematics"]
    th3 = np.array([row[kin["columns"].index("theta3 [deg]")] for row in kin["rows"]], float)
    th4 = np.array([row[kin["columns"].index("theta4 [deg]")] for row in kin["rows"]], float)
    A = 7.0 * np.exp(1j * th)  # run's angles close the loop (6, 7, 2, 8)
    B = A + 2.0 * np.exp(1j * np.radians(th3))
    np.testing.assert_allclose(B, 6.0 + 8.0 * np.exp(1j * np.radians(th4)), atol=1e-3)
    assert main(["tolerance", str(path), "--json"]) == 0
    tab = json.loads(capsys.readouterr().out)["parts"]["g"]["tables"]["theta3"]
    nominal = [row[tab["columns"].index("theta3_nominal [deg]")] for row in tab["rows"]]
    np.testing.assert_allclose(np.mod(nominal, 360.0), np.mod(th3, 360.0), atol=1e-3)


def test_report_self_checks_read_loads_as_the_dynamics_do():
    """``PointLoad`` records and ``(x, y)`` points are loads the dynamics take; the reports'
    self-checks unpacked them as triples of a complex point (a TypeError: FourBar.report with
    a PointLoad failed). A slider block's torque is carried by its guide (as documented in
    ``slidercrank_dynamics``), not left unbalanced on the block."""
    import re

    from machdyn import FourBar, SliderCrank
    from machdyn.dynamics import PointLoad
    from machdyn.linkage import Linkage
    from machdyn.report import report

    def checks(page):
        pairs = re.findall(r"(power balance|equilibrium of each link)</td><td[^>]*>([^<]*)", page)
        assert len(pairs) == 2
        return [float(v) for _, v in pairs]

    props = dict(mass=(1.0, 2.0, 1.5), inertia=(0.1, 0.5, 0.3), cg=(2.0, 3.0 + 0.5j, 3.0))
    loads = dict(external_forces=[PointLoad(3, 2.0 + 0.5j, 3 - 1j)], external_torques={4: 2.0})
    page = report(FourBar(8, 4, 7, 6), **props, gravity=9.81, **loads)
    assert max(checks(page)) < 1e-8
    page = report(SliderCrank(2, 6, 0.5), mass=(1, 2, 1.5), inertia=(0.1, 0.5), cg=(1, 3),
                  external_forces=[(3, 2.0 + 0.5j, 3 - 1j), PointLoad(4, 0.2j, 1 + 0j)],
                  external_torques={4: 2.0, 3: 1.0})  # fmt: skip
    assert max(checks(page)) < 1e-8
    lk = (
        Linkage({"O2": 0, "A": 1j, "B": 3 + 0j})
        .ground("O2")
        .link("crank", "O2", "A", mass=1.0, inertia=0.1)
        .link("rod", "A", "B", mass=1.0, inertia=0.1)
        .link("block", "B")
        .slider("block", "ground", "B", 0)
        .drive("crank")
    )
    page = report(lk, external_forces=[("rod", (0.5, 0.1), 1 + 1j)], gravity=9.81)
    assert max(checks(page)) < 1e-8
