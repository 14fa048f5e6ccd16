"""Scenes are the solver's coordinates, drawn: every joint kind, gaps, and both back ends.

Independent references: ``Linkage.solve`` / ``FourBar.solve`` called here; the
drawn pose (``Linkage.points``) reproduced by solving at the drawn driver values;
rigid-body distances on the scene's own numbers.
"""

from __future__ import annotations

import json
import re

import matplotlib.pyplot as plt
import numpy as np
import pytest

from machdyn import FourBar, InvertedSliderCrank, SliderCrank
from machdyn.draw import Scene, scene, to_html, to_svg
from machdyn.draw.html import DATA_CLASS, frame_data
from machdyn.draw.linkage import default_values, drawn_value
from machdyn.errors import InputError
from machdyn.linkage import Linkage


@pytest.fixture(autouse=True)
def _close():
    yield
    plt.close("all")


def scotch_yoke() -> Linkage:
    lk = Linkage({"O2": 0j, "A": 2.0 + 0j, "Y": 5.0 + 0j}).ground("O2")
    lk.link("crank", "O2", "A").link("yoke", "Y")
    lk.slider("yoke", "ground", "Y", 0.0, through="O2", name="guide")
    return lk.slot("A", "crank", "yoke", np.pi / 2, name="slot").drive("crank")


def loader() -> Linkage:
    """The second notes' loader, driven by its cylinder C-E; a gas spring, a torsion spring."""
    A = 141.0 * np.exp(1j * np.radians(45))
    B = A + 120.0
    pts = {"O2": 0j, "A": A, "B": B, "O4": B - 100j, "P": A + 200.0 * np.exp(1j * np.radians(135))}
    pts |= {"C": 290.0 - 10.0j, "E": A + 50.0 * np.exp(1j * np.radians(-20)), "S": -60 + 0j}
    lk = Linkage(pts).ground("O2", "O4", "C", "S")
    lk.link("arm", "O2", "A").link("3", "A", "B", "P", "E").link("4", "B", "O4")
    lk.spring("gas", "S", "A", stiffness=2.0, free_length=150.0)
    lk.torsion_spring("hinge", "O4", links=("ground", "4"), stiffness=1.0, free_angle=0.0)
    return lk.actuator("cylinder", "C", "E").drive("cylinder")


def planetary() -> Linkage:
    lk = Linkage({"O": (0, 0), "S": (2, 0), "Pc": (0, 3), "Q": (1, 3)}).ground("O")
    lk.link("sun", "O", "S").link("arm", "O", "Pc").link("planet", "Pc", "Q")
    lk.roll("sun", "O", 2.0, "planet", "Pc", 1.0, name="sun/planet")
    lk.roll("planet", "Pc", 1.0, "ground", "O", 4.0, internal=True, name="planet/ring")
    return lk.drive("sun")


def arm_with_elbow_motor() -> Linkage:
    arm = Linkage({"O": 0, "E": 1 + 0j, "H": 1.8 + 0j}).ground("O")
    arm.link("upper", "O", "E").link("fore", "E", "H")
    return arm.motor("elbow", "E", links=("upper", "fore")).drive("upper", "elbow")


@pytest.mark.parametrize(
    ("build", "kinds"),
    [
        (scotch_yoke, {"guide", "slider", "shape", "bar", "pin", "motor", "ground"}),
        (loader, {"actuator", "plate", "bar", "spring", "shape", "ground", "pin"}),
        (planetary, {"wheel", "bar", "motor", "pin"}),
        (arm_with_elbow_motor, {"motor", "bar", "pin"}),
    ],
)
def test_every_joint_kind_is_drawn_at_the_solved_points(build, kinds):
    lk = build()
    s = scene(lk, n=24)
    assert kinds <= {i.kind for i in s.items}
    values = {d: np.full(len(s), drawn_value(lk, d)) for d in lk.drivers}
    first = lk.drivers[0]
    values[first] = default_values(lk, 24)[0][first]
    m = lk.solve(values)
    for p in lk.points:
        drawn = s.point(p)
        good = s.shown
        np.testing.assert_allclose(drawn[good], np.ravel(m.points[p])[good], atol=1e-12)
    # both back ends render it
    svg = to_svg(s)
    assert svg.count("<g") > 3 and "NaN" not in svg
    from machdyn.draw import draw

    draw(lk, n=24)


