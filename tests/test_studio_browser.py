"""The studio in a real browser (Chromium via Playwright), used as a person uses it:
templates, dragging joints, building a six-bar with a slider by clicking, undo/redo,
saving and reloading, a shared link, three-position synthesis, an unassemblable drag.

What the page shows is checked against the library computed another way (FourBar's closed
form for the coupler curve, ``three_position`` for the synthesis, the spec reader for the
saved file). One server and one browser for the module; screenshots in tests/screenshots/.
"""

from __future__ import annotations

import cmath
import time

import numpy as np
import pytest

import machdyn
from browser import Page, screenshots
from machdyn.fourbar import FourBar
from machdyn.studio.templates import TEMPLATES
from machdyn.studio.templates import template as studio_template
from machdyn.synthesis import three_position

pytestmark = pytest.mark.slow


@pytest.fixture
def page(browser, studio):
    p = Page(browser, width=1400, height=860)
    p.page.goto(studio.url)
    wait(p, 1)
    yield p
    p.close()


def js(p, expr):
    return p.page.evaluate(expr)


def analysed(p) -> int:
    return int(js(p, "() => Number(document.body.dataset.analysed || 0)"))


def wait(p, count, timeout=30.0):
    """Until the page has drawn ``count`` answers of the server (or more)."""
    end = time.monotonic() + timeout
    while analysed(p) < count:
        if time.monotonic() > end:
            raise AssertionError(f"the page drew {analysed(p)} answers, expected {count}")
        p.page.wait_for_timeout(40)
    p.page.wait_for_timeout(60)


def settle(p, before, timeout=30.0):
    """Until an answer newer than ``before`` is drawn and no request is in flight."""
    wait(p, before + 1, timeout)
    end = time.monotonic() + timeout
    while js(p, "() => window.studio.analyst.busy || !!window.studio.analyst.waiting"):
        if time.monotonic() > end:
            raise AssertionError("the analysis never settled")
        p.page.wait_for_timeout(40)
    p.page.wait_for_timeout(80)


def screen(p, x, y):
    """Page coordinates of the drawing point (x, y)."""
    box = p.page.locator("#canvas").bounding_box()
    sx, sy = js(p, f"() => [window.studio.view.sx({x}), window.studio.view.sy({y})]")
    return box["x"] + sx, box["y"] + sy


def place(p, scale, tx, ty):
    """Set the view: ``scale`` pixels per unit, the origin at (tx, ty) on the canvas."""
    js(p, f"() => {{ const v = window.studio.view; v.scale = {scale}; v.tx = {tx}; v.ty = {ty}; }}")
    js(p, "() => window.studio.draw()")


def doc(p):
    return js(p, "() => window.studio.store.doc")


def part(p):
    d = doc(p)
    return next(iter(d["linkage"].values()))


def click(p, x, y):
    p.page.mouse.click(*screen(p, x, y))
    p.page.wait_for_timeout(60)


def template(p, name):
    before = analysed(p)
    p.page.select_option("#template", name)
    settle(p, before)


def no_errors(p, allowed=()):
    errs = [e for e in p.errors if not any(a in e for a in allowed)]
    assert not errs, errs


def traced(p, name):
    """The drawn trace of point ``name``: the page's data and the path on the screen."""
    return js(
        p,
        f"""() => {{
        const v = window.studio.view, s = v.scene, j = s.names.indexOf({name!r});
        const d = document.querySelector('#canvas path.trace').getAttribute('d');
        return {{x: s.x[j], y: s.y[j], d, tx: v.tx, ty: v.ty, scale: v.scale,
                 theta: window.studio.result.x}};
    }}""",
    )


def placed_fourbar(points):
    """FourBar of a placed four-bar O2-A-B-O4 with coupler point P, its O2, θ1 and form."""
    O2, O4, A, B, P = (complex(*points[k]) for k in ("O2", "O4", "A", "B", "P"))
    theta1 = cmath.phase(O4 - O2)
    fb = FourBar(
        abs(O4 - O2),
        abs(A - O2),
        abs(B - A),
        abs(B - O4),
        coupler=(abs(P - A), cmath.phase((P - A) / (B - A))),
    )
    return fb, O2, theta1, 1 if cmath.phase((B - O4) / (B - A)) > 0 else 2


def fourbar_curve(points, theta_deg):
    """Coupler point P of a placed four-bar, by FourBar's closed form (not the page's solver)."""
    fb, O2, theta1, form = placed_fourbar(points)
    m = fb.solve(np.radians(theta_deg) - theta1, 1.0, form=form)
    return O2 + np.asarray(m.coupler) * cmath.exp(1j * theta1)


