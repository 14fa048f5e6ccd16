"""Reports of gear pairs, gear trains, planetary trains and rotors, looked at in Chromium.

What a person sees: no console error and nothing loaded but the file; every
section there; each drawing laid out and playing (its frame advances, and a
gear of the train turns at its shaft's speed on screen); the polar plots of
the unbalance with a real size and axis labels with units; every self-check
passing; names typed by the user shown as text. Screenshots:
``tests/screenshots/`` (or ``$MACHDYN_SCREENSHOTS``).
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from browser import Page
from machdyn.cli import main

pytestmark = pytest.mark.slow
EXAMPLES = Path(__file__).parent.parent / "docs" / "examples"


@pytest.fixture
def tab(browser):
    page = Page(browser)
    yield page
    page.close()


def frame(page, k: int) -> str:
    return page.evaluate(
        f"document.querySelectorAll('svg.machdyn-drawing')[{k}].getAttribute('data-frame')"
    )


def test_the_gears_file_report_renders_and_plays(tab, tmp_path):
    path = tmp_path / "gears.html"
    assert main(["report", str(EXAMPLES / "gears.toml"), "-o", str(path), "--samples", "60"]) == 0
    page = tab.open(path, wait_ms=500)
    tab.assert_clean(path)
    assert page.locator("#headline").inner_text().startswith("Gears: 3 parts.")
    assert page.locator("section.l2 h2").all_inner_texts() == [
        "1. exam (gear pair)",
        "2. box (gear train)",
        "3. epicyclic (planetary)",
    ]
    for key in ("mesh", "interference", "loads", "stages", "shafts", "tabular", "torques"):
        assert page.locator(f"section[id$='-{key}']").count() == 1, key
    drawings = page.locator("svg.machdyn-drawing")
    assert drawings.count() == 3
    mesh = page.locator("section[id$='-model'] svg.chart")  # the line of action, close up
    assert mesh.count() == 1 and mesh.bounding_box()["width"] > 400
    for k in range(3):  # laid out, and playing
        box = drawings.nth(k).bounding_box()
        assert box["width"] > 400 and box["height"] > 250
        first = frame(page, k)
        page.wait_for_function(  # polled: a busy machine may draw a frame late
            "([k, f]) => document.querySelectorAll('svg.machdyn-drawing')[k]"
            ".getAttribute('data-frame') !== f",
            arg=[k, first],
            timeout=10_000,
        )
    # the train's wheels on screen: the output (60 T) and the input (18 T) circles
    wheels = page.locator("svg.machdyn-drawing").nth(1).locator("[id$='-wheel_3a']")
    assert wheels.count() == 1 and wheels.bounding_box()["width"] > 100
    states = page.locator("table.checks td.state").all_inner_texts()
    assert len(states) == 3 + 4 + 4 and set(states) == {"pass"}, states
    text = page.locator("body").inner_text()
    assert "ring -350 rpm" in text and "200 rpm" in text
    tab.shot("report_gears_file")


def test_the_rotor_report_renders_its_polar_plots(tab, tmp_path):
    path = tmp_path / "rotor.html"
    assert main(["report", str(EXAMPLES / "rotor.toml"), "-o", str(path)]) == 0
    page = tab.open(path, wait_ms=300)
    tab.assert_clean(path)
    assert page.locator("#headline").inner_text().startswith("shaft (rotor): two-plane")
    for section in ("masses", "balance", "bearings", "selfcheck"):
        assert page.locator(f"section#{section}").count() == 1, section
    charts = page.locator("svg.chart")
    assert charts.count() == 3  # the side view, the unbalance and the moment polar plots
    for k in range(3):
        box = charts.nth(k).bounding_box()
        assert box["width"] > 250 and box["height"] > 200
        labels = charts.nth(k).locator("text.axis-label").all_text_contents()
        assert all(re.search(r"\((kg·)?mm²?\)$", t) for t in labels), labels
    # both polar plots side by side
    assert charts.nth(1).bounding_box()["y"] == charts.nth(2).bounding_box()["y"]
    assert page.locator("table.checks td.state").all_inner_texts() == ["pass"] * 4
    tab.shot("report_rotor_file")


def test_a_planetary_with_odd_names_renders_them_as_text(tab, tmp_path):
    from machdyn.gears import PlanetaryTrain
    from machdyn.report import report

    train = PlanetaryTrain(
        [("<b>sun</b>", 30), ("p&1", 20, "external"), ("p2", 25, "shaft"), ("ring", 75, "internal")]
    )
    path = tmp_path / "planetary.html"
    report(train, path, speeds={"ring": 0.0, "arm": 10.0}, torque={"arm": 2.0})
    page = tab.open(path, wait_ms=300)
    tab.assert_clean(path)
    assert page.locator("b", has_text="sun").count() == 0  # never markup
    assert "<b>sun</b>" in page.locator("body").inner_text()
    assert page.locator("table.checks td.state").all_inner_texts() == ["pass"] * 4
    tab.shot("report_planetary_compound")
