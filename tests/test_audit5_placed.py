"""Audit 5: four-bars placed in the plane (what path synthesis returns) — the synthesis
result's machine file through ``machdyn run``, the studio's candidate documents, and the
drawings — against the plane's geometry written here.

Targets are ten points of the coupler path of a four-bar (80, 30, 70, 60; P: p = 50,
δ = 30°) placed at O2 = (20, −10), θ1 = 40°. For the candidates a small atlas returns:

* ``machdyn run`` of ``candidate_spec`` (the file ``machdyn synth path`` writes: ``O2``,
  ``theta1``): every printed row closes the loop *in the plane* — A = O2 + r2 e^{j(θ2+θ1)},
  B = A + r3 e^{j(θ3+θ1)} = O4 + r4 e^{j(θ4+θ1)} with O4 = O2 + r1 e^{jθ1}, and
  P = A + p e^{jδ}(B − A)/r3 — and its P passes through the targets as closely as the
  synthesis says;
* the studio's candidate document (a ``[linkage]`` drawn at the first target) solved by the
  studio's ``analyse``: its points keep the candidate's lengths, and its coupler point at
  crank angle φ (from +x) is the file's P at θ2 = φ − θ1 on the same circuit — the studio
  and ``machdyn run`` show one mechanism;
* the drawings: ``path_synthesis_scene`` puts the pivots at the candidate's O2, O4 and the
  coupler point on the targets; the report of the candidate file draws it in the plane.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from machdyn.cli import main

O2_TRUE, THETA1_TRUE = 20 - 10j, np.radians(40.0)


def targets() -> np.ndarray:
    """Ten points of the placed four-bar's coupler path, by circle intersection here."""
    r1, r2, r3, r4, p, delta = 80.0, 30.0, 70.0, 60.0, 50.0, np.radians(30.0)
    th = np.radians(np.arange(0.0, 360.0, 36.0))
    A = r2 * np.exp(1j * th)
    d = r1 - A
    L = np.abs(d)
    a = (r3**2 - r4**2 + L**2) / (2 * L)
    B = A + (a + 1j * np.sqrt(r3**2 - a**2)) * d / L  # one circuit, the same for all θ2
    P = A + p * np.exp(1j * delta) * (B - A) / r3
    return O2_TRUE + np.exp(1j * THETA1_TRUE) * P


@pytest.fixture(scope="module")
def found(tmp_path_factory):
    from machdyn.studio import synthesis as studio_synthesis
    from machdyn.synthesis import open_atlas, path_from_atlas
    from machdyn.synthesis.atlas_store import build_atlas

    folder = tmp_path_factory.mktemp("atlas") / "small.atlas"
    build_atlas(folder, 2048, chunk_size=2048, seed=5, progress=False)
    atlas = open_atlas(folder)
    pts = targets()
    res = path_from_atlas(pts, atlas, closed=True, n=3)
    saved = studio_synthesis._small.get("atlas")
    studio_synthesis._small["atlas"] = atlas  # the studio's session atlas: this one
    try:
        body = {"targets": [[z.real, z.imag] for z in pts], "closed": True, "n": 3}
        studio = studio_synthesis.path(body)
    finally:
        if saved is None:
            studio_synthesis._small.pop("atlas", None)
        else:
            studio_synthesis._small["atlas"] = saved
    return res, studio


def run_candidate(tmp_path, capsys, cand, theta2_deg):
    """``machdyn run --json`` of the synthesis file with the given θ2 (degrees)."""
    from machdyn.cli.synth import candidate_spec

    text = candidate_spec(cand, "candidate")
    values = ", ".join(f"{float(v)!r}" for v in theta2_deg)
    text += f"\n[fourbar.candidate.motion]\ntheta2 = {{ values = [{values}] }}\n"
    path = tmp_path / "candidate.toml"
    path.write_text(text, encoding="utf-8")
    assert main(["run", str(path), "--json"]) == 0, text
    part = json.loads(capsys.readouterr().out)["parts"]["candidate"]
    tables = {}
    for name, table in part["tables"].items():
        cols = table["columns"]
        tables[name] = {c: np.array([row[i] for row in table["rows"]]) for i, c in enumerate(cols)}
    return path, tables