def test_four_bar_template_drag_a_pivot_and_the_coupler_curve_follows(page):
    p = page
    template(p, "four-bar")
    p.shot("studio-01-four-bar")
    before = analysed(p)
    x0, y0 = screen(p, 80, 0)  # O4
    x1, y1 = screen(p, 90, -5)
    p.page.mouse.move(x0, y0)
    p.page.mouse.down()
    for k in range(1, 9):
        p.page.mouse.move(x0 + (x1 - x0) * k / 8, y0 + (y1 - y0) * k / 8)
        p.page.wait_for_timeout(30)
    p.page.mouse.up()
    settle(p, before)
    p.shot("studio-02-dragged-pivot")
    pts = part(p)["points"]
    assert pts["O4"] == pytest.approx([90.0, -5.0])  # snapped to the grid
    t = traced(p, "P")
    ok = np.array([v is not None for v in t["x"]])
    got = np.array([v if v is not None else np.nan for v in t["x"]]) + 1j * np.array(
        [v if v is not None else np.nan for v in t["y"]]
    )
    want = fourbar_curve(pts, np.array(t["theta"], float))
    assert ok.all()
    assert np.nanmax(np.abs(got - want)) < 1e-5 * 100
    # ... and the path on the screen is that curve, to a tenth of a pixel
    d = t["d"].replace("M", " ").replace("L", " ").split()
    screen_pts = np.array(d, float).reshape(-1, 2)
    s = t["scale"]
    world = (screen_pts[:, 0] - t["tx"]) / s + 1j * (t["ty"] - screen_pts[:, 1]) / s
    assert np.max(np.min(np.abs(world[:, None] - want[None, :]), axis=1)) < 0.1 / t["scale"] + 1e-9
    no_errors(p)


def test_an_unassemblable_drag_is_reported(page):
    p = page
    template(p, "four-bar")
    before = analysed(p)
    x0, y0 = screen(p, 80, 0)
    x1, y1 = screen(p, 130, 0)
    p.page.mouse.move(x0, y0)
    p.page.mouse.down()
    p.page.mouse.move(x1, y1, steps=6)
    p.page.mouse.up()
    settle(p, before)
    p.shot("studio-03-unassemblable")
    banner = p.page.locator("#banner")
    assert banner.is_visible()
    text = banner.inner_text()
    assert "cannot be solved" in text and "cannot assemble" in text
    lk = machdyn.from_spec(doc(p))
    theta = np.radians(js(p, "() => window.studio.result.x"))
    m = lk.solve(theta)
    shown = js(p, "() => window.studio.result.motion_ok")
    assert shown == [bool(v) for v in m.ok] and not all(shown)
    p.page.click("button[data-tab=analysis]")
    problems = p.page.locator("ul.problems").inner_text()
    assert "cannot assemble" in problems
    p.shot("studio-04-problems-listed")
    no_errors(p)


def test_build_a_six_bar_with_a_slider_by_clicking_then_undo_and_redo(page):
    p = page
    p.page.select_option("#template", "blank")
    p.page.wait_for_timeout(200)
    p.page.click("button[data-tool=ground]")
    place(p, 3, 150, 520)
    click(p, 0, 0)
    click(p, 80, 0)
    p.page.click("button[data-tool=link]")
    for xy in [(0, 0), (0, 30)]:
        click(p, *xy)
    p.page.keyboard.press("Enter")
    for xy in [(0, 30), (50, 60)]:
        click(p, *xy)
    p.page.keyboard.press("Enter")
    for xy in [(50, 60), (80, 0)]:
        click(p, *xy)
    p.page.keyboard.press("Enter")
    for xy in [(50, 60), (140, 40)]:
        click(p, *xy)
    p.page.keyboard.press("Enter")
    before = analysed(p)
    p.page.click("button[data-tool=slider]")
    click(p, 140, 40)
    click(p, 170, 40)
    settle(p, before)
    p.shot("studio-05-six-bar-by-clicking")
    pt = part(p)
    assert pt["ground"] == ["O2", "O4"]  # named as the textbooks do (Norton: O2, O4)
    assert pt["points"]["O2"] == [0, 0] and pt["points"]["O4"] == [80, 0]
    assert len(pt["links"]) == 5 and next(iter(pt["sliders"].values()))["on"] == "ground"
    assert pt["drive"] == ["crank"]  # new links are named by their role, then numbered
    assert list(pt["links"]) == ["crank", "coupler", "rocker", "coupler2", "block1"]
    summary = js(p, "() => window.studio.result.summary")
    assert summary["mobility"] == 1
    assert [g["kind"] for g in summary["groups"]] == ["driver", "RRR", "RRP"]
    lk = machdyn.from_spec(doc(p))
    theta = np.radians(js(p, "() => window.studio.result.x"))
    m = lk.solve(theta)
    assert js(p, "() => window.studio.result.motion_ok") == [bool(v) for v in m.ok]
    # undo back to the four-bar (the slider: its block link and joint at once), then redo
    built = doc(p)
    before = analysed(p)
    p.page.keyboard.press("Control+z")
    settle(p, before)
    assert "sliders" not in part(p)
    before = analysed(p)
    p.page.keyboard.press("Control+y")
    settle(p, before)
    assert doc(p) == built
    for _ in range(60):  # more than 50 steps back
        p.page.keyboard.press("Control+z")
    p.page.wait_for_timeout(300)
    assert js(p, "() => window.studio.store.past.length") == 0
    for _ in range(60):
        p.page.keyboard.press("Control+y")
    p.page.wait_for_timeout(500)
    assert doc(p) == built
    no_errors(p)


