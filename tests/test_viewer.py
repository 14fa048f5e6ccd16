"""The browser viewer embeds the model's poses (parsed back and compared) and nothing remote.

Independent references: FourBar.solve called directly, the link lengths
(|A| = R2, |B − A| = R3, |B − O4| = R4) and the transmission angle from the
joint coordinates.
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess

import numpy as np
import pytest

from machdyn import FourBar, SliderCrank
from machdyn.errors import InputError
from machdyn.viewer import DATA_ID, _script_json, page_data, to_html


def embedded(page: str) -> dict:
    found = re.findall(
        rf'<script type="application/json" id="{DATA_ID}">(.*?)</script>', page, re.S
    )
    assert len(found) == 1
    return json.loads(found[0])


def arr(values) -> np.ndarray:
    return np.array([np.nan if v is None else v for v in values], dtype=float)


def test_poses_round_trip_through_the_page():
    fb = FourBar(8, 4, 7, 6, coupler=(5.0, np.radians(30)))
    page = to_html(fb, n=72, omega2=10.0)
    data = embedded(page)
    F = data["frames"]
    theta2 = np.radians(np.arange(0.0, 360.0, 5.0))
    np.testing.assert_allclose(arr(F["theta2_deg"]), np.degrees(theta2), atol=1e-9)
    m = fb.solve(theta2, omega2=10.0)
    for key, ref in (
        ("theta3_deg", np.degrees(m.theta3)),
        ("theta4_deg", np.degrees(m.theta4)),
        ("omega3", m.omega3),
        ("omega4", m.omega4),
        ("mu_deg", np.degrees(m.mu)),
        ("Ax", m.A.real),
        ("Ay", m.A.imag),
        ("Bx", m.B.real),
        ("By", m.B.imag),
        ("Px", m.coupler.real),
        ("Py", m.coupler.imag),
    ):
        np.testing.assert_allclose(arr(F[key]), ref, rtol=1e-10, atol=1e-10, err_msg=key)
    # the geometry holds in the embedded numbers themselves
    A = arr(F["Ax"]) + 1j * arr(F["Ay"])
    B = arr(F["Bx"]) + 1j * arr(F["By"])
    np.testing.assert_allclose(np.abs(A), 4, rtol=1e-10)
    np.testing.assert_allclose(np.abs(B - A), 7, rtol=1e-10)
    np.testing.assert_allclose(np.abs(B - 8), 6, rtol=1e-10)
    # μ: the acute angle between coupler AB and output O4B
    between = np.degrees(np.abs(np.angle((B - 8) / (B - A))))
    np.testing.assert_allclose(arr(F["mu_deg"]), np.minimum(between, 180 - between), atol=1e-8)
    # the coupler curve is the model's, and every frame's P lies on the drawn extent
    curve = fb.coupler_curve(1, 72).points
    np.testing.assert_allclose(arr(data["curve"]["x"]) + 1j * arr(data["curve"]["y"]), curve)
    E = data["extent"]
    for z in (*A, *B, *curve, 0, 8):
        assert E["xmin"] < z.real < E["xmax"] and E["ymin"] < z.imag < E["ymax"]
    assert data["closed"] is True and data["barker_class"] == "GCRR"


def test_page_is_self_contained_and_interactive():
    page = to_html(FourBar(8, 4, 7, 6, coupler=(5.0, 0.5)), n=36)
    assert page.startswith("<!DOCTYPE html>")
    assert not re.search(r"https?:", page, re.I)
    assert not re.search(r"\b(src|href)\s*=", page, re.I)  # nothing is fetched
    assert "<link" not in page and "@import" not in page
    assert set(re.findall(r"url\(([^)]*)\)", page)) == {"#hatch"}  # only in-page references
    for needle in ('id="play"', 'id="slider"', 'type="range"', "<svg", "requestAnimationFrame"):
        assert needle in page
    for readout in ("theta2", "theta3", "theta4", "omega3", "omega4", "mu"):
        assert f'id="r-{readout}"' in page
    assert "deg" in page and "rad/s" in page


def test_linkage_without_coupler():
    page = to_html(FourBar(8, 4, 7, 6), n=12)
    data = embedded(page)
    assert data["curve"] is None
    assert "Px" not in data["frames"]
    assert len(data["frames"]["Ax"]) == 12


def test_rocker_page_goes_there_and_back_with_nulls_at_toggles():
    fb = FourBar(4, 7, 5, 3)  # RRR2: link 2 rocks; its limits are toggles of links 3 and 4
    data = embedded(to_html(fb, n=10))
    F = data["frames"]
    assert len(F["theta2_deg"]) == 18 and data["input"] == "rocker" and not data["closed"]
    rng = fb.input_range(1)
    assert F["theta2_deg"][0] == pytest.approx(np.degrees(rng.lo))
    assert F["theta2_deg"][9] == pytest.approx(np.degrees(rng.hi))
    grid = rng.grid(10)
    m = fb.solve(np.concatenate([grid, grid[-2:0:-1]]))
    # rates are undefined at the toggles: embedded as null (JSON has no NaN)
    assert [v is None for v in F["omega3"]] == list(~m.ok)
    assert F["omega3"][0] is None and F["omega3"][9] is None
    assert all(F["assembled"])  # the poses themselves are drawn
    assert F["omega2"][:10] == [1.0] * 10 and F["omega2"][10:] == [-1.0] * 8


def test_embedded_text_cannot_close_the_script():
    evil = {"title": "</script><script>alert(1)</script>&\u2028", "x": [1.5, None]}
    text = _script_json(evil)
    assert "<" not in text and ">" not in text and "&" not in text and "\u2028" not in text
    assert json.loads(text) == evil


def test_title_is_escaped(monkeypatch):
    fb = FourBar(8, 4, 7, 6)
    monkeypatch.setattr(FourBar, "__repr__", lambda self: "<b>&")
    page = to_html(fb, n=4)
    assert "<b>&" not in page.split("<script")[0]
    assert "&lt;b&gt;&amp;" in page
    assert embedded(page)["title"] == "<b>&, form 1"


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


def test_only_four_bars():
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
