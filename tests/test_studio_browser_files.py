"""The studio in Chromium with the files users bring: the ``[fourbar]`` file ``machdyn synth
path`` writes (with masses, loads and a table the studio cannot keep) and a hand-written
``[slider_crank]`` file, opened through the page's file picker.

What the page shows is checked against the library computed another way: the coupler
curve on the screen against ``FourBar``'s closed form placed in the plane by hand
(global = O2 + e^{jθ1}·local), the messages against the file's contents. Also: a plotted
quantity follows its link's new name (the same numbers), one that disappears (its
joint deleted) is named in a visible message, and link names are written on the
drawing. One browser page for the module; screenshots in tests/screenshots/.
"""

from __future__ import annotations

import cmath
import time
from pathlib import Path

import numpy as np
import pytest

from browser import Page
from machdyn.fourbar import FourBar
from test_studio_browser import analysed, js, settle, wait
from test_studio_convert import example, synth_file

pytestmark = pytest.mark.slow

O2, THETA1 = 20 - 10j, np.radians(40.0)


def open_file(p, path: Path) -> None:
    before = analysed(p)
    p.page.set_input_files("#open-file", str(path))
    settle(p, before)


@pytest.fixture(scope="module")
def page(browser, studio):
    p = Page(browser, width=1400, height=860)
    p.page.goto(studio.url)
    wait(p, 1)
    yield p
    p.close()


def test_a_synthesised_fourbar_file_opens_drawn_named_and_on_its_closed_form_path(page, tmp_path):
    p = page
    text = synth_file((80.0, 30.0, 70.0, 60.0), (50.0, np.radians(30.0)), O2, 40.0, -1)
    text += (
        "[fourbar.candidate.link3]\nmass = 0.8\ninertia = 0.0009\ncg = [30, 12]\n"
        "[fourbar.candidate.loads]\ntorque4 = -2\n"
        '[fourbar.candidate.simulate]\nmotor = { kind = "constant", torque = 1 }\nturns = 2\n'
    )
    f = tmp_path / "candidate.toml"
    f.write_text(text, encoding="utf-8")
    open_file(p, f)
    notice = p.page.locator("#notice")
    assert notice.is_visible()
    said = notice.inner_text()
    assert "Opened [fourbar.candidate] as a drawn linkage: crank O2–A, coupler A–B–P" in said
    assert "Not kept: [fourbar.candidate.simulate]" in said
    names = p.page.locator("#canvas text.link-name").all_text_contents()
    assert sorted(names) == ["coupler", "crank", "rocker"]
    assert p.page.locator("#tab-design .lists a:text-is('rocker')").is_visible()
    p.shot("studio-20-fourbar-file-opened")
    # the coupler curve the page draws is the file's four-bar, form 2, placed at O2, θ1
    r = js(p, "() => ({x: window.studio.result.x, scene: window.studio.view.scene})")
    j = r["scene"]["names"].index("P")
    shown = np.array(r["scene"]["x"][j], dtype=float) + 1j * np.array(r["scene"]["y"][j], float)
    fb = FourBar(80.0, 30.0, 70.0, 60.0, coupler=(50.0, np.radians(30.0)))
    m = fb.solve(np.radians(r["x"]) - THETA1, 1.0, form=2)
    expected = O2 + np.asarray(m.coupler) * cmath.exp(1j * THETA1)
    rounding = 2 * 10.0 ** -r["scene"]["decimals"]
    assert np.all(m.ok) and np.max(np.abs(shown - expected)) < rounding
    # a plotted quantity whose link is renamed follows the new name: the same numbers
    p.page.click("button[data-tab=plots]")
    q = next(n for n in js(p, "() => window.studio.result.names") if n.startswith("omega_rocker"))
    before = analysed(p)
    p.page.locator(f'#tab-plots input[data-q="{q}"]').check()
    settle(p, before)
    values = js(p, f"() => window.studio.result.columns[{q!r}]")
    assert values is not None and len(values) == len(r["x"])
    p.page.click("button[data-tab=design]")
    p.page.click("#tab-design .lists a:text-is('rocker')")
    before = analysed(p)
    p.page.fill("h3 input.name", "follower")
    p.page.keyboard.press("Enter")
    renamed = q.replace("rocker", "follower")
    deadline = time.monotonic() + 30
    while renamed not in js(p, "() => Object.keys(window.studio.result.columns)"):
        assert time.monotonic() < deadline, "the plot did not follow the renamed link"
        p.page.wait_for_timeout(50)
    assert js(p, "() => window.studio.plots.selected").count(renamed) == 1
    assert js(p, f"() => window.studio.result.columns[{renamed!r}]") == values
    p.page.click("button[data-tab=plots]")
    assert p.page.locator(f'#tab-plots svg.chart path.series[data-q="{renamed}"]').count() == 1
    assert p.page.locator("#tab-plots .card.note").count() == 0
    assert "follower" in p.page.locator("#canvas text.link-name").all_text_contents()
    p.shot("studio-21-plot-of-a-renamed-link")
    # a plotted quantity that is gone (its joint deleted): the page says it was taken off
    gone = next(n for n in js(p, "() => window.studio.result.names") if n.startswith("|VP|"))
    before = analysed(p)
    p.page.locator(f'#tab-plots input[data-q="{gone}"]').check()
    settle(p, before)
    p.page.click("button[data-tab=design]")
    p.page.click("#tab-design .lists a:text-is('P')")
    before = analysed(p)
    p.page.click("#tab-design button:text-is('Delete joint')")
    settle(p, before)
    p.page.click("button[data-tab=plots]")
    note = p.page.locator("#tab-plots .card.note")
    note.wait_for(state="visible", timeout=30_000)
    assert gone in note.inner_text() and "taken off" in note.inner_text()
    assert gone in p.page.locator("#status").inner_text()
    assert renamed in js(p, "() => window.studio.plots.selected")
    p.shot("studio-21b-plot-of-a-deleted-joint")
    # undo the deletion, then the renaming: the plot follows the link back to its old name
    for _ in range(2):
        before = analysed(p)
        p.page.click("#undo")
        settle(p, before)
    deadline = time.monotonic() + 30
    while q not in js(p, "() => Object.keys(window.studio.result.columns)"):
        assert time.monotonic() < deadline, "the plot did not follow the renaming undone"
        p.page.wait_for_timeout(50)
    assert js(p, f"() => window.studio.result.columns[{q!r}]") == values
    assert renamed not in js(p, "() => window.studio.plots.selected")
    p.page.click("#notice-close")
    assert not notice.is_visible()
    assert not p.errors, p.errors