def test_save_reload_and_a_shared_link_reproduce_the_design(page, studio, browser):
    p = page
    template(p, "watt")
    before = analysed(p)
    p.page.click("button[data-tab=design]")
    p.page.mouse.click(*screen(p, 120, 60))  # select O6
    p.page.fill("input[aria-label=x]", "125")
    p.page.keyboard.press("Enter")
    settle(p, before)
    designed = doc(p)
    p.page.click("#save")
    p.page.wait_for_timeout(400)
    assert "saved design.toml" in p.page.locator("#status").inner_text()
    assert machdyn.spec.load_machine(studio.file).to_spec() == designed
    # reload without the link: the saved file is opened
    q = Page(browser, width=1400, height=860)
    q.page.goto(studio.url)
    wait(q, 1)
    assert doc(q) == designed
    q.close()
    # the shared link alone reproduces it
    p.page.click("#share")
    p.page.wait_for_timeout(500)
    link = js(p, "() => location.href")
    assert "#d=" in link
    r = Page(browser, width=1400, height=860)
    r.page.goto(link)
    wait(r, 1)
    assert doc(r) == designed
    r.shot("studio-06-shared-link")
    no_errors(r)
    r.close()


def test_three_position_synthesis_on_the_canvas(page):
    p = page
    c = [0 + 5.086j, 2.019 + 3.181j, 3.933 + 4.051j]  # the notes' three-position table
    d = [0.741 + 2.703j, 4.428 + 2.529j, 6.304 + 4.83j]
    scale = 10.0  # drawn in mm, ten times the notes' numbers
    p.page.click("button[data-tab=synthesis]")
    p.page.uncheck("#snap")
    place(p, 6, 300, 600)
    p.page.click("text=Pick positions")
    for k in range(3):
        click(p, scale * c[k].real, scale * c[k].imag)
        click(p, scale * d[k].real, scale * d[k].imag)
    p.page.click("#run-motion")
    p.page.wait_for_selector("td[data-key=lengths]")
    p.shot("studio-07-three-position")
    picked = js(p, "() => window.studio.synth.motion.pts")
    cc = [complex(*picked[k]) for k in (0, 2, 4)]
    dd = [complex(*picked[k]) for k in (1, 3, 5)]
    ref = three_position(cc, dd)
    shown = [float(v) for v in p.page.locator("td[data-key=lengths]").inner_text().split(",")]
    assert shown == pytest.approx([ref.r1, ref.r2, ref.r3, ref.r4], rel=1e-3)
    assert ref.r2 == pytest.approx(scale * 2.197, rel=2e-3)  # the notes' link 2
    defects = p.page.locator("#tab-synthesis .result").inner_text()
    assert ("No circuit" in defects) == (not ref.defects)
    before = analysed(p)
    p.page.click("#open-motion")
    settle(p, before)
    p.shot("studio-08-synthesised-linkage")
    assert js(p, "() => window.studio.result.summary.mobility") == 1
    no_errors(p)


def test_a_bad_value_shows_the_key_and_the_reason_in_the_page(page):
    p = page
    template(p, "four-bar")
    p.page.click("button[data-tab=design]")
    p.page.mouse.click(*screen(p, 10, 17.32))  # the crank, half-way along
    p.page.fill("input[aria-label=cg]", "O9")
    p.page.keyboard.press("Enter")
    p.page.wait_for_timeout(800)
    status = p.page.locator("#status").inner_text()
    assert "cg" in status and "O9" in status
    p.page.click("button[data-tab=analysis]")
    card = p.page.locator("#tab-analysis .card.error").inner_text()
    assert "links.crank" in card and "cg" in card and "O9" in card
    p.shot("studio-09-bad-value")
    no_errors(p)
    assert screenshots().is_dir()


