"""The studio opens ``[fourbar]`` and ``[slider_crank]`` parts as drawn linkages.

The file ``machdyn synth path`` writes (``candidate_spec``: ``O2``, ``theta1``, ``form`` or
``branch``) and hand-written four-bars and slider-cranks with masses, loads, gravity and
units are converted (``machdyn.studio.convert``) and the drawn linkage is run by
``Machine.run`` — the general ``Linkage`` solver and its Newton–Euler forces — while the
original file is run as ``machdyn run`` runs it: ``FourBar``/``SliderCrank``'s closed
forms. The two code paths must give the same angles (the linkage's absolute angles are
the four-bar's plus θ1), coupler path, rates, driving torque and ground-pin forces.
"""

from __future__ import annotations

import types
from pathlib import Path

import numpy as np
import pytest

from machdyn.errors import InputError
from machdyn.spec import loads, read
from machdyn.studio import document
from machdyn.studio.convert import linkage_document


def example(name: str) -> str:
    return (Path(__file__).parents[1] / "docs" / "examples" / name).read_text(encoding="utf-8")


def both(text: str, name: str):
    """(closed-form tables, linkage tables, converted doc, notes) of one file's part."""
    m = loads(text, "file.toml")
    doc, notes = linkage_document(m)
    assert next(iter(doc["linkage"])) == name
    closed = {t.name: t.columns for t in m.run([name])[name].tables}
    drawn = {t.name: t.columns for t in read(doc).run([name])[name].tables}
    return closed, drawn, doc, notes


def same_angle(a, b, ok, tol=1e-9):
    d = np.angle(np.exp(1j * (np.asarray(a)[ok] - np.asarray(b)[ok])))
    assert np.max(np.abs(d)) < tol


def check_fourbar(closed, drawn, theta1, names=("crank", "coupler", "rocker"), forces=True):
    kc, kd = closed["kinematics"], drawn["kinematics"]
    ok = kc["ok"].astype(bool) & kd["ok"].astype(bool)
    assert ok.sum() >= 0.8 * ok.size, (kc["ok"], kd["ok"])
    same_angle(kd[f"theta_{names[0]}"], kc["theta2"] + theta1, ok)
    same_angle(kd[f"theta_{names[1]}"], kc["theta3"] + theta1, ok)
    same_angle(kd[f"theta_{names[2]}"], kc["theta4"] + theta1, ok)
    for w in ("omega", "alpha"):
        for k, n in zip((3, 4), names[1:], strict=True):
            np.testing.assert_allclose(kd[f"{w}_{n}"][ok], kc[f"{w}{k}"][ok], rtol=1e-8, atol=1e-9)
    if "coupler" in closed:
        cp, pt = closed["coupler"], drawn["points"]
        for c in ("P_x", "P_y", "VP_x", "VP_y", "AP_x", "AP_y"):
            scale = np.max(np.abs(cp[c][ok])) + 1e-12
            np.testing.assert_allclose(pt[c][ok], cp[c][ok], rtol=0, atol=1e-9 * scale)
    if forces:
        fc, fd = closed["forces"], drawn["forces"]
        good = ok & fc["ok"].astype(bool) & fd["ok"].astype(bool)
        pairs = [("T12", f"T_{names[0]}")]
        pairs += [(f"F12_{x}", f"F_ground_{names[0]}_{x}") for x in "xy"]
        pairs += [(f"F14_{x}", f"F_ground_{names[2]}_{x}") for x in "xy"]
        for a, b in pairs:
            scale = np.max(np.abs(fc[a][good])) + 1e-12
            np.testing.assert_allclose(fd[b][good], fc[a][good], rtol=0, atol=1e-8 * scale)
        return good.sum()
    return ok.sum()


def test_hw6_fourbar_with_masses_torque_and_gravity_in_inches():
    text = example("hw6.toml")
    closed, drawn, doc, notes = both(text, "hw6")
    assert check_fourbar(closed, drawn, 0.0) == 13
    part = doc["linkage"]["hw6"]
    assert doc["units"]["length"] == "in" and doc["gravity"] is True
    assert part["points"]["O4"] == [8.0, 0.0] and part["report"] == ["P"]
    assert part["torques"] == {"rocker": -5.0}
    assert part["links"]["coupler"]["cg"] == [3.5, 1.0]
    assert notes[0].startswith("Opened [fourbar.hw6] as a drawn linkage: crank O2–A")
    assert not [n for n in notes if n.startswith("Not kept")]