def test_a_slider_crank_file_opens_with_what_it_keeps_and_drops(page, tmp_path):
    p = page
    text = example("slider_crank.toml").replace(
        "[slider_crank.engine.link4]       # the piston\nmass = 1.5",
        "[slider_crank.engine.link4]\nmass = 1.5\ninertia = 0.1",
    )
    f = tmp_path / "engine.toml"
    f.write_text(text, encoding="utf-8")
    open_file(p, f)
    said = p.page.locator("#notice").inner_text()
    assert "Opened [slider_crank.engine] as a drawn linkage: crank O2–A, coupler A–B" in said
    assert "link4] inertia" in said and "[inverted_slider_crank.shaper]" in said
    names = p.page.locator("#canvas text.link-name").all_text_contents()
    assert sorted(names) == ["coupler", "crank", "slider"]
    pt = next(iter(js(p, "() => window.studio.store.doc")["linkage"].values()))
    assert pt["friction"] == {"guide": {"coulomb": 0.05}}
    assert js(p, "() => window.studio.result.has_forces") is True
    # the default plots show a link that turns (the rod), not the block's constant angle
    shown = js(p, "() => window.studio.plots.selected")
    assert "theta_coupler [deg]" in shown and not [n for n in shown if "theta_slider" in n]
    p.shot("studio-22-slider-crank-file-opened")
    assert not p.errors, p.errors


def test_an_inverted_slider_crank_file_opens_with_its_block_in_the_slot(page, tmp_path):
    p = page
    text = example("slider_crank.toml")
    shaper = text[text.index("[inverted_slider_crank.shaper]") :]
    f = tmp_path / "shaper.toml"
    f.write_text('machdyn = 1\n[units]\nlength = "mm"\n' + shaper, encoding="utf-8")
    open_file(p, f)
    said = p.page.locator("#notice").inner_text()
    assert "Opened [inverted_slider_crank.shaper] as a drawn linkage: crank O2–A" in said
    names = p.page.locator("#canvas text.link-name").all_text_contents()
    assert sorted(names) == ["crank", "rocker", "slider"]
    # the slotted link points at the crank pin in every frame (offset 0): O4, S and A in line
    r = js(p, "() => window.studio.view.scene")
    at = {n: np.array(r["x"][i], float) + 1j * np.array(r["y"][i], float)
          for i, n in enumerate(r["names"]) if n in ("O4", "S", "A")}  # fmt: skip
    cross = np.imag((at["S"] - at["O4"]) * np.conj(at["A"] - at["O4"]))
    assert np.max(np.abs(cross) / np.abs(at["S"] - at["O4"])) < 1e-3
    p.shot("studio-23-inverted-slider-crank-file-opened")
    assert not p.errors, p.errors
