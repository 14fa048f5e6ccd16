"""The browser viewer embeds the model's poses (parsed back and compared) and nothing remote.

Independent references: FourBar.solve called directly, the link lengths
(|A| = R2, |B − A| = R3, |B − O4| = R4) and the transmission angle from the
joint coordinates. The page itself is checked in a browser in test_draw_browser.py.
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess

import numpy as np
import pytest

from machdyn import FourBar, SliderCrank
from machdyn.draw.html import DATA_CLASS, script_json
from machdyn.errors import InputError
from machdyn.viewer import page_data, to_html


def embedded(page: str) -> dict:
    found = re.findall(
        rf'<script type="application/json" class="{DATA_CLASS}">(.*?)</script>', page, re.S
    )
    assert len(found) == 1
    return json.loads(found[0])


def column(data: dict, j: int, frames: int) -> np.ndarray:
    """A point's embedded x + jy in every frame (a fixed point is written once)."""
    x, y = data["x"][j], data["y"][j]
    x = arr(x) if isinstance(x, list) else np.full(frames, x)
    y = arr(y) if isinstance(y, list) else np.full(frames, y)
    return x + 1j * y


def arr(values) -> np.ndarray:
    return np.array([np.nan if v is None else v for v in values], dtype=float)


def test_poses_round_trip_through_the_page():
    fb = FourBar(8, 4, 7, 6, coupler=(5.0, np.radians(30)))
    page = to_html(fb, n=72, omega2=10.0)
    data = embedded(page)
    tol = 0.5 * 10.0 ** -data["decimals"]  # coordinates are printed to this many places
    theta2 = np.radians(np.arange(0.0, 360.0, 5.0))
    m = fb.solve(theta2, omega2=10.0)
    names = ("O2", "O4", "A", "B", "P")
    drawn = {n: column(data, j, 72) for j, n in enumerate(names)}
    for name, ref in (("A", m.A), ("B", m.B), ("P", m.coupler), ("O2", 0j), ("O4", 8 + 0j)):
        np.testing.assert_allclose(drawn[name].real, np.real(ref), atol=tol, rtol=0, err_msg=name)
        np.testing.assert_allclose(drawn[name].imag, np.imag(ref), atol=tol, rtol=0, err_msg=name)
    readout = {r["label"]: arr(r["v"]) for r in data["readout"]}
    for key, ref, digits in (
        ("θ2", np.degrees(theta2), 2),
        ("θ3", np.degrees(m.theta3), 2),
        ("θ4", np.degrees(m.theta4), 2),
        ("ω3", m.omega3, 4),
        ("ω4", m.omega4, 4),
        ("μ", np.degrees(m.mu), 2),
    ):
        np.testing.assert_allclose(readout[key], ref, atol=0.5 * 10.0**-digits + 1e-12, err_msg=key)
    # the geometry holds in the embedded numbers themselves (to the printed precision)
    A, B = drawn["A"], drawn["B"]
    np.testing.assert_allclose(np.abs(A), 4, atol=4 * tol)
    np.testing.assert_allclose(np.abs(B - A), 7, atol=4 * tol)
    np.testing.assert_allclose(np.abs(B - 8), 6, atol=4 * tol)
    # the coupler curve is the model's, drawn as one closed polyline in the SVG
    curve = fb.coupler_curve(1, 72).points
    line = re.search(r'id="(md\d+)-coupler_curve".*?<polyline points="([^"]*)"', page).group(2)
    xy = np.array([[float(v) for v in p.split(",")] for p in line.split()])
    np.testing.assert_allclose(xy[:-1, 0], curve.real, atol=tol, rtol=0)
    np.testing.assert_allclose(xy[:-1, 1], curve.imag, atol=tol, rtol=0)
    assert np.allclose(xy[0], xy[-1])
    assert data["closed"] is True and "GCRR" in page


def test_page_is_self_contained_and_interactive():
    page = to_html(FourBar(8, 4, 7, 6, coupler=(5.0, 0.5)), n=36)
    assert page.startswith("<!DOCTYPE html>")
    body = page.replace('xmlns="http://www.w3.org/2000/svg"', "")  # a namespace, not a fetch
    assert not re.search(r"https?:", body, re.I)
    assert not re.search(r"\b(src|href)\s*=", page, re.I)  # nothing is fetched
    assert "<link" not in page and "@import" not in page
    assert {u.split("-", 1)[1] for u in re.findall(r"url\(#([^)]*)\)", page)} == {"hatch"}
    for needle in (
        'class="play"',
        'class="frame"',
        'type="range"',
        "<svg",
        "requestAnimationFrame",
    ):
        assert needle in page
    for label in ("θ2", "θ3", "θ4", "ω3", "ω4", "μ"):
        assert f"<td>{label}</td>" in page
    assert "deg" in page and "rad/s" in page


def test_other_models_draw_too():
    # the viewer used to refuse anything but a FourBar (InputError: expected a FourBar)
    page = to_html(SliderCrank(2, 6, 0.5), n=24)
    data = embedded(page)
    assert data["frames"] == 24
    assert re.search(r'<g id="md\d+-slider"', page)  # the block on its guide
    assert re.search(r'<g id="md\d+-slide_guide"', page)