def synth_file(r, coupler, O2, theta1_deg, branch):
    """The file ``machdyn synth path`` writes for a placed four-bar (its own writer)."""
    from machdyn.cli.synth import candidate_spec
    from machdyn.fourbar import FourBar
    from machdyn.synthesis.placed import PlacedFourBar

    pl = PlacedFourBar(FourBar(*r, coupler=coupler), O2, np.radians(theta1_deg), branch)
    c = types.SimpleNamespace(
        linkage=pl, distance=np.array([1e-4]), barker_class=pl.fourbar.barker_class
    )
    return candidate_spec(c, "candidate")


@pytest.mark.parametrize(
    "r, branch",
    [((80.0, 30.0, 70.0, 60.0), -1), ((80.0, 30.0, 70.0, 60.0), 1), ((60.0, 90.0, 30.0, 80.0), 1)],
    ids=["crank-rocker form 2", "crank-rocker form 1", "GRCR branch +1"],
)
def test_the_file_synth_path_writes_opens_as_the_same_mechanism(r, branch):
    text = synth_file(r, (50.0, np.radians(30.0)), 20 - 10j, 40.0, branch)
    assert ("branch = 1" in text) == (r[0] == 60.0)  # GRCR: the sign of phi12, else form
    text += '[units]\nlength = "mm"\n'  # a unit system too (angles in the file are deg)
    closed, drawn, doc, notes = both(text, "candidate")
    part = doc["linkage"]["candidate"]
    pts = {k: complex(*v) for k, v in part["points"].items()}
    assert pts["O2"] == pytest.approx(20 - 10j)
    assert np.degrees(np.angle(pts["O4"] - pts["O2"])) == pytest.approx(40.0)
    assert abs(pts["O4"] - pts["O2"]) == pytest.approx(r[0])
    assert abs(pts["B"] - pts["A"]) == pytest.approx(r[2])
    assert abs(pts["P"] - pts["A"]) == pytest.approx(50.0)
    names = list(part["links"])
    assert names[1] == "coupler" and names[0] in ("crank", "input")
    assert check_fourbar(closed, drawn, np.radians(40.0), names, forces=False) >= 8
    assert any("placement (O2, theta1)" in n for n in notes)


def test_a_placed_fourbar_keeps_masses_point_loads_torques_and_gravity():
    text = synth_file((80.0, 30.0, 70.0, 60.0), (50.0, np.radians(30.0)), 20 - 10j, 40.0, 1)
    text = text.replace('title = "candidate"\n', 'title = "candidate"\ngravity = true\n')
    text += (
        '[fourbar.candidate.motion]\ntheta2 = [0, 350, 10]\nomega2 = "120 rpm"\n'
        'alpha2 = "3 rad/s^2"\n'
        '[fourbar.candidate.link2]\nmass = 0.3\ninertia = "2e-4 kg*m^2"\ncg = 15\n'
        '[fourbar.candidate.link3]\nmass = 0.8\ninertia = "9e-4 kg*m^2"\ncg = [30, 12]\n'
        '[fourbar.candidate.link4]\nmass = 0.5\ninertia = "4e-4 kg*m^2"\ncg = [30, -5]\n'
        '[fourbar.candidate.loads]\ntorque4 = "-2 N*m"\n'
        'torques = { link3 = "0.5 N*m", link4 = "0.25 N*m" }\n'
        '[[fourbar.candidate.loads.force]]\nlink = 3\nat = [50, 20]\nforce = ["10 N", "-25 N"]\n'
        '[fourbar.candidate.simulate]\nmotor = { kind = "constant", torque = "1 N*m" }\nturns = 2\n'
        '[units]\nlength = "mm"\nmass = "kg"\ntorque = "N*m"\n'
    )
    closed, drawn, doc, notes = both(text, "candidate")
    assert check_fourbar(closed, drawn, np.radians(40.0)) == 36
    part = doc["linkage"]["candidate"]
    assert part["torques"]["rocker"] == pytest.approx(-1.75)
    assert part["forces"] == [{"link": "coupler", "at": [50.0, 20.0], "force": [10.0, -25.0]}]
    assert part["motion"]["crank"]["sweep"] == pytest.approx([40.0, 390.0, 10.0])
    assert any(n.startswith("Not kept: [fourbar.candidate.simulate]") for n in notes)


