"""Audit 3: the studio's API — numbers, round trips and bad requests, without a browser.

* the slider-crank template's columns (slider travel and speed, rod angle, the
  crank torque at constant speed under gravity) against the slider-crank
  written here: ``x_B = a cos θ + √(b² − (a sin θ − c)²)`` and the power
  balance ``T ω = d(KE)/dt + d(V)/dt`` summed from the links' centres of mass
  (velocities and accelerations by central differences in θ);
* the server's answers equal the Python calls (``analyse``), and a document
  survives save → session, export TOML/JSON → open, for every template;
* bad requests to every call are answered 4xx (or, for ``analyse``, a
  ``refused`` answer naming the key) with a message: never a 500 or a traceback.
"""

from __future__ import annotations

import json
import urllib.error
import urllib.request

import numpy as np
import pytest

from machdyn.studio.analysis import analyse
from machdyn.studio.document import normalise
from machdyn.studio.templates import TEMPLATES, template

G0 = 9.80665  # standard gravity: the document says gravity = true


def post(studio, call, body=None, raw=None):
    data = raw if raw is not None else json.dumps(body).encode()
    headers = {"Content-Type": "application/json", "Host": f"127.0.0.1:{studio.port}"}
    req = urllib.request.Request(
        f"http://127.0.0.1:{studio.port}/api/{call}", data=data, headers=headers, method="POST"
    )
    try:
        with urllib.request.urlopen(req, timeout=120) as r:
            payload, status, kind = r.read(), r.status, r.headers.get("Content-Type", "")
    except urllib.error.HTTPError as e:
        payload, status, kind = e.read(), e.code, e.headers.get("Content-Type", "")
    return status, (json.loads(payload) if kind.startswith("application/json") else payload)


# --- numbers ---------------------------------------------------------------------------


def slider_crank_geometry(doc):
    part = doc["linkage"]["slider_crank"]
    pts = {k: complex(*v) for k, v in part["points"].items()}
    a = abs(pts["A"] - pts["O2"])
    b = abs(pts["B"] - pts["A"])
    c = pts["B"].imag  # the guide through B, along x
    return part, a, b, c


def test_slider_crank_template_columns_equal_the_closed_form_and_power_balance():
    doc = normalise(template("slider-crank"))
    part, a, b, c = slider_crank_geometry(doc)
    assert doc["units"]["length"] == "mm" and doc["gravity"] is True
    out = analyse(doc, samples=24)
    assert all(out["ok"])
    col = out["columns"]
    theta = np.radians(np.asarray(col["theta_crank [deg]"]))
    w = part["motion"]["crank"]["velocity"]  # rad/s, constant

    def xB(t):
        return a * np.cos(t) + np.sqrt(b**2 - (a * np.sin(t) - c) ** 2)

    h = 1e-5

    # the studio sends 7 significant digits of each column's largest value
    def close(got, want, rel=1e-6):
        want = np.asarray(want)
        np.testing.assert_allclose(got, want, rtol=0, atol=rel * np.abs(want).max())

    close(col["d_cylinder [mm]"], xB(theta))
    speed = (xB(theta + h) - xB(theta - h)) / (2 * h) * w
    close(col["ddot_cylinder [mm/s]"], speed, 2e-6)  # θ itself is rounded to 1e-4 deg
    rod = np.degrees(np.arcsin((c - a * np.sin(theta)) / b))
    close(col["theta_rod [deg]"], rod, 2e-6)

    # T12 by the power balance, SI (mm → m, kg·mm² → kg·m²)
    links = part["links"]
    m2, m3, m4 = links["crank"]["mass"], links["rod"]["mass"], links["piston"]["mass"]
    I2, I3 = links["crank"]["inertia"] * 1e-6, links["rod"]["inertia"] * 1e-6
    c2, c3 = links["crank"]["cg"], links["rod"]["cg"]

    def centres(t):
        A = a * np.exp(1j * t)
        B = xB(t) + 1j * c
        e3 = (B - A) / b
        return [1e-3 * c2 * A / a, 1e-3 * (A + c3 * e3), 1e-3 * B], np.angle(e3)

    (g_p, th3_p), (g_0, _), (g_m, th3_m) = centres(theta + h), centres(theta), centres(theta - h)
    power = np.zeros_like(theta)
    for m, gp, g0, gm in zip((m2, m3, m4), g_p, g_0, g_m, strict=True):
        v = (gp - gm) / (2 * h) * w
        acc = (gp - 2 * g0 + gm) / h**2 * w**2
        power += m * (v.real * acc.real + v.imag * acc.imag) + m * G0 * v.imag
    w3 = np.angle(np.exp(1j * (th3_p - th3_m))) / (2 * h) * w
    th3 = lambda t: centres(t)[1]  # noqa: E731
    a3 = np.angle(np.exp(1j * (th3(theta + 1e-3) - 2 * th3(theta) + th3(theta - 1e-3)))) / 1e-6
    power += I3 * w3 * a3 * w**2  # I2's kinetic energy is constant at constant ω
    assert I2 > 0
    close(col["T_crank [N*m]"], power / w, 2e-5)


