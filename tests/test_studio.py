"""The studio's server and its calls, without a browser: security, bad input, and answers
checked against the library computed another way (closed forms, the spec reader)."""

from __future__ import annotations

import cmath
import json
import math
import urllib.error
import urllib.request

import numpy as np
import pytest

import machdyn
from machdyn.errors import InputError
from machdyn.fourbar import FourBar
from machdyn.studio.analysis import analyse
from machdyn.studio.document import edit, from_text, normalise
from machdyn.studio.exports import _hull_outline, export
from machdyn.studio.server import BODY_LIMIT, Studio
from machdyn.studio.templates import TEMPLATES, template


def request(studio, call, body, *, headers=None, method="POST", raw=None):
    """(status, parsed JSON or bytes) of one request to the studio."""
    data = raw if raw is not None else json.dumps(body).encode()
    h = {"Content-Type": "application/json", "Host": f"127.0.0.1:{studio.port}"}
    h.update(headers or {})
    req = urllib.request.Request(
        f"http://127.0.0.1:{studio.port}/api/{call}", data=data, headers=h, method=method
    )
    try:
        with urllib.request.urlopen(req, timeout=60) as r:
            payload = r.read()
            status = r.status
            kind = r.headers.get("Content-Type", "")
    except urllib.error.HTTPError as e:
        payload, status, kind = e.read(), e.code, e.headers.get("Content-Type", "")
    return status, (json.loads(payload) if kind.startswith("application/json") else payload)


# ------------------------------------------------------------------ security and bad input
def test_only_loopback_and_the_studios_own_host_and_origin(studio):
    assert studio.url.startswith("http://127.0.0.1:")
    status, answer = request(studio, "session", {}, headers={"Host": "evil.example:80"})
    assert status == 403 and "Host" in answer["error"]
    status, answer = request(studio, "session", {}, headers={"Origin": "http://evil.example"})
    assert status == 403 and "evil.example" in answer["error"]
    status, _ = request(studio, "session", {}, headers={"Sec-Fetch-Site": "cross-site"})
    assert status == 403
    own = {"Origin": f"http://localhost:{studio.port}", "Host": f"localhost:{studio.port}"}
    status, answer = request(studio, "session", {}, headers=own)
    assert status == 200 and answer["file"] == "design.toml"
    # the page itself is refused to a rebound name too
    req = urllib.request.Request(studio.url, headers={"Host": "attacker.test"})
    with pytest.raises(urllib.error.HTTPError) as err:
        urllib.request.urlopen(req, timeout=10)
    assert err.value.code == 403


def test_bodies_json_and_methods_are_checked_with_a_message(studio):
    status, answer = request(studio, "analyse", None, raw=b"{not json")
    assert status == 400 and "not valid JSON" in answer["error"]
    status, answer = request(studio, "analyse", None, raw=b"[1, 2]")
    assert status == 400 and "object" in answer["error"]
    big = b'{"doc": "' + b"x" * (BODY_LIMIT + 10) + b'"}'
    status, answer = request(studio, "analyse", None, raw=big)
    assert status == 413 and "too large" in answer["error"]
    status, answer = request(studio, "session", {}, headers={"Content-Type": "text/plain"})
    assert status == 415
    status, answer = request(studio, "nosuchcall", {})
    assert status == 404 and "nosuchcall" in answer["error"]
    status, answer = request(studio, "session", None, method="GET", raw=b"")
    assert status == 405


def test_a_document_the_reader_refuses_names_the_key(studio):
    doc = template("four-bar")
    doc["linkage"]["fourbar"]["links"]["crank"]["mass"] = "3 m"
    status, answer = request(studio, "analyse", {"doc": doc})
    assert status == 200  # an answer: this design cannot be analysed, and why
    assert "mass" in answer["refused"] and "a mass" in answer["refused"]
    assert answer["key"].endswith("links.crank.mass")
    status, answer = request(studio, "export", {"doc": doc, "format": "csv"})
    assert status == 422 and answer["key"].endswith("links.crank.mass")
    status, answer = request(studio, "analyse", {"doc": doc, "samples": "many"})
    assert status == 422 and answer["key"] == "samples"