def test_run_of_the_synthesis_file_closes_the_loop_in_the_plane(found, tmp_path, capsys):
    res, _ = found
    assert res.candidates
    for cand in res.candidates[:2]:
        pl = cand.linkage
        r1, r2, r3, r4 = (float(v) for v in pl.lengths)
        p, delta = pl.fourbar.coupler
        _, tab = run_candidate(tmp_path, capsys, cand, np.arange(0.0, 360.0, 5.0))
        kin, cp = tab["kinematics"], tab["coupler"]
        ok = kin["ok"].astype(bool)
        assert ok.sum() >= 8
        O2, t1 = complex(pl.O2), float(pl.theta1)  # the file's placement, read back below
        O4 = O2 + r1 * np.exp(1j * t1)
        th2, th3, th4 = (
            np.radians(kin[k][ok]) + t1 for k in ("theta2 [deg]", "theta3 [deg]", "theta4 [deg]")
        )
        A = O2 + r2 * np.exp(1j * th2)
        B = A + r3 * np.exp(1j * th3)
        scale = r1 + r2 + r3 + r4
        np.testing.assert_allclose(np.abs(B - O4), r4, atol=1e-3 * scale)  # 4 decimals of deg
        np.testing.assert_allclose(B, O4 + r4 * np.exp(1j * th4), atol=1e-3 * scale)
        P = cp["P_x [L]"][ok] + 1j * cp["P_y [L]"][ok]
        np.testing.assert_allclose(P, A + p * np.exp(1j * delta) * (B - A) / r3, atol=1e-3 * scale)


def test_studio_candidate_is_the_files_mechanism_on_the_same_circuit(found, tmp_path, capsys):
    from machdyn.studio.analysis import analyse

    res, studio = found
    assert len(studio["candidates"]) >= 2
    for cand, shown in zip(res.candidates[:2], studio["candidates"][:2], strict=False):
        pl = cand.linkage
        part = shown["doc"]["linkage"]["path"]
        pts = {k: complex(*v) for k, v in part["points"].items()}
        assert abs(pts["O2"] - complex(pl.O2)) < 1e-9 * abs(complex(pl.O4) - complex(pl.O2))
        lengths = [abs(pts["O4"] - pts["O2"]), abs(pts["A"] - pts["O2"])]
        lengths += [abs(pts["B"] - pts["A"]), abs(pts["B"] - pts["O4"])]
        np.testing.assert_allclose(lengths, [float(v) for v in pl.lengths], rtol=1e-9)
        out = analyse(shown["doc"], samples=72)
        col = out["columns"]
        ok = np.array(out["ok"])
        phi = np.array(col["theta_crank [deg]"])
        P = np.array(col["P_x [L]"], dtype=float) + 1j * np.array(col["P_y [L]"], dtype=float)
        _, tab = run_candidate(tmp_path, capsys, cand, phi - np.degrees(float(pl.theta1)))
        cp = tab["coupler"]
        ok_run = cp["ok"].astype(bool)
        np.testing.assert_array_equal(ok, ok_run)  # the same poses assemble
        Q = cp["P_x [L]"] + 1j * cp["P_y [L]"]
        size = float(sum(pl.lengths))
        np.testing.assert_allclose(P[ok], Q[ok], rtol=0, atol=2e-6 * size)
        # and the studio's path passes through the targets as the synthesis says
        fine = analyse(shown["doc"], samples=3600)["columns"]
        path = np.array(fine["P_x [L]"], float) + 1j * np.array(fine["P_y [L]"], float)
        miss = [np.nanmin(np.abs(path - z)) for z in targets()]
        assert max(miss) <= shown["max_distance"] + 0.01 * size


PLACED = """
machdyn = 1
title = "placed"
gravity = true
[units]
length = "mm"
[fourbar.cand]
r1 = 80.0
r2 = 30.0
r3 = 70.0
r4 = 60.0
coupler = { p = 50.0, delta = "30 deg" }
O2 = [20.0, -10.0]
theta1 = "40 deg"
[fourbar.cand.motion]
omega2 = "10 rad/s"
[fourbar.cand.link2]
mass = "0.1 kg"
inertia = "100 kg*mm^2"
cg = 15.0
[fourbar.cand.link3]
mass = "0.3 kg"
inertia = "500 kg*mm^2"
cg = [35.0, 5.0]
"""