def test_the_server_answers_what_the_library_computes(studio):
    doc = normalise(template("four-bar"))
    status, answer = post(studio, "analyse", {"doc": doc, "samples": 36})
    assert status == 200
    direct = analyse(doc, samples=36)
    assert answer["names"] == direct["names"]
    for name, values in direct["columns"].items():
        np.testing.assert_allclose(answer["columns"][name], values, rtol=1e-12, atol=1e-12)
    # and the four-bar's rocker angle equals two circles intersected here
    part = doc["linkage"][next(iter(doc["linkage"]))]
    pts = {k: complex(*v) for k, v in part["points"].items()}
    crank, rocker = part["links"]["crank"]["points"], part["links"]["rocker"]["points"]
    O2, O4 = pts[crank[0]], pts[rocker[0]]
    A0, B0 = pts[crank[1]], pts[rocker[1]]
    r2, r3, r4 = abs(A0 - O2), abs(B0 - A0), abs(B0 - O4)
    theta = np.radians(answer["columns"]["theta_crank [deg]"])
    A = O2 + r2 * np.exp(1j * theta)
    d = O4 - A
    L = np.abs(d)
    along = (r3**2 - r4**2 + L**2) / (2 * L)
    side = np.sign(((B0 - A0) / (O4 - A0)).imag)  # the drawn assembly
    B = A + (along + side * 1j * np.sqrt(r3**2 - along**2)) * d / L
    theta4 = np.degrees(np.angle(B - O4))
    got = np.asarray(answer["columns"]["theta_rocker [deg]"])
    np.testing.assert_allclose(
        np.exp(1j * np.radians(got)), np.exp(1j * np.radians(theta4)), atol=2e-5
    )  # θ2 rounded to 1e-4 deg


@pytest.mark.parametrize("name", list(TEMPLATES))
def test_every_template_round_trips_through_save_export_and_open(studio, name):
    status, answer = post(studio, "template", {"name": name})
    assert status == 200
    doc = answer["doc"]
    status, saved = post(studio, "save", {"doc": doc})
    assert status == 200 and saved["saved"] == "design.toml"
    status, session = post(studio, "session", {})
    assert status == 200 and session["error"] is None and session["doc"] == doc
    for fmt, ending in (("toml", ".toml"), ("json", ".json")):
        status, data = post(studio, "export", {"doc": doc, "format": fmt})
        assert status == 200
        text = data.decode() if isinstance(data, bytes) else json.dumps(data)
        status, opened = post(studio, "open", {"text": text, "name": f"x{ending}"})
        assert status == 200 and opened["doc"] == doc, fmt


# --- bad requests -------------------------------------------------------------------------


