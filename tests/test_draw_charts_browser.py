"""Report charts looked at in headless Chromium: titles inside, notes apart, honest legends.

What is asserted is what Chromium lays out (bounding boxes of the rendered SVG
text), not the SVG source. Screenshots: ``tests/screenshots/`` (or
``$MACHDYN_SCREENSHOTS``).
"""

from __future__ import annotations

import numpy as np
import pytest

from browser import Page, screenshots
from machdyn import FourBar, InvertedSliderCrank, SliderCrank
from machdyn.draw.engineering import shaking_charts, torque_chart
from machdyn.flywheel import size_flywheel
from machdyn.report import report

pytestmark = pytest.mark.slow

ISC = dict(
    mass=(2.0, 0.5, 6.0),
    inertia=(0.01, 0.001, 0.2),
    cg=(0.05, 0.01j, 0.25 + 0.01j),
    gravity=9.81,
    load_torque4=-40.0,
    friction="coulomb",
    mu=0.1,
)


@pytest.fixture
def tab(browser):
    page = Page(browser, width=1100)
    yield page
    page.close()


def inside(inner: dict, outer: dict, tol: float = 0.5) -> bool:
    return (
        inner["x"] >= outer["x"] - tol
        and inner["y"] >= outer["y"] - tol
        and inner["x"] + inner["width"] <= outer["x"] + outer["width"] + tol
        and inner["y"] + inner["height"] <= outer["y"] + outer["height"] + tol
    )


def intersect(a: dict, b: dict) -> bool:
    return (
        a["x"] < b["x"] + b["width"]
        and b["x"] < a["x"] + a["width"]
        and a["y"] < b["y"] + b["height"]
        and b["y"] < a["y"] + a["height"]
    )


def html_of(svgs: str, path) -> None:
    path.write_text(f"<!doctype html><meta charset=utf-8><body>{svgs}</body>", encoding="utf-8")


@pytest.mark.parametrize(
    "name, model, kw",
    [
        (
            "slidercrank",
            SliderCrank(2.0, 6.0, 0.5),
            dict(
                mass=(1.0, 2.0, 0.5),
                inertia=(0.1, 0.6),
                cg=(1.0, 3.0 + 0.2j),
                load_force4=-20.0,
            ),
        ),
        ("inverted_slidercrank", InvertedSliderCrank(0.1, 0.3, 0.02), ISC),
        (
            "fourbar",
            FourBar(8, 4, 7, 6),
            dict(mass=(1, 2, 1.5), inertia=(0.1, 0.5, 0.3), cg=(2, 3.5, 3)),
        ),
    ],
)
def test_every_chart_title_lies_inside_its_chart(tab, tmp_path, name, model, kw):
    path = tmp_path / f"{name}.html"
    report(model, path, omega2=12.0, k=0.05, **kw)
    page = tab.open(path, wait_ms=300)
    tab.assert_clean(path)
    charts = page.locator("svg.chart")
    assert charts.count() >= 4
    polars = 0
    for k in range(charts.count()):
        svg = charts.nth(k)
        title = svg.locator("text.title")
        assert title.count() == 1
        box, outer = title.bounding_box(), svg.bounding_box()
        assert inside(box, outer), (name, title.text_content(), box, outer)
        # the plot frame starts below the title: no line of the title over the plot
        frame = svg.locator("rect").first.bounding_box()
        assert box["y"] + box["height"] <= frame["y"] + 1, title.text_content()
        polars += "max |F|" in title.text_content()
    assert polars >= 3, name
    page.locator("section#forces").screenshot(path=str(screenshots() / f"charts_{name}_pins.png"))