def test_switch_the_circuit_and_show_the_instant_centres(page):
    p = page
    template(p, "four-bar")
    B = complex(*part(p)["points"]["B"])
    p.page.click("button[data-tab=analysis]")
    assert "GCRR" in p.page.locator("td[data-key=class]").inner_text()
    before = analysed(p)
    p.page.click("#tab-analysis button:has-text('switch')")
    settle(p, before)
    pts = {k: complex(*v) for k, v in part(p)["points"].items()}
    u = (pts["O4"] - pts["A"]) / abs(pts["O4"] - pts["A"])
    assert abs(pts["B"] - (pts["A"] + u * ((B - pts["A"]) / u).conjugate())) < 1e-6
    before = analysed(p)
    p.page.check("#centres")
    settle(p, before)
    p.shot("studio-10-switched-with-centres")
    centres = js(p, "() => window.studio.view.centres.centres")
    assert len(centres) == 6  # n (n - 1) / 2 centres of four bodies
    labels = p.page.locator("#canvas .centres text").all_text_contents()
    assert {"ground·crank", "crank·coupler", "coupler·rocker", "ground·rocker"} <= set(labels)
    # I13 (ground, coupler) is where O2A and O4B meet, by hand
    k = js(p, "() => window.studio.frame")
    assert k == js(p, "() => window.studio.result.drawn")  # the pose drawn is the document's
    O2, A, O4, B2 = pts["O2"], pts["A"], pts["O4"], pts["B"]
    v, w = A - O2, B2 - O4
    t = ((O4 - O2) * w.conjugate()).imag / (v * w.conjugate()).imag
    ic = js(
        p, "() => window.studio.view.centres.centres.find(c => c.pair.join() === 'ground,coupler')"
    )
    assert abs(complex(ic["x"][k], ic["y"][k]) - (O2 + t * v)) < 1e-3
    no_errors(p)


def test_path_synthesis_from_clicked_points(page):
    p = page
    template(p, "four-bar")
    p.page.click("button[data-tab=synthesis]")
    p.page.uncheck("#snap")
    curve = js(p, "() => { const s = window.studio.view.scene, j = s.names.indexOf('P');"
               " return s.x[j].map((x, i) => [x, s.y[j][i]]); }")  # fmt: skip
    p.page.click("#pick-path")
    for x, y in curve[::45]:  # eight points on the template's own coupler curve
        click(p, x, y)
    p.page.click("#pick-path")
    p.page.click("#run-path")
    p.page.wait_for_selector("table.candidates", timeout=120_000)
    p.shot("studio-11-path-synthesis")
    found = js(p, "() => window.studio.synth.path.result.candidates")
    assert found and found[0]["max_distance"] < 0.05 * 100  # within 5 % of the path's size
    targets = np.array([complex(x, y) for x, y in curve[::45]])
    cand = found[0]
    line = np.array([complex(*q) for q in cand["curve"] if q is not None])
    gap = np.abs(targets[:, None] - line[None, :]).min(axis=1).max()
    assert gap <= cand["max_distance"] + 0.02 * 100  # its curve passes near every target
    no_errors(p)


def test_a_coupler_point_added_to_a_link_traces_the_closed_form_curve(page):
    p = page
    template(p, "four-bar")
    p.page.click("button[data-tab=design]")
    corners = [part(p)["points"][k] for k in ("A", "B", "P")]
    p.page.mouse.click(*screen(p, *np.mean(corners, axis=0)))  # the coupler plate's centroid
    assert p.page.locator("h3 input.name").input_value() == "coupler"
    p.page.click("#add-point")
    before = analysed(p)
    click(p, 60, 30)
    settle(p, before)
    pt = part(p)
    new = next(n for n in pt["links"]["coupler"]["points"] if n not in ("A", "B", "P"))
    assert new in pt["report"]
    t = traced(p, new)
    pts = {k: v for k, v in pt["points"].items() if k in ("O2", "O4", "A", "B")}
    pts["P"] = pt["points"][new]
    got = np.array(t["x"], float) + 1j * np.array(t["y"], float)
    assert np.max(np.abs(got - fourbar_curve(pts, np.array(t["theta"], float)))) < 1e-3
    p.shot("studio-12-coupler-point-added")
    no_errors(p)


def test_names_are_text_files_open_and_exports_download(page, tmp_path):
    p = page
    template(p, "slider-crank")
    p.page.click("button[data-tab=design]")
    p.page.mouse.click(*screen(p, *js(p, "() => window.studio.view.pointAt('A')")))
    evil = '<img src=x onerror="alert(1)">'
    before = analysed(p)
    p.page.fill("h3 input.name", evil)
    p.page.keyboard.press("Enter")
    settle(p, before)
    assert evil in part(p)["points"]
    labels = p.page.locator("#canvas text.label").all_text_contents()
    assert evil in labels  # shown as text ...
    assert p.page.locator("#canvas img, #side img").count() == 0  # ... never as markup
    assert not p.dialogs
    # open a machine file through the file picker (the same path as a drop)
    f = tmp_path / "watt.toml"
    f.write_text(machdyn.spec.dumps(studio_template("watt")))
    before = analysed(p)
    p.page.set_input_files("#open-file", str(f))
    settle(p, before)
    assert next(iter(doc(p)["linkage"])) == "watt"
    # ... and by dropping it on the page
    text = f.read_text()
    before = analysed(p)
    p.page.evaluate(
        "(t) => { const dt = new DataTransfer(); dt.items.add(new File([t], 'dropped.toml'));"
        " window.dispatchEvent(new DragEvent('drop', {dataTransfer: dt, cancelable: true})); }",
        text.replace("Watt II six-bar", "dropped"),
    )
    settle(p, before)
    assert doc(p)["title"] == "dropped"
    with p.page.expect_download() as info:
        p.page.select_option("#export", "csv")
    path = info.value.path()
    with open(path, encoding="utf-8") as f:
        header = f.readline().strip().split(",")
    assert header[0] == "theta_crank [deg]" and "T_crank [N*m]" in header
    p.shot("studio-13-opened-and-exported")
    no_errors(p)


