"""The inverted slider-crank's design report with forces, looked at in headless Chromium.

Independent references: the numbers read off the rendered page against
``InvertedSliderCrank.dynamics`` called here; the self-check states shown.
Screenshots: ``tests/screenshots/`` (or ``$MACHDYN_SCREENSHOTS``).
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from browser import Page
from machdyn import InvertedSliderCrank
from machdyn.report import report
from machdyn.report.slidercrank import slidercrank_sweep

pytestmark = pytest.mark.slow

KW = dict(
    mass=(2.0, 0.5, 6.0),
    inertia=(0.01, 0.001, 0.2),
    cg=(0.05, 0.01j, 0.25 + 0.01j),
    gravity=9.81,
    load_torque4=-40.0,
    friction="coulomb",
    mu=0.1,
)


@pytest.fixture(scope="module")
def tab(browser):
    page = Page(browser)
    yield page
    page.close()


def test_the_inverted_slider_crank_report_shows_its_forces(tab, tmp_path):
    isc = InvertedSliderCrank(0.1, 0.3, 0.02)
    path = tmp_path / "shaper.html"
    report(isc, path, omega2=12.0, k=0.05, **KW)
    page = tab.open(path, wait_ms=500)
    tab.assert_clean(path)
    assert page.locator("#headline").inner_text().startswith("inverted slider-crank, crank 0.1")
    for section in ("model", "class", "kinematics", "forces", "flywheel", "shaking", "selfcheck"):
        assert page.locator(f"section#{section}").count() == 1, section
    # peak input torque and where it occurs, as the API gives it
    th = slidercrank_sweep(isc, 360)
    f = isc.dynamics(th, 12.0, **KW)
    j = int(np.nanargmax(f.T12))
    shown = page.locator('[data-key="T12_max"]').inner_text()
    assert float(re.match(r"\s*(-?[\d.]+)", shown).group(1)) == pytest.approx(f.T12[j], rel=5e-4)
    assert f"θ2 = {np.degrees(th[j]):.1f}°" in shown
    # four pin-force polars, the torque curve with its lobes, the shaking polar: all laid out
    forces = page.locator("section#forces svg.chart")
    assert forces.count() == 4
    titles = " ".join(forces.nth(k).text_content() for k in range(4))
    for name in ("F12", "F32", "F43", "F14"):
        assert name in titles, name
    assert page.locator("section#flywheel svg.chart").count() == 1
    assert page.locator("section#shaking svg.chart").count() >= 1
    charts = page.locator("svg.chart")
    for k in range(charts.count()):
        box = charts.nth(k).bounding_box()
        assert box["width"] > 250 and box["height"] > 150
        labels = charts.nth(k).locator("text.axis-label").all_text_contents()
        assert len(labels) == 2 and all(re.search(r"\(.+\)$", t) for t in labels), labels
    states = dict(
        zip(
            page.locator("table.checks td:first-child").all_inner_texts(),
            page.locator("table.checks td.state").all_inner_texts(),
            strict=True,
        )
    )
    assert set(states.values()) == {"pass"}, states
    for name in ("power balance", "equilibrium of each link", "momentum"):
        assert any(k.startswith(name) for k in states), (name, states)
    tab.shot("report_inverted_slidercrank_forces")