def test_report_draws_a_placed_fourbar_where_the_plane_says(tmp_path):
    import html
    import re

    path = tmp_path / "placed.toml"
    path.write_text(PLACED, encoding="utf-8")
    out = tmp_path / "placed.html"
    assert main(["report", str(path), "-o", str(out)]) == 0
    page = out.read_text(encoding="utf-8")
    raw = re.search(
        r'<script type="application/json" class="machdyn-frames">(.*?)</script>', page, re.S
    )
    data = json.loads(html.unescape(raw.group(1)))
    tol = 1.5 * 10.0 ** -data["decimals"]
    xy = [
        np.asarray(x, float) + 1j * np.asarray(y, float)
        for x, y in zip(data["x"], data["y"], strict=True)
    ]
    O2, O4, A, B, P = xy  # the four-bar scene's points: O2, O4, A, B, P
    t1 = np.radians(40.0)
    assert abs(O2 - (20 - 10j)) < tol and abs(O4 - (20 - 10j + 80 * np.exp(1j * t1))) < tol
    th2 = np.radians(np.asarray(data["readout"][0]["v"], float))  # θ2 from O2 → O4
    np.testing.assert_allclose(A, O2 + 30 * np.exp(1j * (th2 + t1)), atol=tol + 30 * 1e-4)
    np.testing.assert_allclose(np.abs(B - A), 70, atol=2 * tol)
    np.testing.assert_allclose(np.abs(B - O4), 60, atol=2 * tol)
    np.testing.assert_allclose(P, A + 50 * np.exp(1j * np.radians(30)) * (B - A) / 70, atol=4 * tol)
    # the coupler curve drawn behind it: P of the same placed four-bar (frame 0 on it)
    svg = re.search(r'id="md\d+-coupler_curve".*?points="([^"]+)"', page, re.S).group(1)
    curve = np.array([complex(*map(float, q.split(","))) for q in svg.split()])
    assert np.min(np.abs(curve - P[0])) < 0.02 * 80
    text = re.sub(
        r"\s+",
        " ",
        re.sub(r"<[^>]+>", " ", re.sub(r"<(svg|script|style)\b.*?</\1>", " ", page, flags=re.S)),
    )
    assert "placed: O2 (20, -10) mm" in text and "placed: θ1 40°" in text


def test_path_synthesis_drawing_puts_pivots_and_coupler_point_in_the_plane(found):
    import machdyn.draw as md

    res, _ = found
    for cand in res.candidates[:2]:
        s = md.scene(cand, n=720)
        pl = cand.linkage
        r1, r2, r3, r4 = (float(v) for v in pl.lengths)
        p, delta = pl.fourbar.coupler
        O2, O4 = s.point("O2"), s.point("O4")
        np.testing.assert_allclose(np.abs(O4 - O2), r1, rtol=1e-12)
        assert np.allclose(O2, complex(pl.O2)) and np.allclose(np.angle(O4 - O2), pl.theta1)
        ok = s.shown
        A, B, C = s.point("A")[ok], s.point("B")[ok], s.point("C")[ok]
        np.testing.assert_allclose(np.abs(A - O2[ok]), r2, rtol=1e-9)
        np.testing.assert_allclose(np.abs(B - A), r3, rtol=1e-9)
        np.testing.assert_allclose(np.abs(B - O4[ok]), r4, rtol=1e-9)
        np.testing.assert_allclose(C, A + p * np.exp(1j * delta) * (B - A) / r3, atol=1e-9 * r1)
        # the drawn coupler point passes the targets as the synthesis reports (720 poses)
        step = 2 * np.pi / 720 * (r2 + r3 + p)  # how far a point moves between poses, at most
        for z, d in zip(targets(), np.ravel(cand.distance), strict=True):
            assert np.min(np.abs(C - z)) <= d + step


TOLERANCED = """
machdyn = 1
gravity = true
[units]
length = "mm"
[fourbar.f]
r1 = 80.0
r2 = 30.0
r3 = 70.0
r4 = 60.0
coupler = { p = 50.0, delta = "30 deg" }
O2 = [20.0, -10.0]
theta1 = "40 deg"
[fourbar.f.motion]
theta2 = [0, 330, 30]
omega2 = "10 rad/s"
[fourbar.f.link2]
mass = "0.1 kg"
inertia = "100 kg*mm^2"
cg = 15.0
[fourbar.f.link3]
mass = "0.3 kg"
inertia = "500 kg*mm^2"
cg = [35.0, 5.0]
[fourbar.f.link4]
mass = "0.2 kg"
inertia = "300 kg*mm^2"
cg = 30.0
[fourbar.f.tolerance]
r2 = 0.05
samples = 200
"""