def test_slider_cranks_with_friction_loads_and_a_point_on_the_rod():
    base = example("slider_crank.toml")
    extra = ("gravity = true\n" + base).replace(
        "[slider_crank.engine]\n",
        '[slider_crank.engine]\npoint = { p = 80, delta = "20 deg" }\nform = 2\n',
    )
    extra = extra.replace(
        'friction = "coulomb"\nmu = 0.05',
        'friction = "viscous"\nbeta = 0.4\ntorques = { link3 = "3 N*m" }',
    )
    extra = extra.replace(
        "[slider_crank.engine.link4]       # the piston\nmass = 1.5",
        "[slider_crank.engine.link4]\nmass = 1.5\ninertia = 0.1",
    )
    for text, rows in ((base, 13), (extra, 13)):
        closed, drawn, doc, notes = both(text, "engine")
        kc, kd = closed["kinematics"], drawn["kinematics"]
        ok = kc["ok"].astype(bool) & kd["ok"].astype(bool)
        assert ok.sum() == rows
        same_angle(kd["theta_crank"], kc["theta2"], ok)
        # Norton's slider-crank loop a e^{j theta2} - b e^{j theta3} = B: theta3 is the angle
        # of B -> A; the drawn link's x axis runs A -> B (its mass frame in both files)
        same_angle(kd["theta_coupler"], kc["theta3"] + np.pi, ok)
        np.testing.assert_allclose(kd["omega_coupler"], kc["omega3"], rtol=1e-9, atol=1e-9)
        # the guide's displacement from the drawn pose (theta2 = 0) is d - d(0)
        np.testing.assert_allclose(
            kd["d_guide"] - kd["d_guide"][0], kc["d"] - kc["d"][0], atol=1e-8
        )
        np.testing.assert_allclose(kd["ddot_guide"], kc["d_dot"], rtol=1e-9, atol=1e-6)
        fc, fd = closed["forces"], drawn["forces"]
        for a, b in (
            ("T12", "T_crank"),
            ("F12_x", "F_ground_crank_x"),
            ("F12_y", "F_ground_crank_y"),
        ):
            scale = np.max(np.abs(fc[a]))
            np.testing.assert_allclose(fd[b], fc[a], rtol=0, atol=1e-8 * scale)
        part = doc["linkage"]["engine"]
        assert part["sliders"]["guide"]["on"] == "ground"
        assert part["forces"] == [{"link": "slider", "at": "B", "force": [-2000.0, 0.0]}]
    assert part["friction"] == {"guide": {"viscous": 0.4}}
    assert part["report"] == ["P"]
    np.testing.assert_allclose(closed["point"]["P_x"], drawn["points"]["P_x"], atol=1e-9)
    np.testing.assert_allclose(closed["point"]["P_y"], drawn["points"]["P_y"], atol=1e-9)
    assert any("link4] inertia" in n for n in notes)
    assert any("[inverted_slider_crank.shaper]" in n for n in notes)  # kept as it was


def test_open_and_save_in_the_studio(tmp_path):
    text = example("hw6.toml")
    doc, notes = document.read_text(text, "hw6.toml")
    assert "linkage" in doc and "fourbar" not in doc and notes
    # a file that would lose a key on Save is not overwritten (Download is the way)
    lossy = tmp_path / "lossy.toml"
    lossy.write_text(text + "[fourbar.hw6.tolerance]\nr2 = 0.01\n", encoding="utf-8")
    with pytest.raises(InputError, match=r"tolerance"):
        document.save(lossy, doc)
    assert "[fourbar.hw6.tolerance]" in lossy.read_text(encoding="utf-8")
    # ... one that loses nothing is written as the drawn linkage, and opens again
    plain = tmp_path / "plain.toml"
    plain.write_text(text, encoding="utf-8")
    document.save(plain, doc)
    again, notes2 = document.read_text(plain.read_text(encoding="utf-8"), "plain.toml")
    assert again == doc and notes2 == []
    session = document.session(tmp_path / "lossy.toml", {})
    assert session["doc"]["linkage"]["hw6"] and any("tolerance" in n for n in session["notes"])