def test_solving_at_the_drawn_driver_values_gives_the_drawing():
    # drawn_value is the drawing's own driver value: solving there reproduces every point
    for lk in (scotch_yoke(), loader(), planetary(), arm_with_elbow_motor()):
        m = lk.solve({d: np.array([drawn_value(lk, d)]) for d in lk.drivers})
        for p, z in lk.points.items():
            assert abs(complex(np.ravel(m.points[p])[0]) - z) < 1e-9, (lk.drivers, p)


def test_a_rocking_driver_goes_there_and_back_within_its_reach():
    # a four-bar driven by its rocker (GRCR 6-9-3-8 turned around: the 9-link rocks)
    A = 9.0 * np.exp(1j * np.radians(60))
    B = A + 3 * np.exp(1j * np.radians(-10))
    # place O4 on the circle of radius 8 about B, at distance 6 from O2 (pick the meeting point)
    d = abs(B)
    a = (6**2 - 8**2 + d**2) / (2 * d)
    O4 = a * B / d + np.sqrt(36 - a**2) * 1j * B / d
    lk = Linkage({"O2": 0j, "O4": O4, "A": A, "B": B}).ground("O2", "O4")
    lk = lk.link("in", "O2", "A").link("c", "A", "B").link("out", "O4", "B").drive("in")
    values, closed = default_values(lk, 20)
    v = values["in"]
    assert closed and v.size == 38  # 20 out, 18 back
    m = lk.solve(values)
    assert m.ok[1:-1].all()
    assert np.allclose(v[1:19][::-1], v[20:])  # the return stroke retraces the outward one
    # the ends are the assemblable limits: a little beyond them nothing assembles
    step = np.ptp(v[:20]) / 19
    beyond = lk.solve(np.array([v[19] + 3 * step, v[0] - 3 * step]))
    assert not beyond.ok.any()


def test_unsolved_frames_are_gaps_never_zeros():
    fb = FourBar(6, 9, 3, 8)  # a rocker input: 10° cannot be assembled
    theta2 = np.radians([60.0, 10.0, 80.0])
    s = scene(fb, theta2=theta2)
    assert s.shown.tolist() == [True, False, True]
    assert np.isnan(s.point("A")[1]) and s.reason[1]
    data = frame_data(s)
    A = data["x"][s.index("A")]
    assert A[1] is None and A[0] is not None  # null in the page, not 0
    readout = {r["label"]: r["v"] for r in data["readout"]}
    assert readout["θ3"][1] is None and readout["θ2"][1] == 10.0
    # the SVG of that frame hides the moving links and says why
    assert 'class="moving" visibility="hidden"' in to_svg(s, 1)
    page = to_html(s)
    embedded = json.loads(re.search(rf'class="{DATA_CLASS}">(.*?)</script>', page).group(1))
    assert "cannot be assembled" in embedded["reason"][1]


def test_closed_form_models_draw_through_the_same_scene():
    for model in (FourBar(8, 4, 7, 6), SliderCrank(2, 6, 0.5), InvertedSliderCrank(2, 4, 0.5)):
        s = scene(model, n=12)
        assert isinstance(s, Scene) and len(s) == 12
        # rigid links keep their lengths in the drawn numbers
        for item in s.items:
            if item.kind == "bar" and s.shown.all():
                p, q = (s.point(n) for n in item.points)
                assert np.ptp(np.abs(q - p)) < 1e-9, (model, item.gid)


def test_inverted_slider_crank_block_rides_on_link_4():
    isc = InvertedSliderCrank(2.0, 4.0, 0.5)
    s = scene(isc, n=36)
    m = isc.solve(np.linspace(0, 2 * np.pi, 36, endpoint=False))
    np.testing.assert_allclose(s.point("A"), m.A, atol=1e-12)
    # A is on the slot line of link 4: at distance |c| from O4 across the direction θ4
    e4 = np.exp(1j * m.theta4)
    across = ((m.A - 4.0) * np.conj(e4)).imag
    np.testing.assert_allclose(across, 0.5, atol=1e-12)
    np.testing.assert_allclose(s.angles["theta4"], m.theta4, atol=1e-12)


def test_bad_input_names_the_field():
    with pytest.raises(InputError, match="cannot draw a str"):
        scene("four-bar")
    with pytest.raises(InputError) as err:
        scene(FourBar(8, 4, 7, 6), n=0)
    assert err.value.field == "n"
    with pytest.raises(InputError, match="no driver"):
        scene(Linkage({"O": 0, "A": 1}).ground("O").link("a", "O", "A"))
    s = scene(FourBar(8, 4, 7, 6), n=4)
    with pytest.raises(InputError) as err:
        to_svg(s, uid="1 bad")
    assert err.value.field == "uid"