def _placed_power_balance(th2):
    """T12 (N·mm) and P (mm) of TOLERANCED by circle intersection in the plane and the power
    balance T ω = Σ m (v·a + g v_y) + I ω α (SI), velocities by five-point differences."""
    O2, t1, w = 20 - 10j, np.radians(40.0), 10.0
    O4 = O2 + 80 * np.exp(1j * t1)

    def pose(t):
        A = O2 + 30 * np.exp(1j * (t + t1))
        d = O4 - A
        L = np.abs(d)
        a = (70**2 - 60**2 + L**2) / (2 * L)
        B = A + (a + 1j * np.sqrt(70**2 - a**2)) * d / L  # form 1: B left of A → O4
        e2, e3, e4 = (A - O2) / 30, (B - A) / 70, (B - O4) / 60
        G = (O2 + 15 * e2, A + (35 + 5j) * e3, O4 + 30 * e4)
        P = A + 50 * np.exp(1j * np.radians(30)) * e3
        return G, (np.angle(e2), np.angle(e3), np.angle(e4)), P

    h = 1e-3
    poses = [pose(th2 + k * h) for k in (-2, -1, 0, 1, 2)]
    power = 0.0
    for i, (m, inertia) in enumerate(((0.1, 100e-6), (0.3, 500e-6), (0.2, 300e-6))):
        z = [p[0][i] * 1e-3 for p in poses]
        q = np.unwrap(np.array([p[1][i] for p in poses]), axis=0)
        v = (z[0] - 8 * z[1] + 8 * z[3] - z[4]) / (12 * h) * w
        acc = (-z[0] + 16 * z[1] - 30 * z[2] + 16 * z[3] - z[4]) / (12 * h * h) * w * w
        wq = (q[0] - 8 * q[1] + 8 * q[3] - q[4]) / (12 * h) * w
        aq = (-q[0] + 16 * q[1] - 30 * q[2] + 16 * q[3] - q[4]) / (12 * h * h) * w * w
        power = power + m * ((np.conj(v) * acc).real + 9.80665 * v.imag) + inertia * wq * aq
    return power / w * 1e3, poses[2][2]


def test_tolerance_of_a_placed_fourbar_nominals_are_the_planes(tmp_path, capsys):
    """``machdyn tolerance`` printed P_nominal in the four-bar's own frame and T12_nominal
    with no gravity at all for a placed four-bar (−0.33 N·mm where 122.6 is right)."""
    path = tmp_path / "tol.toml"
    path.write_text(TOLERANCED, encoding="utf-8")
    assert main(["tolerance", str(path), "--json"]) == 0
    tables = json.loads(capsys.readouterr().out)["parts"]["f"]["tables"]
    cols = {}
    for table in tables.values():
        for i, c in enumerate(table["columns"]):
            cols[c] = np.array([row[i] for row in table["rows"]], dtype=object)
    th2 = np.radians(cols["theta2 [deg]"].astype(float))
    T, P = _placed_power_balance(th2)
    got = cols["T12_nominal [N*m]"].astype(float) * 1e3 if "T12_nominal [N*m]" in cols else None
    got = cols["T12_nominal [N*mm]"].astype(float) if got is None else got
    np.testing.assert_allclose(got, T, rtol=0, atol=1e-6 * np.abs(T).max())
    Px = cols["P_nominal_x [mm]"].astype(float)
    Py = cols["P_nominal_y [mm]"].astype(float)
    np.testing.assert_allclose(Px + 1j * Py, P, rtol=0, atol=1e-9 * 80)


def test_tolerance_leaves_out_a_t12_without_the_files_loads(tmp_path, capsys):
    """A four-bar's [[loads.force]] and loads.torques cannot enter the tolerance's T12: it
    printed a T12 without them; now no T12, and a warning saying why (geometry kept)."""
    text = TOLERANCED + "[[fourbar.f.loads.force]]\nlink = 3\nat = [10.0, 0.0]\n"
    path = tmp_path / "tol.toml"
    path.write_text(text + "force = [0.0, -5.0]\n", encoding="utf-8")
    assert main(["tolerance", str(path)]) == 0
    out = capsys.readouterr().out
    assert "T12 of f" not in out and "theta4 of f" in out
    assert "T12 is not toleranced" in out


def test_studio_dxf_of_a_candidate_has_its_pin_holes_at_the_planes_points(found, tmp_path):
    ezdxf = pytest.importorskip("ezdxf")
    from machdyn.studio.exports import export

    res, studio = found
    doc = studio["candidates"][0]["doc"]
    pl = res.candidates[0].linkage
    A, B, P, _ = pl.pose(float(np.ravel(res.candidates[0].theta2)[0]))
    where = {"O2": complex(pl.O2), "O4": complex(pl.O4), "A": complex(A), "B": complex(B)}
    where["P"] = complex(P)
    (tmp_path / "c.dxf").write_bytes(export(doc, "dxf").data)
    holes = [
        (e.dxf.layer, complex(e.dxf.center.x, e.dxf.center.y))
        for e in ezdxf.readfile(tmp_path / "c.dxf").modelspace()
        if e.dxftype() == "CIRCLE"
    ]
    links = {"link_crank": "O2 A", "link_coupler": "A B P", "link_rocker": "O4 B"}
    links["ground"] = "O2 O4"
    for layer, names in links.items():
        centres = [z for lay, z in holes if lay == layer]
        for name in names.split():
            assert min(abs(z - where[name]) for z in centres) < 1e-9 * abs(pl.lengths[0]), name