def positions(r, name):
    """Point ``name`` in every frame of the page's scene, as complex numbers (NaN: not shown)."""
    s = r["scene"]
    j = s["names"].index(name)
    x, y = s["x"][j], s["y"][j]
    n = s["frames"]
    x = [x] * n if not isinstance(x, list) else x
    y = [y] * n if not isinstance(y, list) else y
    return np.array([complex(a, b) if a is not None else np.nan for a, b in zip(x, y, strict=True)])


def scene(p):
    return js(p, "() => ({...window.studio.result, columns: {}})")


def guide_line(pt, slider, r):
    """Per frame, a point of the slider's guide and its direction, moved with the guide's link.

    Read from the drawn document alone: the line through ``through`` (or ``at``) along
    ``direction`` (an angle in degrees, a vector, or towards a point), carried by the rigid
    motion of link ``on`` (two of its points), or fixed when ``on`` is the ground.
    """
    pts = {k: complex(*v) for k, v in pt["points"].items()}
    q0 = pts[slider.get("through") or slider["at"]]
    d = slider["direction"]
    u0 = (
        pts[d] - q0
        if isinstance(d, str)
        else complex(*d)
        if isinstance(d, list)
        else cmath.exp(1j * np.radians(d))
    )
    if slider["on"] == "ground":
        return np.full(r["scene"]["frames"], q0), np.full(r["scene"]["frames"], u0)
    a, b = pt["links"][slider["on"]]["points"][:2]
    ak, bk = positions(r, a), positions(r, b)
    turn = (bk - ak) / (pts[b] - pts[a])
    turn /= np.abs(turn)
    return ak + turn * (q0 - pts[a]), turn * u0


def assert_rigid_and_on_guides(pt, r):
    """Every link keeps its drawn side lengths and every block stays on its guide, each frame."""
    tol = 3 * 10.0 ** -r["scene"]["decimals"]
    pts = {k: complex(*v) for k, v in pt["points"].items()}
    for name, link in pt["links"].items():
        for i, a in enumerate(link["points"]):
            for b in link["points"][i + 1 :]:
                d = np.abs(positions(r, a) - positions(r, b))
                assert np.max(np.abs(d - abs(pts[a] - pts[b]))) < tol, (name, a, b)
    for name, slider in (pt.get("sliders") or {}).items():
        q, u = guide_line(pt, slider, r)
        off = ((positions(r, slider["at"]) - q) * np.conj(u)).imag / np.abs(u)
        assert np.max(np.abs(off)) < tol, name


def test_every_template_opens_assembled_rigid_and_on_its_guides(page):
    p = page
    for k, name in enumerate(TEMPLATES):
        template(p, name)
        r = scene(p)
        assert not p.page.locator("#banner").is_visible(), name
        assert r["summary"]["mobility"] == 1 and all(r["ok"]), name
        pt = part(p)
        assert_rigid_and_on_guides(pt, r)  # loop closure, checked on the page's numbers
        drawn = p.page.locator("#canvas .world .item.bar, #canvas .world .item.plate").count()
        assert drawn >= sum(len(link["points"]) >= 2 for link in pt["links"].values()), name
        p.shot(f"studio-14-template-{k}-{name}")
    no_errors(p)