def test_a_server_exception_is_a_message_and_a_log_line(studio, caplog):
    studio.calls["boom"] = (lambda body: 1 / 0, False)
    try:
        with caplog.at_level("ERROR", logger="machdyn.studio"):
            status, answer = request(studio, "boom", {})
    finally:
        del studio.calls["boom"]
    assert status == 500 and "ZeroDivisionError" in answer["error"]
    assert any("boom failed" in r.getMessage() for r in caplog.records)


def test_save_writes_only_the_file_given_and_session_reads_it_back(studio):
    doc = normalise(template("watt"))
    status, answer = request(studio, "save", {"doc": doc})
    assert status == 200 and answer["saved"] == "design.toml"
    assert studio.file.read_text().startswith("machdyn = 1")
    status, answer = request(studio, "session", {})
    assert answer["doc"] == doc
    bare = Studio(None, port=0)
    with pytest.raises(InputError, match="without a file"):
        bare.calls["save"][0]({"doc": doc})


def test_save_refuses_a_document_the_reader_refuses_and_leaves_the_file(studio):
    good = normalise(template("four-bar"))
    assert request(studio, "save", {"doc": good})[0] == 200
    before = studio.file.read_text()
    bad = json.loads(json.dumps(good))
    bad["linkage"]["fourbar"]["links"]["crank"]["mass"] = -1.0
    status, answer = request(studio, "save", {"doc": bad})
    assert 400 <= status < 500 and "linkage.fourbar.links.crank.mass" in json.dumps(answer)
    assert studio.file.read_text() == before
    assert from_text(before, "design.toml") == good  # what is on disk still opens


def test_asked_for_quantities_that_are_not_columns_are_listed_as_unknown():
    every = analyse(template("four-bar"), samples=12)
    assert every["unknown"] == [] and len(every["columns"]) == len(every["names"])
    real = every["names"][3]
    out = analyse(template("four-bar"), samples=12, quantities=["omega_9 [rad/s]", real, "omega_3"])
    assert list(out["columns"]) == [real] and out["columns"][real] == every["columns"][real]
    assert out["unknown"] == ["omega_9 [rad/s]", "omega_3"]  # (a label carries its unit)


def test_an_analysis_answer_carries_server_timing(studio):
    """Server-Timing: the analysis' wall time and its worker thread's CPU time (benchmark)."""
    body = json.dumps({"doc": template("four-bar"), "samples": 36}).encode()
    req = urllib.request.Request(
        f"http://127.0.0.1:{studio.port}/api/analyse",
        data=body,
        headers={"Content-Type": "application/json", "Host": f"127.0.0.1:{studio.port}"},
        method="POST",
    )
    with urllib.request.urlopen(req, timeout=60) as r:
        timing = r.headers["Server-Timing"]
    wall, cpu = (float(t.split("dur=")[1]) for t in timing.split(", "))
    assert timing.startswith("app;dur=") and ", cpu;dur=" in timing and wall > 0 and cpu >= 0


# ------------------------------------------------------------------ answers
def test_templates_read_and_close_and_move():
    for name in TEMPLATES:
        doc = template(name)
        lk = machdyn.from_spec(doc)
        assert lk.mobility() == 1, name
        out = analyse(doc, samples=36, quantities=[])
        assert out["summary"]["mobility"] == 1
        assert sum(out["ok"]) >= 2, name  # every template moves