def test_small_flywheel_lobe_labels_never_overlap(tab, tmp_path):
    # T - T_avg = sin θ + 0.05 sin 40θ: two big lobes and, near each crossing of
    # sin θ, narrow lobes whose labels would sit on each other and on the big ones'
    th = np.radians(np.arange(0.0, 360.0, 0.25))
    T = 20.0 + np.sin(th) + 0.05 * np.sin(40 * th)
    fly = size_flywheel(th, T, 50.0, 0.05)
    assert len(fly.lobes.area) >= 4  # the small lobes exist (and stay in the lobe table)
    chart = torque_chart(th, T, flywheel=fly, unit="N·m")
    path = tmp_path / "lobes.html"
    html_of(chart.to_svg(), path)
    page = tab.open(path)
    tab.assert_clean(path)
    labels = page.locator("svg.chart text:not(.title)", has_text="ΔE =")
    boxes = [labels.nth(k).bounding_box() for k in range(labels.count())]
    texts = labels.all_text_contents()
    assert 2 <= len(boxes) < len(fly.lobes.area)  # some left out, the big ones shown
    biggest = sorted(np.abs(fly.lobes.area))[-2:]
    for area in biggest:
        assert any(t.startswith(f"ΔE = {area:.4g}") or f"{area:.4g}" in t for t in texts), texts
    for i in range(len(boxes)):
        for j in range(i):
            assert not intersect(boxes[i], boxes[j]), (texts[i], texts[j])
    page.screenshot(path=str(screenshots() / "charts_small_lobes.png"))


def legend_texts(page) -> list[str]:
    # legend entries are the texts right of the plot frame
    frame = page.locator("svg.chart rect").first.bounding_box()
    out = []
    texts = page.locator("svg.chart").first.locator("text")
    for k in range(texts.count()):
        b = texts.nth(k).bounding_box()
        if b and b["x"] > frame["x"] + frame["width"]:
            out.append(texts.nth(k).text_content())
    return out


def test_shaking_legend_says_before_after_only_with_an_after(tab, tmp_path):
    th = np.radians(np.arange(0.0, 360.0, 5.0))
    before = 3 * np.exp(1j * th)
    path = tmp_path / "shaking.html"
    html_of(shaking_charts(before, theta=th, force_unit="N")[0].to_svg(380, 380), path)
    page = tab.open(path)
    alone = legend_texts(page)
    page.screenshot(path=str(screenshots() / "charts_shaking_unbalanced.png"))
    assert alone and not any("before" in t or "after" in t for t in alone), alone
    html_of(shaking_charts(before, 0.1 * before, force_unit="N")[0].to_svg(380, 380), path)
    page = tab.open(path)
    both = legend_texts(page)
    page.screenshot(path=str(screenshots() / "charts_shaking_balanced.png"))
    assert any(t.startswith("before balancing") for t in both), both
    assert any(t.startswith("after balancing") for t in both), both
    # and the inverted slider-crank report, which has no balancing, says so nowhere
    path = tmp_path / "isc.html"
    report(InvertedSliderCrank(0.1, 0.3, 0.02), path, omega2=12.0, k=0.05, **ISC)
    page = tab.open(path)
    shaking = page.locator("section#shaking")
    assert "before balancing" not in shaking.inner_text()
    assert "before balancing" not in " ".join(
        shaking.locator("svg.chart").nth(k).text_content()
        for k in range(shaking.locator("svg.chart").count())
    )


def test_gear_mesh_point_names_never_overlap(tab, tmp_path):
    from machdyn.draw.elements import gear_scene
    from machdyn.draw.html import to_html
    from machdyn.gears import Gear, GearPair

    # a fine pitch: the first contact point sits just below the pitch point
    pair = GearPair(Gear(18, diametral_pitch=24), Gear(40, diametral_pitch=24))
    path = tmp_path / "mesh.html"
    to_html(gear_scene(pair, n=24), path)
    page = tab.open(path, wait_ms=400)
    tab.assert_clean(path)
    labels = page.locator("g.labels text[data-point]")
    texts = labels.all_text_contents()
    assert {"pitch", "first"} <= set(texts), texts
    for _ in range(2):  # the frame first drawn, and one the player moved to
        boxes = [labels.nth(k).bounding_box() for k in range(labels.count())]
        for i in range(len(boxes)):
            for j in range(i):
                assert not intersect(boxes[i], boxes[j]), (texts[i], texts[j])
        page.wait_for_timeout(300)
    page.locator("svg.machdyn-drawing").screenshot(path=str(screenshots() / "charts_gear_mesh.png"))