def test_a_ternary_plate_and_a_slider_on_a_moving_link_by_clicking(page):
    """A crank-shaper built by clicking: crank, slotted ternary arm, rod, ram on the ground."""
    p = page
    p.page.select_option("#template", "blank")
    p.page.wait_for_timeout(200)
    place(p, 2.5, 300, 560)
    p.page.click("button[data-tool=ground]")
    click(p, 0, 0)
    click(p, 0, -60)
    p.page.click("button[data-tool=link]")
    for chain in [[(0, 0), (20, 0)], [(0, -60), (60, 40), (0, 60)], [(60, 40), (120, 40)]]:
        for xy in chain:
            click(p, *xy)
        p.page.keyboard.press("Enter")
    p.page.click("button[data-tool=slider]")
    click(p, 20, 0)  # the crank pin slides ...
    click(p, 30, 30)  # ... along the arm, towards its pivot (a click on the arm's plate)
    before = analysed(p)
    p.page.click("button[data-tool=slider]")
    click(p, 120, 40)  # the ram slides on the ground
    click(p, 150, 40)
    settle(p, before)
    p.shot("studio-15-shaper-by-clicking")
    pt = part(p)
    assert {s["on"] for s in pt["sliders"].values()} == {"ground", "rocker"}
    assert len(pt["links"]["rocker"]["points"]) == 3
    r = scene(p)
    assert r["summary"]["mobility"] == 1
    assert [g["kind"] for g in r["summary"]["groups"]] == ["driver", "RPR", "RRP"]
    assert all(r["ok"])
    assert_rigid_and_on_guides(pt, r)  # the pin stays in the moving slot, the ram on its guide
    # the slot passes through the arm's pivot: the arm turns as O4→A does, A by hand
    pts = {k: complex(*v) for k, v in pt["points"].items()}
    o2, o4 = (next(n for n in pt["ground"] if pts[n] == z) for z in (0, -60j))
    pin = next(s["at"] for s in pt["sliders"].values() if s["on"] != "ground")
    x = np.radians(r["x"])
    a = pts[o2] + (pts[pin] - pts[o2]) * np.exp(1j * (x - x[r["drawn"]])) - pts[o4]
    c = positions(r, pt["links"]["rocker"]["points"][1]) - pts[o4]
    rounding = 3 * 10.0 ** -r["scene"]["decimals"] / np.abs(c).min()  # the page's decimals
    assert np.max(np.abs(np.angle((c / a) / (c / a)[r["drawn"]]))) < rounding
    p.page.click("button[data-tab=design]")
    p.page.click("#tab-design .lists a:text-is('rocker')")
    assert "ternary plate" in p.page.locator("#tab-design .selection").inner_text()
    no_errors(p)


def test_zoom_pan_snap_and_the_keyboard(page):
    p = page
    template(p, "four-bar")
    box = p.page.locator("#canvas").bounding_box()
    view = "() => { const v = window.studio.view; return [v.scale, v.tx, v.ty]; }"
    s0 = js(p, view)[0]
    px, py = 300.0, 200.0
    under = js(p, f"() => window.studio.view.toWorld({px}, {py})")
    p.page.mouse.move(box["x"] + px, box["y"] + py)
    p.page.mouse.wheel(0, -200)
    p.page.wait_for_timeout(200)
    s1, _, _ = js(p, view)
    assert s1 == pytest.approx(s0 * np.exp(0.3))  # zoomed in about the pointer ...
    # (the event's coordinates are whole pixels: the point under it stays within a pixel)
    assert js(p, f"() => window.studio.view.toWorld({px}, {py})") == pytest.approx(
        under, abs=1 / s0
    )
    p.page.mouse.move(box["x"] + 40, box["y"] + 40)  # ... panned by dragging empty space
    _, tx1, ty1 = js(p, view)
    p.page.mouse.down()
    p.page.mouse.move(box["x"] + 90, box["y"] + 70, steps=5)
    p.page.mouse.up()
    assert js(p, view)[1:] == pytest.approx([tx1 + 50, ty1 + 30])
    p.page.keyboard.press("f")
    assert js(p, view) != [s1, tx1 + 50, ty1 + 30]
    # tools from the keyboard, and a ground pivot snapped to half the grid step
    p.page.keyboard.press("g")
    assert p.page.get_attribute("button[data-tool=ground]", "aria-pressed") == "true"
    step = js(p, "() => window.studio.view.gridStep() / 2")
    click(p, 12.3 * step, 2.4 * step)
    new = next(v for k, v in part(p)["points"].items() if k not in ("O2", "O4", "A", "B", "P"))
    assert new == pytest.approx([12 * step, 2 * step])
    p.page.keyboard.press("Control+z")
    p.page.keyboard.press("s")
    assert p.page.get_attribute("button[data-tool=select]", "aria-pressed") == "true"
    # a joint picked from the list and moved with the arrow keys, analysed each time
    p.page.click("button[data-tab=design]")
    p.page.focus("#tab-design .lists a:text-is('O4')")
    p.page.keyboard.press("Enter")
    p.page.locator("#canvas").focus()
    for key in ["ArrowRight", "ArrowUp", "Alt+ArrowUp"]:  # a step right, 1.1 steps up
        before = analysed(p)
        p.page.keyboard.press(key)
        settle(p, before)
    step = js(p, "() => window.studio.view.gridStep() / 2")
    pts = part(p)["points"]
    assert pts["O4"] == pytest.approx([80 + step, 1.1 * step])
    t = traced(p, "P")
    got = np.array(t["x"], float) + 1j * np.array(t["y"], float)
    want = fourbar_curve(pts, np.array(t["theta"], float))
    assert (np.isfinite(got) == np.isfinite(want)).all()  # no longer Grashof: the same gaps
    assert np.nanmax(np.abs(got - want)) < 1e-3
    assert "mobility 1" in p.page.get_attribute("#canvas", "aria-label")
    p.shot("studio-16-keyboard")
    no_errors(p)