def test_the_four_bar_coupler_curve_equals_the_closed_form():
    """The traced point P of the template against FourBar's closed form, placed by hand."""
    doc = template("four-bar")
    pts = {k: complex(*v) for k, v in doc["linkage"]["fourbar"]["points"].items()}
    out = analyse(doc, samples=72)
    scene = out["scene"]
    j = scene["names"].index("P")
    P = np.array(scene["x"][j], float) + 1j * np.array(scene["y"][j], float)
    O2, O4, A, B = pts["O2"], pts["O4"], pts["A"], pts["B"]
    theta1 = cmath.phase(O4 - O2)
    p, delta = abs(pts["P"] - A), cmath.phase((pts["P"] - A) / (B - A))
    fb = FourBar(abs(O4 - O2), abs(A - O2), abs(B - A), abs(B - O4), coupler=(p, delta))
    form = 1 if cmath.phase((B - O4) / (B - A)) > 0 else 2  # the notes' sign of phi12
    theta2 = np.radians(out["x"]) - theta1
    m = fb.solve(theta2, 1.0, form=form)
    expected = O2 + np.asarray(m.coupler) * cmath.exp(1j * theta1)
    assert np.all(out["ok"])
    assert np.max(np.abs(P - expected)) < 1e-4 * 80  # seven significant digits sent


def test_an_unassemblable_range_is_reported_with_the_solvers_reason():
    doc = template("four-bar")
    doc["linkage"]["fourbar"]["points"]["O4"] = [100.0, 0.0]  # no longer Grashof: a rocker
    doc["linkage"]["fourbar"]["points"]["B"] = [95.0, 55.0]
    out = analyse(doc, samples=90, quantities=[])
    lk = machdyn.from_spec(doc)
    x = np.radians(out["x"])
    m = lk.solve(x)
    assert out["motion_ok"] == [bool(v) for v in m.ok]
    assert not all(out["ok"]) and any(out["ok"])
    reasons = {p["reason"] for p in out["problems"]}
    assert reasons == {str(r) for r in np.asarray(m.reason)[~np.asarray(m.ok)]}
    ends = [k["frame"] for k in out["limits"] if k["kind"] == "limit"]
    assert all(out["ok"][k] for k in ends) and ends


def test_quantities_carry_units_and_equal_the_run_tables():
    doc = template("watt")
    out = analyse(doc, samples=24, quantities=["T_crank [N*m]", "|VD| [mm/s]"])
    assert set(out["columns"]) == {"T_crank [N*m]", "|VD| [mm/s]"}
    assert out["x_label"] == "theta_crank [deg]"
    lk = machdyn.from_spec(doc)
    x = np.radians(out["x"])
    m = lk.solve(x, velocity=10.0, acceleration=0.0)
    speed = np.abs(np.ravel(m.point_velocity["D"]))
    # seven significant digits of the column's largest value are sent
    assert np.allclose(out["columns"]["|VD| [mm/s]"], speed, rtol=0, atol=1e-6 * speed.max())


def test_centres_of_the_four_bar_equal_kennedy_by_hand():
    doc = template("four-bar")
    out = analyse(doc, samples=12, quantities=[], centres=True)
    pts = {k: complex(*v) for k, v in doc["linkage"]["fourbar"]["points"].items()}
    k = out["drawn"]
    got = {tuple(c["pair"]): complex(c["x"][k], c["y"][k]) for c in out["centres"]["centres"]}
    # I13 (ground-coupler) is where the lines O2A and O4B meet
    O2, O4, A, B = pts["O2"], pts["O4"], pts["A"], pts["B"]
    u, v = A - O2, B - O4
    t = ((O4 - O2) * v.conjugate()).imag / (u * v.conjugate()).imag
    I13 = O2 + t * u
    assert abs(got["ground", "coupler"] - I13) < 1e-4