# ----------------------------------------------------------------------------- elements
def test_the_roller_rides_the_turning_cam():
    from machdyn import cams

    prog = cams.CamProgram(
        [
            cams.Segment("rise", np.radians(60), 1.0, "cycloidal"),
            cams.Segment("dwell", np.radians(120)),
            cams.Segment("fall", np.radians(60), 1.0, "cycloidal"),
            cams.Segment("dwell", np.radians(120)),
        ]
    )
    cam = cams.TranslatingRoller(prime_radius=3.0, roller_radius=0.5).profile(prog, n=720)
    s = scene(cam, n=48)
    (shape,) = [i for i in s.items if i.gid == "cam"]
    for f in range(0, 48, 7):
        surface = shape.outline * np.exp(1j * s.angles["cam"][f])  # the cam as drawn
        roller = s.point("roller")[f]
        # the roller touches the cam: its centre is one roller radius from the surface
        assert np.abs(surface - roller).min() == pytest.approx(0.5, abs=2e-3)
        # and sits on the follower's axis (x = 0) at the prime radius + s
        assert roller.real == pytest.approx(0.0, abs=1e-12)
        assert roller.imag == pytest.approx(3.0 + cam.s[f * 15], abs=1e-12)


def test_gears_turn_at_the_velocity_ratio_along_their_line_of_action():
    from machdyn.gears import Gear, GearPair

    pair = GearPair(Gear(18, module=1.0), Gear(40, module=1.0))
    s = scene(pair, n=30)
    np.testing.assert_allclose(np.diff(s.angles["gear"]) / np.diff(s.angles["pinion"]), -18 / 40)
    first, last = s.point("first")[0], s.point("last")[0]
    # the line of action is tangent to both base circles (Norton §9.2)
    for centre, rb in ((0j, pair.pinion.base_radius), (s.point("Og")[0], pair.gear.base_radius)):
        u = (last - first) / abs(last - first)
        assert abs(((centre - first) * np.conj(u)).imag) == pytest.approx(rb, rel=1e-9)
    assert abs(last - first) == pytest.approx(pair.length_of_action, rel=1e-9)


def test_instant_centres_of_any_model_off_the_view_are_border_arrows_with_coordinates():
    """A linkage drawn with its centres: each one inside the view is a cross, each one
    outside an arrow labelled with its coordinates — which equal the four-bar's closed-form
    centres (FourBar.instant_centres, a different code path) of the same geometry."""
    from machdyn.draw import draw

    theta2 = np.radians(100.0)
    fb = FourBar(8, 4, 7, 6)
    m = fb.solve(theta2)
    A, B = complex(m.A), complex(m.B)
    lk = (
        Linkage({"O2": 0j, "O4": 8 + 0j, "A": A, "B": B})
        .ground("O2", "O4")
        .link("2", "O2", "A")
        .link("3", "A", "B")
        .link("4", "O4", "B")
        .drive("2")
    )
    ax = draw(lk, 0, n=2, instant_centres=True)  # frame 0: the drawn pose
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    truth = fb.instant_centres(theta2)
    names = {"1": "ground"}
    arrows = {
        t.get_gid(): t.get_text()
        for t in ax.texts
        if (t.get_gid() or "").startswith("centre_arrow")
    }
    cross = next(line for line in ax.lines if line.get_gid() == "instant_centres")
    inside = set(zip(np.round(cross.get_xdata(), 6), np.round(cross.get_ydata(), 6), strict=True))
    outside = 0
    for (i, j), c in truth.items():
        z = complex(np.ravel(c.point)[0])
        a, b = names.get(str(i), str(i)), names.get(str(j), str(j))
        if x0 <= z.real <= x1 and y0 <= z.imag <= y1:
            assert (round(z.real, 6), round(z.imag, 6)) in inside, (i, j)
        else:
            outside += 1
            text = arrows.get(f"centre_arrow_I({a}, {b})") or arrows[f"centre_arrow_I({b}, {a})"]
            x, y = (float(v) for v in re.findall(r"\(([-\d.e+]+), ([-\d.e+]+)\)", text)[-1])
            assert x == pytest.approx(z.real, rel=1e-3) and y == pytest.approx(z.imag, rel=1e-3)
    assert outside >= 1  # this pose puts I24 far off the drawing
    plt.close("all")