def test_speed_control_and_plots_of_the_listed_quantities(page):
    p = page
    template(p, "four-bar")
    # the animation runs at 90 frames a second times the speed picked
    for speed in ("1", "4"):
        p.page.select_option("#speed", speed)
        js(p, "() => { if (!window.studio.playing) window.studio.togglePlay(); }")
        p.page.wait_for_timeout(150)
        t0, f0 = js(p, "() => [performance.now(), window.studio.pos]")
        p.page.wait_for_timeout(600)
        t1, f1 = js(p, "() => [performance.now(), window.studio.pos]")
        js(p, "() => { if (window.studio.playing) window.studio.togglePlay(); }")
        rate = ((f1 - f0) % 360) / ((t1 - t0) / 1000)
        assert rate == pytest.approx(90 * float(speed), rel=0.25)
    p.page.click("button[data-tab=plots]")
    names = js(p, "() => window.studio.result.names")
    for kind in ("theta_", "omega_", "alpha_", "|VP|", "|AP|", "mu_", "F_crank_coupler", "T_crank"):
        assert any(n.startswith(kind) for n in names), kind
    assert len(names) == len(set(names))
    p.page.fill("#tab-plots input[type=search]", "|VP|")
    before = analysed(p)
    p.page.check("input[data-q='|VP| [mm/s]']")
    settle(p, before)
    assert p.page.locator("#tab-plots svg.chart path.series[data-q='|VP| [mm/s]']").count() == 1
    r = js(p, "() => window.studio.result")
    fb, _, theta1, form = placed_fourbar(part(p)["points"])
    m = fb.solve(np.radians(r["x"]) - theta1, 10.0, form=form)  # the template's 10 rad/s
    assert np.array(r["columns"]["|VP| [mm/s]"]) == pytest.approx(np.abs(m.coupler_velocity))
    # clicking on the chart moves the drawing to that input, and the legend reads its value
    chart = p.page.locator("#tab-plots svg.chart").first.bounding_box()
    p.page.mouse.click(chart["x"] + 0.5 * chart["width"], chart["y"] + 0.5 * chart["height"])
    k = js(p, "() => window.studio.frame")
    assert k != r["drawn"]
    shown = p.page.locator("#tab-plots b[data-value='|VP| [mm/s]']").inner_text()
    assert float(shown) == pytest.approx(abs(m.coupler_velocity[k]), rel=1e-4)
    p.shot("studio-17-plot-cursor")
    no_errors(p)


def test_a_path_drawn_with_the_mouse_becomes_target_points(page):
    p = page
    template(p, "four-bar")
    p.page.click("button[data-tab=synthesis]")
    p.page.uncheck("#snap")
    p.page.click("#pick-path")
    centre = screen(p, 40, 40)
    turn = np.linspace(0, 6, 61)  # radians: 600 px of stroke on a circle of 100 px
    ring = list(zip(centre[0] + 100 * np.cos(turn), centre[1] + 100 * np.sin(turn), strict=True))
    p.page.mouse.move(*ring[0])
    p.page.mouse.down()
    for xy in ring[1:]:
        p.page.mouse.move(*xy)
    p.page.mouse.up()
    p.page.click("#pick-path")
    pts = np.array([complex(*q) for q in js(p, "() => window.studio.synth.path.pts")])
    scale = js(p, "() => window.studio.view.scale")
    assert 20 <= pts.size <= 27  # a target every 24 px along 600 px of stroke
    assert np.abs(np.abs(pts - complex(40, 40)) - 100 / scale).max() < 0.02 * 100 / scale
    assert not p.page.locator("#run-path").is_disabled()
    p.shot("studio-18-path-drawn")
    no_errors(p)