def test_linkage_without_coupler():
    page = to_html(FourBar(8, 4, 7, 6), n=12)
    data = embedded(page)
    assert "coupler_curve" not in page and "coupler_triangle" not in page
    assert len(data["x"]) == 4 and len(data["x"][2]) == 12  # O2, O4, A, B; A moves


def test_rocker_page_goes_there_and_back_with_nulls_at_toggles():
    fb = FourBar(4, 7, 5, 3)  # RRR2: link 2 rocks; its limits are toggles of links 3 and 4
    data = embedded(to_html(fb, n=10))
    readout = {r["label"]: r["v"] for r in data["readout"]}
    assert data["frames"] == 18 and not data["closed"]
    rng = fb.input_range(1)
    assert readout["θ2"][0] == pytest.approx(np.degrees(rng.lo), abs=0.005)
    assert readout["θ2"][9] == pytest.approx(np.degrees(rng.hi), abs=0.005)
    grid = rng.grid(10)
    m = fb.solve(np.concatenate([grid, grid[-2:0:-1]]))
    # rates are undefined at the toggles: embedded as null (JSON has no NaN), never 0
    assert [v is None for v in readout["ω3"]] == list(~m.ok)
    assert readout["ω3"][0] is None and readout["ω3"][9] is None
    assert all(data["shown"])  # the poses themselves are drawn
    # the return stroke runs backwards: ω3 changes sign against the forward stroke
    fwd = fb.solve(grid[1:-1], omega2=1.0).omega3
    np.testing.assert_allclose(arr(readout["ω3"][10:])[::-1], -fwd[::-1][::-1], atol=1e-4)


def test_embedded_text_cannot_close_the_script():
    evil = {"title": "</script><script>alert(1)</script>&\u2028", "x": [1.5, None]}
    text = script_json(evil)
    assert "<" not in text and ">" not in text and "&" not in text and "\u2028" not in text
    assert json.loads(text) == evil


def test_title_is_escaped(monkeypatch):
    import machdyn.draw.build as build

    monkeypatch.setattr(build, "describe", lambda fb: "<b>&")
    page = to_html(FourBar(8, 4, 7, 6), n=4)
    assert "<b>&" not in page
    assert "&lt;b&gt;&amp;" in page


def test_writes_the_file(tmp_path):
    path = tmp_path / "hw6.html"
    page = to_html(FourBar(8, 4, 7, 6), n=8, path=path)
    assert path.read_text(encoding="utf-8") == page


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"n": 1}, "n"),
        ({"n": 2.5}, "n"),
        ({"n": 10**6}, "n"),
        ({"form": 3}, "form"),
        ({"fps": 0}, "fps"),
        ({"omega2": float("nan")}, "omega2"),
    ],
)
def test_bad_input(kwargs, field):
    with pytest.raises(InputError) as err:
        to_html(FourBar(8, 4, 7, 6), **kwargs)
    assert err.value.field == field


def test_page_data_is_for_four_bars():
    with pytest.raises(InputError, match="FourBar"):
        page_data(SliderCrank(2, 6))


@pytest.mark.skipif(shutil.which("node") is None, reason="node.js is not installed")
def test_script_parses():
    # optional: a syntax check of the page's script when node.js happens to be present
    page = to_html(FourBar(8, 4, 7, 6, coupler=(5, 0.5)), n=8)
    script = re.findall(r"<script>(.*?)</script>", page, re.S)
    assert len(script) == 1
    proc = subprocess.run(
        ["node", "--check", "-"], input=script[0], capture_output=True, text=True, timeout=30
    )
    assert proc.returncode == 0, proc.stderr


def test_random_linkages_embed_closed_loops(rng):
    # seeded property test over all kinds of four-bars (cranks, rockers, GRCR/GRRC, both forms)
    tried = 0
    while tried < 25:
        r = rng.uniform(0.5, 10.0, size=4)
        if 2 * r.max() >= r.sum():  # the lengths cannot close a loop
            continue
        tried += 1
        fb = FourBar(*r, coupler=(rng.uniform(0, 5), rng.uniform(-np.pi, np.pi)))
        form = int(rng.integers(1, 3))
        data = page_data(fb, form=form, n=120)
        F = data["frames"]
        shown = np.array(F["assembled"])
        assert shown.all(), fb  # a default sweep stays inside the input's range
        A = arr(F["Ax"]) + 1j * arr(F["Ay"])
        B = arr(F["Bx"]) + 1j * arr(F["By"])
        P = arr(F["Px"]) + 1j * arr(F["Py"])
        np.testing.assert_allclose(np.abs(A), r[1], rtol=1e-9)
        np.testing.assert_allclose(np.abs(B - A), r[2], rtol=1e-9)
        np.testing.assert_allclose(np.abs(B - r[0]), r[3], rtol=1e-9)
        np.testing.assert_allclose(np.abs(P - A), fb.coupler[0], rtol=1e-9, atol=1e-9)
        # consecutive frames are neighbours (no jump to the other circuit): the output
        # link turns by less than 20° from one frame to the next, also when the loop closes
        B = np.append(B, B[0])
        turn = np.degrees(np.abs(np.angle((B[1:] - r[0]) / (B[:-1] - r[0]))))
        assert turn.max() < 20, (fb, form, turn.max())
