"""Drawings of every model, looked at in a real browser (headless Chromium, Playwright).

Independent references: the solver's own coordinates (``Linkage.solve``,
``FourBar.solve``) read back from the DOM the page's script produced, to the
printed precision; the link lengths of the six-bar checked on the drawn
numbers themselves; nothing loaded but the file; no console error.
Screenshots: ``tests/screenshots/`` (or ``$MACHDYN_SCREENSHOTS``).
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from browser import Page, screenshots
from closed_forms import circle_meet
from machdyn import FourBar, InvertedSliderCrank, SliderCrank
from machdyn.draw import scene, to_html
from machdyn.linkage import Linkage

pytestmark = pytest.mark.slow


@pytest.fixture
def tab(browser):
    page = Page(browser)
    yield page
    page.close()


def watt_with_slider(theta2: float = np.pi / 6, names: dict | None = None) -> Linkage:
    """Watt II six-bar (crank-rocker 8-2-7-6, ternary rocker O4-B-C) driving a slider on y = 8."""
    n = {k: k for k in ("O2", "O4", "A", "B", "C", "D", "G", "2", "3", "4", "5", "6")}
    n.update(names or {})
    O4 = 8.0 + 0j
    A = 2.0 * np.exp(1j * theta2)
    B = circle_meet(A, 7.0, O4, 6.0)
    C = O4 + 4.0 * (B - O4) / abs(B - O4) * np.exp(1j * np.radians(-35))
    D = complex(C.real + np.sqrt(36 - (8 - C.imag) ** 2), 8.0)
    pts = {n["O2"]: 0j, n["O4"]: O4, n["A"]: A, n["B"]: B, n["C"]: C, n["D"]: D, n["G"]: 8j}
    lk = Linkage(pts).ground(n["O2"], n["O4"], n["G"])
    lk.link(n["2"], n["O2"], n["A"]).link(n["3"], n["A"], n["B"])
    lk.link(n["4"], n["O4"], n["B"], n["C"]).link(n["5"], n["C"], n["D"]).link(n["6"], n["D"])
    lk.slider(n["6"], "ground", n["D"], 0.0, name="slide", through=n["G"])
    return lk.drive(n["2"])


def _cam():
    from machdyn import cams

    prog = cams.CamProgram(
        [
            cams.Segment("rise", np.radians(60), 1.0, "cycloidal"),
            cams.Segment("dwell", np.radians(120)),
            cams.Segment("fall", np.radians(60), 1.0, "cycloidal"),
            cams.Segment("dwell", np.radians(120)),
        ]
    )
    return cams.TranslatingRoller(prime_radius=3.0, roller_radius=0.5).profile(prog)


def _gears():
    from machdyn.gears import Gear, GearPair

    return GearPair(Gear(18, module=1.0), Gear(40, module=1.0))


def _path():
    from machdyn.synthesis import PlacedFourBar
    from machdyn.synthesis.path import PathSynthesis

    pl = PlacedFourBar.from_pivots(O2=0, O4=8, A=4, B=8 + 6j, P=5 + 3j)
    targets = pl.pose(np.radians([0.0, 40.0, 80.0, 120.0]))[2] + 0.05
    return PathSynthesis(
        pl, targets, np.zeros(4), np.full(4, 0.07), "GCRR", True, 0.6, True, 0.0, ()
    )


ELEMENTS = {"cam": _cam, "gears": _gears, "path": _path}


DRAWN = """(uid) => {
  const svg = document.getElementById(uid);
  const out = {bars: [], plates: [], pins: [], sliders: [], frame: svg.getAttribute("data-frame")};
  svg.querySelectorAll("g.moving line.bar, g.static line.bar").forEach((l) => out.bars.push({
    name: l.getAttribute("data-name"), visible: l.getAttribute("visibility") !== "hidden",
    xy: ["x1", "y1", "x2", "y2"].map((a) => Number(l.getAttribute(a)))}));
  svg.querySelectorAll("polygon.plate").forEach((p) => out.plates.push({
    name: p.getAttribute("data-name"),
    xy: p.getAttribute("points").trim().split(/\\s+/).map((s) => s.split(",").map(Number))}));
  svg.querySelectorAll("g[id$='-pins'] circle").forEach((c) => out.pins.push(
    [Number(c.getAttribute("cx")), Number(c.getAttribute("cy"))]));
  svg.querySelectorAll("g[id*='-slider']").forEach((g) => out.sliders.push(
    g.getAttribute("transform")));
  return out;
}"""


def show(tab: Page, k: int) -> dict:
    tab.page.evaluate(f"document.querySelector('.machdyn-scene').machdynShow({k})")
    uid = tab.page.evaluate("document.querySelector('svg.machdyn-drawing').id")
    return tab.page.evaluate(DRAWN, uid)


def test_six_bar_with_a_slider_is_drawn_at_the_solved_coordinates(tab, tmp_path):
    lk = watt_with_slider()
    s = scene(lk, n=60)
    path = tmp_path / "watt_slider.html"
    to_html(lk, path, n=60)
    page = tab.open(path)
    tab.assert_clean(path)
    places = int(page.evaluate("document.querySelector('svg').getAttribute('data-decimals')"))
    tol = 0.5 * 10.0**-places + 1e-12
    # the frames' driver values, read from the scene, solved again here directly
    theta2 = np.radians(s.readout[0].values)
    m = lk.solve(theta2)
    assert m.ok.all()
    for k in (0, 7, 23, 41, 59):
        drawn = show(tab, k)
        assert drawn["frame"] == str(k)
        bars = {b["name"]: np.array(b["xy"]) for b in drawn["bars"]}
        assert set(bars) == {"2", "3", "5"}  # binary links as bars; 4 is a plate
        for name, (p, q) in (("2", ("O2", "A")), ("3", ("A", "B")), ("5", ("C", "D"))):
            ref = [
                m.points[p][k].real,
                m.points[p][k].imag,
                m.points[q][k].real,
                m.points[q][k].imag,
            ]
            np.testing.assert_allclose(bars[name], ref, atol=tol, rtol=0, err_msg=f"{name} at {k}")
        (plate,) = drawn["plates"]
        corners = {complex(round(x, places), round(y, places)) for x, y in plate["xy"]}
        for p in ("O4", "B", "C"):
            z = m.points[p][k]
            assert any(abs(c - z) <= 2 * tol for c in corners), (p, k)
        pins = np.array(drawn["pins"])
        for p in ("O2", "A", "B", "D", "O4", "C"):
            hit = np.abs(pins[:, 0] + 1j * pins[:, 1] - m.points[p][k]).min()
            assert hit <= 2 * tol, (p, k)
        # the block sits on the solved D, along the ground guide (y = 8)
        (slider,) = drawn["sliders"]
        x, y, angle = map(float, re.findall(r"-?\d+(?:\.\d+)?(?:e-?\d+)?", slider)[:3])
        assert abs(x - m.points["D"][k].real) <= tol and abs(y - 8.0) <= tol and angle == 0
        # the drawn numbers keep the link lengths (to the printed precision)
        A, B = bars["3"][:2] @ [1, 1j], bars["3"][2:] @ [1, 1j]
        assert abs(abs(B - A) - 7.0) < 4 * tol
    tab.shot("linkage_watt_slider")


@pytest.mark.parametrize(
    ("name", "model", "expect"),
    [
        (
            "fourbar_hw6",
            FourBar(8, 4, 7, 6, coupler=(5, np.radians(30))),
            ("link2", "coupler_curve"),
        ),
        ("slidercrank", SliderCrank(2.0, 6.0, 0.5, point=(3.0, 0.4)), ("slider", "slide_guide")),
        ("inverted_slidercrank", InvertedSliderCrank(2.0, 4.0, 0.5), ("slider", "link4")),
        ("cam_roller", "cam", ("cam", "roller", "follower")),
        ("gear_pair", "gears", ("pinion", "gear", "line_of_action")),
        ("path_synthesis", "path", ("link2", "coupler_curve", "targets")),
    ],
)
def test_each_model_draws_in_the_browser(tab, tmp_path, name, model, expect):
    model = ELEMENTS[model]() if isinstance(model, str) else model
    path = tmp_path / f"{name}.html"
    to_html(model, path, n=48)
    page = tab.open(path)
    tab.assert_clean(path)
    uid = page.evaluate("document.querySelector('svg.machdyn-drawing').id")
    for gid in expect:
        assert page.locator(f"#{uid}-{gid}").count() == 1, gid
    # playing moves the drawing, and the readout shows numbers for the frame shown
    first = page.evaluate("document.querySelector('svg').getAttribute('data-frame')")
    page.wait_for_timeout(250)
    assert page.evaluate("document.querySelector('svg').getAttribute('data-frame')") != first
    cells = page.locator("table.readout td.v").all_inner_texts()
    assert cells and all(re.fullmatch(r"-?\d+\.\d+|–", c) for c in cells), cells
    box = page.locator("svg.machdyn-drawing").bounding_box()
    assert box["width"] > 600 and box["height"] > 250  # not collapsed
    tab.shot(f"draw_{name}")


def test_user_names_are_text_never_markup(tab, tmp_path):
    evil = "<script>alert(1)</script>"
    lk = watt_with_slider(names={"3": evil, "C": "<b>C</b>", "4": "a&b"})
    path = tmp_path / "evil.html"
    page_text = to_html(lk, path, n=12)
    assert evil not in page_text and "<b>C</b>" not in page_text
    page = tab.open(path)
    tab.assert_clean(path)  # no alert() dialog ran
    titles = page.locator("svg title").all_text_contents()
    assert evil in titles and "a&b" in titles  # shown as the names they are
    labels = page.locator("svg g.labels text").all_text_contents()
    assert "<b>C</b>" in labels
    rows = page.locator("table.readout td:first-child").all_text_contents()
    assert f"θ {evil}" in rows


# --------------------------------------------------------------------------------------
# the design report, as a person sees it


def test_the_report_renders_and_plays(tab, tmp_path):
    from machdyn.report import report

    fb = FourBar(8, 4, 7, 6, coupler=(5, np.radians(30)))
    path = tmp_path / "report.html"
    report(fb, path, omega2=10.0, mass=(1, 2, 1.5), inertia=(0.1, 0.5, 0.3), cg=(2, 3.5, 3), k=0.05)
    page = tab.open(path, wait_ms=500)
    tab.assert_clean(path)
    assert page.locator("#headline").inner_text().startswith("four-bar 8-4-7-6 (GCRR)")
    for section in (
        "model",
        "class",
        "toggles",
        "angles",
        "ma",
        "kinematics",
        "forces",
        "flywheel",
        "balancing",
        "selfcheck",
    ):
        assert page.locator(f"section#{section}").count() == 1, section
    assert page.locator("table.checks td.state").all_inner_texts() == ["pass"] * 12
    charts = page.locator("svg.chart")
    assert charts.count() >= 10
    for k in range(charts.count()):  # every chart is laid out with a real size
        box = charts.nth(k).bounding_box()
        assert box["width"] > 250 and box["height"] > 150
    # the drawing in the report plays
    first = page.evaluate(
        "document.querySelector('svg.machdyn-drawing').getAttribute('data-frame')"
    )
    page.wait_for_timeout(200)
    assert (
        page.evaluate("document.querySelector('svg.machdyn-drawing').getAttribute('data-frame')")
        != first
    )
    tab.shot("report_fourbar_hw6")


def test_the_report_prints_to_pdf(tmp_path):
    from machdyn.report import report

    pytest.importorskip("playwright.sync_api")
    path = tmp_path / "hw6.pdf"
    report(FourBar(8, 4, 7, 6), path, n=90)
    data = path.read_bytes()
    assert data.startswith(b"%PDF") and len(data) > 10_000
    assert (tmp_path / "hw6.html").exists()


def test_a_machine_report_of_several_parts_renders(tab, tmp_path):
    from machdyn.cli import main

    path = tmp_path / "slider_crank.html"
    examples = __import__("pathlib").Path(__file__).parent.parent / "docs" / "examples"
    assert main(["report", str(examples / "slider_crank.toml"), "-o", str(path)]) == 0
    page = tab.open(path, wait_ms=500)
    tab.assert_clean(path)
    assert page.locator("#headline").inner_text().startswith("Slider-cranks: 2 parts.")
    assert page.locator("section.l2 h2").all_inner_texts()[:2] == [
        "1. engine (slider crank)",
        "2. shaper (inverted slider crank)",
    ]
    assert page.locator("svg.machdyn-drawing").count() == 2  # each part drawn, each playing
    states = page.locator("table.checks td.state").all_inner_texts()
    assert len(states) == 11 + 7 and set(states) == {"pass"}  # no k: no flywheel check
    for k in range(page.locator("svg.chart").count()):
        box = page.locator("svg.chart").nth(k).bounding_box()
        assert box["width"] > 250 and box["height"] > 150
        labels = page.locator("svg.chart").nth(k).locator("text.axis-label").all_text_contents()
        assert len(labels) == 2 and all(re.search(r"\(.+\)$", t) for t in labels), labels
    tab.shot("report_machine_slider_cranks")


def test_the_linkage_report_shows_every_chart_with_units(tab, tmp_path):
    from machdyn.report import report
    from test_report import watt

    path = tmp_path / "watt.html"
    report(watt(), path, velocity=10.0, n=180, gravity=9.81, k=0.05)
    page = tab.open(path, wait_ms=500)
    tab.assert_clean(path)
    for section in ("model", "class", "angles", "kinematics", "forces", "flywheel", "shaking"):
        assert page.locator(f"section#{section}").count() == 1, section
    charts = page.locator("svg.chart")
    assert charts.count() >= 10
    for k in range(charts.count()):
        labels = charts.nth(k).locator("text.axis-label").all_text_contents()
        assert len(labels) == 2 and all(re.search(r"\(.+\)$", t) for t in labels), labels
    assert set(page.locator("table.checks td.state").all_inner_texts()) == {"pass"}
    tab.shot("report_linkage_watt")


def _polar_traces(page, section: str) -> tuple[dict, dict]:
    """Bounding boxes of the 'before' and 'after' traces of a section's shaking polar chart.

    A trace is a red (before) or green (after) line; an 'after' balanced to rounding
    is drawn as green dots (a line of no length shows nothing).
    """
    polar = page.locator(f"section#{section} svg.chart").first
    legend = polar.locator("text").all_text_contents()
    assert any(t.startswith("before balancing: max") for t in legend), legend
    assert any(t.startswith("after balancing: max") for t in legend), legend
    before = polar.locator('polyline[stroke="#d62728"]').bounding_box()
    line = polar.locator('polyline[stroke="#2ca02c"]')
    if line.count():
        return before, line.bounding_box()
    dots = [polar.locator('circle[fill="#2ca02c"]').nth(k).bounding_box() for k in range(3)]
    x0, y0 = min(d["x"] for d in dots), min(d["y"] for d in dots)
    x1 = max(d["x"] + d["width"] for d in dots)
    y1 = max(d["y"] + d["height"] for d in dots)
    return before, {"x": x0, "y": y0, "width": x1 - x0, "height": y1 - y0}


def test_the_slider_crank_report_shows_the_balanced_shaking_force(tab, tmp_path):
    from machdyn.report import report

    path = tmp_path / "engine.html"
    # zero offset, rod centre on AB: after the counterweight only the force along the
    # slide is left, so the 'after' trace is a horizontal line through the origin
    report(
        SliderCrank(2.0, 7.0),
        path,
        omega2=30.0,
        mass=(1.5, 2.0, 3.0),
        inertia=(0.2, 4.0),
        cg=(0.6, 2.5),
        k=0.05,
    )
    page = tab.open(path, wait_ms=300)
    tab.assert_clean(path)
    before, after = _polar_traces(page, "shaking")
    assert before["height"] > 50 and after["width"] > 50
    assert after["height"] < 8, after  # nothing across the slide (the stroke's width)
    table = page.locator("section#shaking table").inner_text()
    assert "crank counterweight m·R" in table and "reciprocating mass m_B" in table
    assert set(page.locator("table.checks td.state").all_inner_texts()) == {"pass"}
    tab.shot("report_slider_crank_balancing")
    page.locator("section#shaking").screenshot(
        path=screenshots() / "report_slider_crank_shaking.png"
    )


def test_the_linkage_report_shows_counterweights_before_and_after(tab, tmp_path):
    from machdyn.report import report
    from test_balancing_linkages import fourbar_linkage

    path = tmp_path / "fourbar_linkage.html"
    report(fourbar_linkage(), path, velocity=10.0, n=180)
    page = tab.open(path, wait_ms=300)
    tab.assert_clean(path)
    before, after = _polar_traces(page, "shaking")
    # Berkof–Lowen: the balanced four-bar's shaking force is a dot at the origin
    assert before["width"] > 50 and before["height"] > 50
    assert after["width"] < 8 and after["height"] < 8, after  # (a dot's size)
    origin = page.locator("section#shaking svg.chart").first.locator('circle[fill="#000"]')
    box = origin.bounding_box()
    assert abs(after["x"] - box["x"]) < 1 and abs(after["y"] - box["y"]) < 1
    table = page.locator("section#shaking table").inner_text()
    assert "complete force balance" in table and "counterweight on crank" in table
    assert "counterweight on rocker" in table
    checks = page.locator("table.checks td.state").all_inner_texts()
    names = page.locator("table.checks td:first-child").all_inner_texts()
    assert set(checks) == {"pass"}
    assert {"equilibrium of each link", "momentum by differences"} <= set(names), names
    tab.shot("report_linkage_fourbar_balancing")
    page.locator("section#shaking").screenshot(path=screenshots() / "report_linkage_shaking.png")
    page.locator("section#selfcheck").screenshot(path=screenshots() / "report_linkage_checks.png")