def test_three_position_synthesis_with_fixed_pivots_picked_on_the_canvas(page):
    """HW 6's coupler point and pin B at θ2 = 20°, 70°, 130° with its own pivots O2, O4
    picked: the page must give HW 6 back (8-4-7-6 cm), within the pixel of each click."""
    from machdyn.synthesis import three_position_fixed_pivots

    p = page
    m = FourBar(80, 40, 70, 60, coupler=(50, np.radians(30))).solve(np.radians([20, 70, 130]))
    c, d = np.asarray(m.coupler), np.asarray(m.B)
    p.page.click("button[data-tab=synthesis]")
    p.page.uncheck("#snap")
    place(p, 5, 250, 600)
    p.page.click("text=Pick positions")
    for k in range(3):
        click(p, c[k].real, c[k].imag)
        click(p, d[k].real, d[k].imag)
    p.page.select_option("#tab-synthesis select[aria-label=pivots]", "fixed")
    click(p, 0, 0)
    click(p, 80, 0)
    p.page.click("#run-motion")
    p.page.wait_for_selector("td[data-key=lengths]")
    p.shot("studio-19-three-position-fixed-pivots")
    picked = [complex(*q) for q in js(p, "() => window.studio.synth.motion.pts")]
    O2, O4 = (complex(*q) for q in js(p, "() => window.studio.synth.motion.extra"))
    assert abs(O2) < 0.2 and abs(O4 - 80) < 0.2  # the clicks, within a pixel
    ref = three_position_fixed_pivots(picked[0::2], picked[1::2], O2, O4)
    shown = [float(v) for v in p.page.locator("td[data-key=lengths]").inner_text().split(",")]
    assert shown == pytest.approx([ref.r1, ref.r2, ref.r3, ref.r4], rel=1e-3)
    assert shown == pytest.approx([80, 40, 70, 60], rel=0.02)  # HW 6 back
    assert "No circuit, branch or order defect" in p.page.locator("#tab-synthesis").inner_text()
    no_errors(p)


def test_a_sliders_guide_is_edited_in_the_side_panel(page):
    p = page
    template(p, "slider-crank")
    p.page.click("button[data-tab=design]")
    p.page.click("#tab-design .lists a:text-is('cylinder')")
    before = analysed(p)
    p.page.fill("input[aria-label='guide direction']", "10")
    p.page.keyboard.press("Enter")
    settle(p, before)
    pt = part(p)
    assert pt["sliders"]["cylinder"]["direction"] == 10
    r = scene(p)
    assert all(r["ok"])
    assert_rigid_and_on_guides(pt, r)  # the piston now runs along 10°, by hand
    b = positions(r, "B")
    assert np.ptp(np.angle((b - b[0])[np.abs(b - b[0]) > 1]) % np.pi) < 3e-3  # (3 decimals)
    p.shot("studio-20-guide-edited")
    no_errors(p)


def test_mass_properties_edited_in_the_panel_drive_the_torque(page):
    # The rocker's mass, I_G and centre of mass typed in the side panel reach the document
    # and the input torque; the torque is checked against FourBar's closed-form dynamics
    # (machdyn.dynamics, not the Linkage force assembly the studio runs) with the same numbers.
    p = page
    template(p, "four-bar")
    p.page.click("button[data-tab=design]")
    p.page.click("#tab-design .lists a:text-is('rocker')")
    labels = p.page.locator("#tab-design label").all_inner_texts()
    assert any(t.startswith("mass (kg)") for t in labels), labels
    for label, value in (("mass", "0.9"), ("inertia", "400"), ("cg", "30, 5")):
        before = analysed(p)
        p.page.fill(f"input[aria-label='{label}']", value)
        p.page.keyboard.press("Enter")
        settle(p, before)
    rocker = part(p)["links"]["rocker"]
    assert (rocker["mass"], rocker["inertia"], rocker["cg"]) == (0.9, 400, [30, 5])
    p.page.click("button[data-tab=plots]")
    p.page.fill("#tab-plots input[type=search]", "T_crank")
    box = p.page.locator("input[data-q='T_crank [N*m]']")
    if not box.is_checked():  # the driver's torque is plotted by default when there are masses
        before = analysed(p)
        box.check()
        settle(p, before)
    r = js(p, "() => window.studio.result")
    pts = part(p)["points"]
    fb, _, theta1, form = placed_fourbar(pts)
    links = part(p)["links"]
    A, B, P = (complex(*pts[k]) for k in ("A", "B", "P"))
    f = fb.dynamics(
        np.radians(r["x"]) - theta1,
        10.0,  # the template's crank speed, rad/s
        form=form,
        mass=(links["crank"]["mass"], links["coupler"]["mass"], 0.9),
        inertia=(links["crank"]["inertia"], links["coupler"]["inertia"], 400.0),
        cg=(links["crank"]["cg"], (P - A) / (B - A) * abs(B - A), 30 + 5j),
        gravity=9806.65,  # standard gravity in mm/s² (the template's units: mm, kg)
    )
    torque = np.array(r["columns"]["T_crank [N*m]"], float)
    assert torque == pytest.approx(f.T12 * 1e-6, abs=1e-6)  # kg·mm²/s² → N·m, 7 digits shown
    p.page.click("button[data-tab=design]")
    p.page.click("#tab-design .lists a:text-is('rocker')")
    p.shot("studio-21-mass-properties")
    no_errors(p)