# ------------------------------------------------------------------ document edits and files
def test_edits_rename_everywhere_and_set_lengths():
    doc = template("quick-return")
    renamed = edit(doc, {"kind": "rename_point", "old": "A", "new": "pin"})
    part = renamed["linkage"]["quick_return"]
    assert part["sliders"]["slot"]["at"] == "pin" and "pin" in part["links"]["crank"]["points"]
    machdyn.from_spec(renamed)  # still reads
    renamed = edit(doc, {"kind": "rename_link", "old": "arm", "new": "slotted arm"})
    part = renamed["linkage"]["quick_return"]
    assert part["sliders"]["slot"]["on"] == "slotted arm"
    machdyn.from_spec(renamed)
    stretched = edit(doc, {"kind": "length", "from": "O2", "to": "A", "value": 25.0})
    a = stretched["linkage"]["quick_return"]["points"]["A"]
    assert math.hypot(*a) == pytest.approx(25.0)
    with pytest.raises(InputError, match="taken"):
        edit(doc, {"kind": "rename_link", "old": "arm", "new": "crank"})
    with pytest.raises(InputError, match="positive"):
        edit(doc, {"kind": "length", "from": "O2", "to": "A", "value": -1})


def test_files_from_text_give_line_numbers_and_upgrade():
    text = machdyn.spec.dumps(template("four-bar"))
    assert from_text(text, "a.toml") == normalise(template("four-bar"))
    bad = text.replace("mass = 0.2", 'mass = "0.2 m"', 1)
    with pytest.raises(InputError, match=r"a.toml:\d+:.*mass"):
        from_text(bad, "a.toml")
    with pytest.raises(InputError, match="JSON syntax"):
        from_text("{", "a.json")


def test_dxf_outlines_are_the_hull_of_circles():
    """A binary link's outline is a stadium: perimeter 2 L + 2 pi r (from the bulges)."""
    L, r = 7.0, 0.5
    out = _hull_outline([0j, L * cmath.exp(0.3j)], r)
    perimeter = 0.0
    for k, (x, y, bulge) in enumerate(out):
        x2, y2, _ = out[(k + 1) % len(out)]
        chord = math.hypot(x2 - x, y2 - y)
        if bulge:
            angle = 4 * math.atan(bulge)
            perimeter += r * angle
            assert chord == pytest.approx(2 * r * math.sin(angle / 2))
        else:
            perimeter += chord
    assert perimeter == pytest.approx(2 * L + 2 * math.pi * r)


def test_exports_read_back(tmp_path):
    ezdxf = pytest.importorskip("ezdxf")
    doc = template("four-bar")
    f = export(doc, "dxf")
    (tmp_path / "a.dxf").write_bytes(f.data)
    d = ezdxf.readfile(tmp_path / "a.dxf")
    layers = {e.dxf.layer for e in d.modelspace()}
    assert {"link_crank", "link_coupler", "link_rocker"} <= layers
    assert d.header["$INSUNITS"] == 4  # millimetres
    csv = export(doc, "csv").data.decode()
    header = csv.splitlines()[0].split(",")
    assert header[0] == "theta_crank [deg]" and "T_crank [N*m]" in header
    assert export(doc, "svg").data.startswith(b"<svg")
    assert b"<html" in export(doc, "report").data[:200].lower()
    assert machdyn.spec.read(json.loads(export(doc, "json").data))
    with pytest.raises(InputError, match="must be one of"):
        export(doc, "bmp")