def test_a_press_driven_by_a_gear_pair_keeps_its_references_and_flywheel():
    """docs/examples/press.toml: the four-bar is driven_by a gear pair, a flywheel takes its
    torque; drawn as a linkage, the references hold and the flywheel is sized the same."""
    m = loads(example("press.toml"), "press.toml")
    doc, notes = linkage_document(m)
    assert "[gear_pair.reducer], [flywheel.crank]" in notes[1]
    closed, drawn = m.run(), read(doc).run()
    fc = {t.name: t.columns for t in closed["press"].tables}["forces"]
    fd = {t.name: t.columns for t in drawn["press"].tables}["forces"]
    np.testing.assert_allclose(fd["T_crank"], fc["T12"], rtol=1e-9, atol=1e-9 * np.ptp(fc["T12"]))
    sized = [{s.label: s.value for s in r["crank"].summary} for r in (closed, drawn)]
    assert sized[1]["I (flywheel inertia)"] == pytest.approx(sized[0]["I (flywheel inertia)"])
    assert sized[1]["omega_avg"] == pytest.approx(sized[0]["omega_avg"])


@pytest.mark.parametrize("form, friction", [(1, 'friction = "coulomb"\nmu = 0.1'), (2, "")])
def test_an_inverted_slider_crank_with_an_offset_slot_masses_friction_and_gravity(form, friction):
    """Norton's inversion #3 (A − O4 = (b + jc) e^{jθ4}): the slotted link drawn through O4
    and a point on its x axis, the block sliding in it; against InvertedSliderCrank."""
    text = (
        'machdyn = 1\ngravity = true\n[units]\nlength = "mm"\nmass = "kg"\ntorque = "N*m"\n'
        f"[inverted_slider_crank.q]\ncrank = 100\nground = 260\noffset = 30\nform = {form}\n"
        '[inverted_slider_crank.q.motion]\ntheta2 = [10, 350, 20]\nomega2 = "90 rpm"\n'
        "[inverted_slider_crank.q.link2]\nmass = 0.4\ninertia = 300\ncg = 50\n"
        "[inverted_slider_crank.q.link3]\nmass = 0.2\ninertia = 20\ncg = [5, 2]\n"
        "[inverted_slider_crank.q.link4]\nmass = 1.1\ninertia = 9000\ncg = [150, 10]\n"
        f'[inverted_slider_crank.q.loads]\ntorque4 = "-4 N*m"\n{friction}\n'
        "[[inverted_slider_crank.q.loads.force]]\nlink = 3\nat = [4, -3]\n"
        'force = ["5 N", "2 N"]\n'
    )
    closed, drawn, _, notes = both(text, "q")
    kc, kd = closed["kinematics"], drawn["kinematics"]
    ok = kc["ok"].astype(bool) & kd["ok"].astype(bool)
    assert ok.all() and ok.size == 18
    same_angle(kd["theta_rocker"], kc["theta4"], ok)
    # the block turns with the slot (a one-point link's angle is counted from the drawing)
    same_angle(kd["theta_slider"] - kd["theta_slider"][0], kc["theta4"] - kc["theta4"][0], ok)
    np.testing.assert_allclose(kd["omega_rocker"], kc["omega4"], rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(kd["alpha_rocker"], kc["alpha4"], rtol=1e-9, atol=1e-8)
    # the block's travel along the slot is b's
    np.testing.assert_allclose(kd["d_guide"] - kd["d_guide"][0], kc["b"] - kc["b"][0], atol=1e-8)
    fc, fd = closed["forces"], drawn["forces"]
    good = ok & fc["ok"].astype(bool) & fd["ok"].astype(bool)
    assert good.all()
    pairs = [("T12", "T_crank"), ("F12_x", "F_ground_crank_x"), ("F14_y", "F_ground_rocker_y")]
    for a, b in pairs:
        scale = np.max(np.abs(fc[a]))
        np.testing.assert_allclose(fd[b], fc[a], rtol=0, atol=1e-8 * scale)
    assert not [n for n in notes if n.startswith("Not kept")]