def _doc():
    return normalise(template("four-bar"))


def _with(change):
    doc = _doc()
    change(doc["linkage"][next(iter(doc["linkage"]))])
    return doc


BAD = [
    ("template", {"name": "pentagon"}, "template"),
    ("template", {"name": 3}, "name"),
    ("template", {}, "name"),
    ("open", {"text": "a = [", "name": "x.toml"}, "x.toml"),
    ("open", {"text": "[1, 2]", "name": "x.json"}, "machine file"),
    ("open", {"text": "{", "name": "x.json"}, "x.json"),
    ("open", {"text": 5, "name": "x.toml"}, "text"),
    ("edit", {"doc": "x", "op": {}}, "doc"),
    ("edit", {"doc": _doc(), "op": {"kind": "explode"}}, "op.kind"),
    (
        "edit",
        {"doc": _doc(), "op": {"kind": "length", "from": "O2", "to": "A", "value": -3}},
        "op.value",
    ),
    ("edit", {"doc": _doc(), "op": {"kind": "rename_point", "old": "ZZ", "new": "Q"}}, "op.old"),
    ("edit", {"doc": _doc(), "op": {"kind": "rename_point", "old": "A", "new": "B"}}, "op.new"),
    ("export", {"doc": _doc(), "format": "exe"}, "format"),
    ("export", {"doc": _doc(), "format": "svg", "frame": "first"}, "frame"),
    ("export", {"doc": {"machdyn": 1}, "format": "csv"}, None),
    ("synth_motion", {}, "c"),
    ("synth_path", {"points": [["a", "b"]]}, "targets"),
    ("save", {"doc": [1, 2]}, "doc"),
]


@pytest.mark.parametrize(("call", "body", "key"), BAD)
def test_bad_requests_are_4xx_with_a_message(studio, call, body, key):
    status, answer = post(studio, call, body)
    assert 400 <= status < 500, (status, answer)
    assert isinstance(answer, dict) and answer["error"] and "Traceback" not in answer["error"]
    if key is not None:
        assert answer.get("key") == key or key in answer["error"]


@pytest.mark.parametrize(
    ("change", "key"),
    [
        (lambda p: p["points"].__setitem__("A", [float("nan"), 0.0]), ".points.A"),
        (lambda p: p["points"].__setitem__("A", "x"), ".points.A"),
        (lambda p: p["links"]["crank"].__setitem__("mass", -1.0), ".links.crank.mass"),
        (lambda p: p.__setitem__("drive", ["nothing"]), ".drive"),
        (lambda p: p["links"].__setitem__("crank", {"points": ["O2", "Q"]}), ".crank"),
    ],
)
def test_a_bad_document_is_refused_naming_its_key(studio, change, key):
    # NaN is sent as the bare token Python's json writes: the server reads it, the spec refuses
    status, answer = post(studio, "analyse", {"doc": _with(change), "samples": 24})
    assert status == 200 and "refused" in answer, answer
    assert key in answer.get("key", "") or key.strip(".").split(".")[-1] in answer["refused"]


@pytest.mark.parametrize("samples", [0, 7, 20_001, 10**400, -1, 3.5, True])
def test_sample_counts_out_of_range_are_named(studio, samples):
    raw = json.dumps({"doc": _doc()})[:-1] + f', "samples": {json.dumps(samples)}}}'
    status, answer = post(studio, "analyse", raw=raw.encode())
    assert status in (200, 422), answer
    text = answer.get("refused") or answer.get("error")
    assert "samples" in text and "Traceback" not in text


def test_unknown_calls_methods_and_bodies(studio):
    assert post(studio, "explode", {})[0] == 404
    assert post(studio, "analyse", raw=b"{not json")[0] == 400
    assert post(studio, "analyse", raw=b"[1, 2]")[0] == 400
    status, answer = post(studio, "analyse", raw=b"\xff\xfe")
    assert status == 400 and "JSON" in answer["error"]