def test_the_command_starts_the_server_and_refuses_bad_arguments(tmp_path):
    import subprocess
    import sys

    from machdyn.cli import main

    assert main(["studio", str(tmp_path / "a.txt"), "--no-browser"]) == 1
    assert main(["studio", "--port", "70000", "--no-browser"]) == 1
    proc = subprocess.Popen(
        [sys.executable, "-c", "from machdyn.cli import main; main()", "studio", "--no-browser"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        line = proc.stdout.readline()
        assert line.startswith("machdyn studio: http://127.0.0.1:")
        url = line.split()[2]
        with urllib.request.urlopen(url, timeout=10) as r:
            page = r.read().decode()
            assert "default-src 'self'" in r.headers["Content-Security-Policy"]
        assert '<script type="module" src="/static/js/main.js">' in page
        with urllib.request.urlopen(url + "static/js/main.js", timeout=10) as r:
            assert b"class App" in r.read()
    finally:
        proc.terminate()
        proc.wait(10)


def test_transmission_angle_and_class_equal_the_closed_form():
    doc = template("four-bar")
    out = analyse(doc, samples=36, quantities=["mu_coupler_rocker [deg]"])
    fb = FourBar(80, 40, 70, 60)
    m = fb.solve(np.radians(out["x"]), 1.0, form=1)  # O2O4 along +x: local = global angles
    assert np.allclose(out["columns"]["mu_coupler_rocker [deg]"], np.degrees(m.mu), atol=1e-4)
    (loop,) = out["summary"]["classes"]
    assert loop["code"] == fb.barker_class == "GCRR"
    assert loop["lengths"] == [80.0, 40.0, 70.0, 60.0]


def test_flip_redraws_the_dyad_on_its_other_assembly():
    """B is mirrored in the line A-O4; the coupler and rocker move rigidly with it."""
    doc = template("four-bar")
    pts = {k: complex(*v) for k, v in doc["linkage"]["fourbar"]["points"].items()}
    out = edit(doc, {"kind": "flip", "group": "RRR dyad (coupler, rocker)"})
    new = {k: complex(*v) for k, v in out["linkage"]["fourbar"]["points"].items()}
    A, O4, B, P = pts["A"], pts["O4"], pts["B"], pts["P"]
    u = (O4 - A) / abs(O4 - A)
    mirrored = A + u * ((B - A) / u).conjugate()
    assert abs(new["B"] - mirrored) < 1e-9
    assert abs(new["A"] - A) < 1e-9 and abs(new["O4"] - O4) < 1e-9
    assert abs((new["P"] - A) / (new["B"] - A) - (P - A) / (B - A)) < 1e-12  # rigid coupler
    again = edit(out, {"kind": "flip", "group": "RRR dyad (coupler, rocker)"})
    assert abs(complex(*again["linkage"]["fourbar"]["points"]["B"]) - B) < 1e-9
    with pytest.raises(machdyn.errors.MachdynError):
        edit(doc, {"kind": "flip", "group": "driver crank (crank)"})


def hw6_positions():
    """The notes' HW 6 four-bar (8-4-7-6 cm, here mm ×10) at θ2 = 20°, 70°, 130°:
    its coupler point P (50 mm at 30° from AB) and pin B, the three positions of line CD."""
    m = FourBar(80, 40, 70, 60, coupler=(50, math.radians(30))).solve(np.radians([20, 70, 130]))
    return np.asarray(m.coupler), np.asarray(m.B)


def test_three_position_synthesis_with_fixed_pivots_gives_the_linkage_back():
    """Norton's inversion (Ex. 3-7) with HW 6's own pivots returns HW 6, and the design the
    page opens, solved by the general linkage solver at the reported θ2, carries C through
    the three positions (loop closure, not the synthesis' code)."""
    from machdyn.studio.synthesis import motion

    c, d = hw6_positions()
    xy = [[float(z.real), float(z.imag)] for z in (*c, *d)]
    out = motion({"c": xy[:3], "d": xy[3:], "O2": [0, 0], "O4": [80, 0]})
    assert out["lengths"] == pytest.approx([80, 40, 70, 60])
    assert out["theta2_deg"] == pytest.approx([20, 70, 130])
    assert not out["defects"] and out["class"] == "GCRR"
    lk = machdyn.from_spec(out["doc"])
    m = lk.solve(np.radians(out["theta2_deg"]))
    assert m.ok.all()
    assert np.allclose(m.points["C"], c) and np.allclose(m.points["B"], d)
    with pytest.raises(InputError, match="O4"):
        motion({"c": xy[:3], "d": xy[3:], "O2": [0, 0]})
