"""Plots and animations draw what the models solved (content checks, not just "it ran").

Independent references: the link lengths and the coupler triangle (|A − O2| = R2,
|B − A| = R3, |B − O4| = R4, |P − A| = p at δ from AB), Kennedy's rule for the
instant centres, and the GIF read back with PIL.
"""

from __future__ import annotations

import io

import matplotlib.pyplot as plt
import numpy as np
import pytest
from PIL import Image

from machdyn import FourBar, SliderCrank
from machdyn.errors import AssemblyError, InputError
from machdyn.plot import (
    animate,
    draw_fourbar,
    plot_coupler_curve,
    plot_kinematics,
    plot_slider_crank,
    plot_slider_motion,
    sweep,
)

P_DELTA = (5.0, np.radians(30))


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


@pytest.fixture
def hw6():
    """The notes' HW 6 crank-rocker (GCRR 8-4-7-6) with a coupler point."""
    return FourBar(8, 4, 7, 6, coupler=P_DELTA)


def by_gid(container, gid):
    found = [a for a in container if a.get_gid() == gid]
    assert len(found) == 1, f"expected one artist {gid!r}, found {len(found)}"
    return found[0]


def ends(line):
    x, y = (np.asarray(v, dtype=float) for v in line.get_data())
    return x + 1j * y


def assert_pose_geometry(fb, A, B, P=None):
    r1, r2, r3, r4 = fb.lengths
    assert abs(A) == pytest.approx(r2, rel=1e-12)
    assert abs(B - A) == pytest.approx(r3, rel=1e-12)
    assert abs(B - r1) == pytest.approx(r4, rel=1e-12)
    if P is not None:
        p, delta = fb.coupler
        assert abs(P - A) == pytest.approx(p, rel=1e-12)
        assert np.angle((P - A) / (B - A)) == pytest.approx(delta, abs=1e-12)


# --------------------------------------------------------------------------------------
# draw_fourbar


def test_links_are_drawn_at_the_solved_joints(hw6):
    theta2 = np.radians(60)
    ax = draw_fourbar(hw6, theta2)
    m = hw6.solve(theta2)
    A, B, P = complex(m.A), complex(m.B), complex(m.coupler)
    assert_pose_geometry(hw6, A, B, P)
    np.testing.assert_allclose(ends(by_gid(ax.lines, "link1")), [0, 8])
    np.testing.assert_allclose(ends(by_gid(ax.lines, "link2")), [0, A])
    np.testing.assert_allclose(ends(by_gid(ax.lines, "link3")), [A, B])
    np.testing.assert_allclose(ends(by_gid(ax.lines, "link4")), [8, B])
    np.testing.assert_allclose(ends(by_gid(ax.lines, "joints")), [0, A, B, 8])
    np.testing.assert_allclose(ends(by_gid(ax.lines, "coupler_point")), [P])
    tri = by_gid(ax.patches, "coupler_triangle").get_xy()
    np.testing.assert_allclose(tri[:3, 0] + 1j * tri[:3, 1], [A, B, P])
    # the pose is inside the view, and both ground pivots are hatched
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    for z in (0, 8, A, B, P):
        assert x0 <= z.real <= x1 and y0 <= z.imag <= y1
    for gid in ("ground_O2", "ground_O4"):
        assert by_gid(ax.patches, gid).get_hatch() == "////"
    assert ax.get_aspect() == 1.0


def test_pose_from_a_motion_by_index_and_negative_index(hw6):
    theta2 = np.radians([10, 100, 200])
    m = hw6.solve(theta2, form=2)
    for index, k in ((1, 1), (-1, 2)):
        ax = draw_fourbar(hw6, m, index=index)
        np.testing.assert_allclose(ends(by_gid(ax.lines, "link3")), [m.A[k], m.B[k]])
        assert_pose_geometry(hw6, m.A[k], m.B[k], m.coupler[k])
        assert np.angle((m.B[k] - 8) / (m.B[k] - m.A[k])) < 0  # form 2: φ12 = θ4 − θ3 < 0


def test_linkage_without_coupler_draws_no_triangle():
    fb = FourBar(8, 4, 7, 6)
    ax = draw_fourbar(fb, 0.3, labels=False)
    gids = {a.get_gid() for a in [*ax.lines, *ax.patches]}
    assert "coupler_triangle" not in gids and "coupler_point" not in gids
    assert not ax.texts


def centres_drawn(ax):
    """Every centre as drawn: a labelled cross in the view, or an arrow at the border whose
    label gives its coordinates (or 'at ∞' and its direction)."""
    found = {}
    for t in ax.texts:
        text = t.get_text()
        if not text.startswith("I"):
            continue
        name = text[:3]
        if t.get_gid() and t.get_gid().startswith("centre_arrow_"):
            if "∞" in text:
                found[name] = complex("inf")
            else:
                x, y = text[text.index("(") + 1 : text.index(")")].split(",")
                found[name] = complex(float(x), float(y))
        else:
            found[name] = complex(*t.xy)
    return found


def test_instant_centres_obey_kennedy_and_keep_the_view(hw6):
    theta2 = np.radians(50)
    plain = draw_fourbar(hw6, theta2)
    _, ax = plt.subplots()
    draw_fourbar(hw6, theta2, ax=ax, instant_centres=True)
    m = hw6.solve(theta2)
    A, B = complex(m.A), complex(m.B)
    labels = centres_drawn(ax)
    assert sorted(labels) == ["I12", "I13", "I14", "I23", "I24", "I34"]
    assert labels["I12"] == pytest.approx(0) and labels["I14"] == pytest.approx(8)
    assert labels["I23"] == pytest.approx(A) and labels["I34"] == pytest.approx(B)
    marks = ends(by_gid(ax.lines, "instant_centres"))
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    inside = [n for n, z in labels.items() if x0 <= z.real <= x1 and y0 <= z.imag <= y1]
    assert len(marks) == len(inside) >= 4
    # a centre off the view has an arrow at the border, pointing towards it
    for name in set(labels) - set(inside):
        arrow = by_gid(ax.texts, f"centre_arrow_{name}")
        tip, tail = complex(*arrow.xy), complex(*arrow.xyann)
        assert x0 <= tip.real <= x1 and y0 <= tip.imag <= y1
        direction = (labels[name] - tail) / (tip - tail)
        assert abs(np.angle(direction)) < 1e-3  # the arrow points at the printed centre

    def collinear(p, q, r):
        return abs(((q - p).conjugate() * (r - p)).imag) / (abs(q - p) * abs(r - p))

    # Kennedy: I13 on lines I12-I23 and I14-I34; I24 on lines I12-I14 and I23-I34
    # (coordinates as printed, 4 significant digits)
    assert collinear(0, A, labels["I13"]) < 1e-3 and collinear(8, B, labels["I13"]) < 1e-3
    assert collinear(0, 8, labels["I24"]) < 1e-3 and collinear(A, B, labels["I24"]) < 1e-3
    plain.apply_aspect()  # the plain drawing's view as shown (equal aspect applied)
    assert ax.get_xlim() == pytest.approx(plain.get_xlim(), rel=1e-6)
    assert ax.get_ylim() == pytest.approx(plain.get_ylim(), rel=1e-6)


def test_parallel_links_put_a_centre_at_infinity():
    # a parallelogram: links 2 and 4 stay parallel, so I13 is at infinity
    fb = FourBar(5, 2, 5, 2)
    ax = draw_fourbar(fb, np.radians(70), instant_centres=True)
    notes = {t.get_gid(): t.get_text() for t in ax.texts if t.get_gid()}
    # links 2 and 4 stay parallel (I13 at infinity along them, at 70°), and so do
    # links 1 and 3 (I24 along the ground, at 0°)
    assert notes["centre_arrow_I13"] == "I13 at ∞ (70.0°)"
    assert notes["centre_arrow_I24"] == "I24 at ∞ (0.0°)"
    assert len(ends(by_gid(ax.lines, "instant_centres"))) == 4


def test_bad_poses_and_inputs(hw6):
    with pytest.raises(AssemblyError):  # outside a rocker's range
        draw_fourbar(FourBar(6, 9, 3, 8), np.radians(10))
    m = FourBar(6, 9, 3, 8).solve(np.radians([10.0, 60.0]))
    with pytest.raises(AssemblyError, match="no pose to draw"):
        draw_fourbar(FourBar(6, 9, 3, 8), m, index=0)
    draw_fourbar(FourBar(6, 9, 3, 8), m, index=1)  # the assembled sample is fine
    with pytest.raises(InputError, match="index"):
        draw_fourbar(hw6, np.radians([1, 2]), index=2)
    with pytest.raises(InputError, match="index"):
        draw_fourbar(hw6, 0.1, index=0.5)
    with pytest.raises(InputError, match="motion"):
        draw_fourbar(FourBar(8, 4, 7, 5), hw6.solve(0.1))
    with pytest.raises(InputError, match="form"):
        draw_fourbar(hw6, 0.1, form=3)


# --------------------------------------------------------------------------------------
# plot_kinematics


def unmasked(line):
    x = np.asarray(line.get_xdata(), dtype=float)
    y = np.ma.masked_invalid(np.ma.asarray(line.get_ydata(), dtype=float))
    keep = ~np.ma.getmaskarray(y)
    return x[keep], np.asarray(y[keep])


def test_kinematic_curves_are_the_motion_arrays_in_degrees():
    # a double crank: θ3 and θ4 wrap through 360°
    fb = FourBar(2, 4, 4, 4)
    theta2 = np.radians(np.arange(0.0, 360.0, 3.0))
    m = fb.solve(theta2, omega2=7.0, alpha2=2.0)
    assert m.ok.all()
    fig = plot_kinematics(m, jerk=True, mu=True)
    lines = {line.get_gid(): line for ax in fig.axes for line in ax.lines if line.get_gid()}
    deg = np.degrees(theta2)
    for name in ("theta3", "theta4", "mu"):
        x, y = unmasked(lines[name])
        np.testing.assert_allclose(x, deg)
        np.testing.assert_allclose(y, np.degrees(getattr(m, name)))
    for name in ("omega3", "omega4", "alpha3", "alpha4", "jerk3", "jerk4"):
        x, y = unmasked(lines[name])
        np.testing.assert_allclose(x, deg)
        np.testing.assert_allclose(y, getattr(m, name))
    # no segment is drawn across a wrap from 360° to 0°
    for name in ("theta3", "theta4"):
        y = np.ma.masked_invalid(np.ma.asarray(lines[name].get_ydata(), dtype=float))
        jumps = np.abs(np.diff(y))
        assert np.ma.count(jumps) > 0 and jumps.max() < 180.0
        assert np.ma.count_masked(y) >= 1  # the wrap was broken at least once
    labels = [ax.get_ylabel() for ax in fig.axes]
    assert labels == ["angle (deg)", "ω (rad/s)", "α (rad/s²)", "jerk (rad/s³)"]
    assert fig.axes[-1].get_xlabel() == "θ2 (deg)"


def test_flagged_samples_are_gaps():
    # GRCR 6-9-3-8: link 2 rocks between 31.59° and 92.12° (form 1); its ends are toggles
    fb = FourBar(6, 9, 3, 8)
    rng = fb.input_range(1)
    theta2 = np.concatenate([np.radians([0.0, 20.0]), np.linspace(rng.lo, rng.hi, 9)])
    theta2 = np.append(theta2, np.radians(150.0))
    m = fb.solve(theta2, omega2=1.0)
    assembled = np.zeros(theta2.size, bool)
    assembled[2:11] = True
    toggles = np.zeros(theta2.size, bool)
    toggles[[2, 10]] = True  # the limits of the input rocker
    np.testing.assert_array_equal(m.assembled, assembled)
    np.testing.assert_array_equal(m.ok, assembled & ~toggles)
    fig = plot_kinematics(m)
    lines = {line.get_gid(): line for ax in fig.axes for line in ax.lines if line.get_gid()}
    for name in ("omega3", "omega4", "alpha3", "alpha4"):
        mask = np.ma.getmaskarray(lines[name].get_ydata())
        np.testing.assert_array_equal(mask, ~m.ok)  # gaps exactly at the flagged samples
    x, y = unmasked(lines["theta4"])
    np.testing.assert_allclose(x, np.degrees(theta2[assembled]))  # positions kept at toggles
    np.testing.assert_allclose(y, np.degrees(m.theta4[assembled]))
    assert "flagged" in fig.axes[0].get_title()


def test_plot_kinematics_rejects_other_results():
    with pytest.raises(InputError, match="FourBarMotion"):
        plot_kinematics(SliderCrank(2, 6).solve(0.1))


# --------------------------------------------------------------------------------------
# plot_coupler_curve


def test_coupler_curve_satisfies_the_loop_and_closes(hw6):
    ax = plot_coupler_curve(hw6, n=90)
    pts = ends(by_gid(ax.lines, "coupler_curve"))
    curve = hw6.coupler_curve(1, 90)
    assert pts.size == 91 and pts[0] == pts[-1]
    np.testing.assert_allclose(pts[:-1], curve.points)
    # independent check: from θ2 and P rebuild B and close the loop with link 4
    p, delta = P_DELTA
    A = 4 * np.exp(1j * curve.theta2)
    assert np.abs(np.abs(pts[:-1] - A) - p) == pytest.approx(0, abs=1e-12)
    B = A + 7 * (pts[:-1] - A) / p * np.exp(-1j * delta)
    np.testing.assert_allclose(np.abs(B - 8), 6, rtol=1e-12)
    # the linkage is drawn at the first point of the curve
    np.testing.assert_allclose(ends(by_gid(ax.lines, "coupler_point")), pts[:1])


def test_coupler_curve_of_a_grcr_form_runs_both_branches():
    fb = FourBar(6, 9, 3, 8, coupler=(2.0, 1.0))
    ax = plot_coupler_curve(fb, form=2, n=50)
    pts = ends(by_gid(ax.lines, "coupler_curve"))
    assert pts[0] == pts[-1]
    # form 2 of a GRCR: θ2 below the ground line
    assert np.all(np.sin(fb.coupler_curve(2, 50).theta2) <= 1e-12)


def test_coupler_curve_needs_a_coupler_point():
    with pytest.raises(InputError, match="coupler"):
        plot_coupler_curve(FourBar(8, 4, 7, 6))


# --------------------------------------------------------------------------------------
# slider-crank


def test_slider_crank_pose_and_block():
    sc = SliderCrank(crank=2.0, coupler=6.0, offset=0.5, point=(3.0, 0.4))
    theta2 = np.radians(135)
    ax = plot_slider_crank(sc, theta2)
    m = sc.solve(theta2)
    A, B = complex(m.A), complex(m.B)
    assert abs(A) == pytest.approx(2.0) and abs(B - A) == pytest.approx(6.0)
    assert B.imag == pytest.approx(0.5)  # on the slide line
    np.testing.assert_allclose(ends(by_gid(ax.lines, "link2")), [0, A])
    np.testing.assert_allclose(ends(by_gid(ax.lines, "link3")), [A, B])
    block = by_gid(ax.patches, "slider").get_xy()[:4]
    centre = complex(*block.mean(axis=0))
    assert centre == pytest.approx(B)
    assert abs(complex(*(block[1] - block[0])).imag) < 1e-12  # along the slide line
    guide = ends(by_gid(ax.lines, "slide_guide"))
    lo, hi = sc.stroke(1)
    assert guide.real.min() < lo and guide.real.max() > hi  # the guide covers the stroke
    P = ends(by_gid(ax.lines, "coupler_point"))[0]
    assert abs(P - A) == pytest.approx(3.0)
    assert np.angle((P - A) / (B - A)) == pytest.approx(0.4)  # δ from the line A→B
    tri = by_gid(ax.patches, "coupler_triangle").get_xy()
    np.testing.assert_allclose(tri[:3, 0] + 1j * tri[:3, 1], [A, B, P])


def test_slider_motion_curves_and_gaps():
    sc = SliderCrank(crank=3.0, coupler=2.0)  # the crank rocks within ±41.81°
    theta2 = np.radians(np.arange(-60.0, 61.0, 5.0))
    m = sc.solve(theta2, omega2=2.0)
    fig = plot_slider_motion(m)
    lines = {line.get_gid(): line for ax in fig.axes for line in ax.lines if line.get_gid()}
    x, y = unmasked(lines["d"])
    inside = np.abs(theta2) <= np.arcsin(2 / 3)
    np.testing.assert_allclose(x, np.degrees(theta2[inside]))
    # d from the triangle O2-A-B: d = a cos θ2 + sqrt(b² − (a sin θ2)²)
    t = theta2[inside]
    np.testing.assert_allclose(y, 3 * np.cos(t) + np.sqrt(4 - (3 * np.sin(t)) ** 2))
    np.testing.assert_array_equal(np.ma.getmaskarray(lines["d_dot"].get_ydata()), ~m.ok)
    with pytest.raises(InputError, match="SliderCrankMotion"):
        plot_slider_motion(FourBar(8, 4, 7, 6).solve(0.1))
    with pytest.raises(InputError, match="SliderCrank"):
        plot_slider_crank(FourBar(8, 4, 7, 6), 0.1)
    with pytest.raises(AssemblyError):
        plot_slider_crank(sc, m, index=0)


# --------------------------------------------------------------------------------------
# sweep and animate


def test_sweep_of_a_crank_is_one_turn(hw6):
    s = sweep(hw6, n=8, omega2=3.0)
    np.testing.assert_allclose(s.theta2, np.radians(np.arange(0, 360, 45)))
    assert np.all(s.omega2 == 3.0)
    m = hw6.solve(s.theta2, omega2=3.0)
    np.testing.assert_allclose(s.B, m.B)
    np.testing.assert_allclose(s.omega4, m.omega4)


def test_sweep_of_a_rocker_goes_there_and_back():
    fb = FourBar(4, 7, 5, 3)  # RRR2, a triple rocker: link 2 rocks about θ2 = 0
    assert fb.form_rule == "phi12"
    rng = fb.input_range(1)
    s = sweep(fb, n=10)
    assert len(s) == 18
    assert s.theta2[0] == pytest.approx(rng.lo) and s.theta2[9] == pytest.approx(rng.hi)
    assert np.all(np.diff(s.theta2[:10]) > 0) and np.all(np.diff(s.theta2[9:]) < 0)
    assert np.all(s.omega2[:10] == 1.0) and np.all(s.omega2[10:] == -1.0)
    assert s.assembled.all()
    np.testing.assert_allclose(s.B[10:], fb.solve(s.theta2[10:], omega2=-1.0).B)
    # the return stroke ends one step from the start: the loop closes smoothly
    steps = np.abs(np.diff(np.append(s.B, s.B[0])))
    assert steps[-1] <= steps[:-1].max()


def test_sweep_of_a_grcr_form_closes_over_both_branches():
    fb = FourBar(6, 9, 3, 8)
    assert fb.form_rule == "phi34"
    s = sweep(fb, form=1, n=40)
    assert len(s) == 78
    grid = fb.input_range(1).grid(40)
    np.testing.assert_allclose(s.theta2, np.concatenate([grid, grid[-2:0:-1]]))
    np.testing.assert_allclose(s.B[:40], fb.solve(grid, branch=1).B)
    np.testing.assert_allclose(s.B[40:], fb.solve(grid[-2:0:-1], branch=-1).B)
    assert np.all(np.sin(s.theta2) > 0)  # form 1 of a GRCR: θ2 above the ground line
    # the branches meet at the toggles, so the motion is a closed loop without jumps
    steps = np.abs(np.diff(np.append(s.B, s.B[0])))
    assert steps.max() < 3 * np.median(steps)


def test_gif_has_the_requested_frames(tmp_path, hw6):
    path = tmp_path / "hw6.gif"
    anim = animate(hw6, path=path, n=6, fps=10, dpi=25, figsize=(4, 3.2))
    with Image.open(path) as im:
        assert im.n_frames == 6
        assert im.info["duration"] == 100
    # after saving, the figure shows the last pose, at the solved joints
    fig = anim._fig  # matplotlib keeps the animated figure here
    ax = fig.axes[0]
    m = hw6.solve(np.radians(300))
    np.testing.assert_allclose(ends(by_gid(ax.lines, "link3")), [m.A, m.B])
    assert "300.00°" in by_gid(ax.texts, "status").get_text()
    # frames are drawn on a cached background: the last one matches a full render of the
    # figure up to the GIF's colour quantisation
    buf = io.BytesIO()
    fig.savefig(buf, format="rgba", dpi=fig.dpi)
    with Image.open(path) as im:
        im.seek(im.n_frames - 1)
        last = np.asarray(im.convert("RGB"))
    full = np.frombuffer(buf.getvalue(), np.uint8).reshape(*last.shape[:2], 4)[..., :3]
    diff = np.abs(full.astype(int) - last.astype(int)).max(axis=2)
    assert diff.mean() < 4 and diff.max() <= 64
    # the coupler curve behind the linkage is the model's, closed over the turn
    curve = ends(by_gid(ax.lines, "coupler_curve"))
    np.testing.assert_allclose(curve[:-1], hw6.coupler_curve(1, 360).points)
    assert curve[0] == curve[-1]


def test_animation_of_explicit_angles_flags_what_cannot_be_drawn(tmp_path):
    fb = FourBar(6, 9, 3, 8)
    path = tmp_path / "rocker.gif"
    anim = animate(fb, np.radians([10.0, 40.0, 60.0, 80.0]), path=path, dpi=25, figsize=(4, 3.5))
    with Image.open(path) as im:
        assert im.n_frames == 4
    assert len(list(anim.new_frame_seq())) == 4
    # after saving, the figure shows the last frame: θ2 = 10° is outside the rocker's range
    anim2 = animate(fb, np.radians([60.0, 10.0]), path=path, dpi=25, figsize=(4, 3.5))
    ax = anim2._fig.axes[0]
    assert "cannot be assembled" in by_gid(ax.texts, "status").get_text()
    assert not by_gid(ax.lines, "link3").get_visible()


def test_animate_rejects_bad_input(tmp_path, hw6):
    with pytest.raises(InputError, match=r"\.gif"):
        animate(hw6, path=tmp_path / "x.avi", n=4)
    assert not (tmp_path / "x.avi").exists()
    with pytest.raises(InputError, match="fps"):
        animate(hw6, fps=0, n=4)
    with pytest.raises(InputError, match="n"):
        animate(hw6, n=1)
    with pytest.raises(InputError, match="cannot draw a str"):
        animate("a four-bar", n=4)


# --------------------------------------------------------------------------------------
# the `animate` command (on a typer app of its own; the lead registers it on the main app)


@pytest.fixture
def cli():
    import typer
    from typer.testing import CliRunner

    from machdyn.cli.plot import animate as animate_command

    app = typer.Typer()
    app.command("animate")(animate_command)
    app.command("other")(lambda: None)  # two commands, so "animate" is a subcommand
    runner = CliRunner()
    return lambda *args: runner.invoke(app, ["animate", *map(str, args)])


def test_cli_writes_each_kind_of_file(cli, tmp_path):
    gif = tmp_path / "hw6.gif"
    result = cli(8, 4, 7, 6, "--coupler", "5:30", "--frames", 5, "--out", gif)
    assert result.exit_code == 0, result.output
    assert "5 frames" in result.output
    with Image.open(gif) as im:
        assert im.n_frames == 5
    page = tmp_path / "hw6.html"
    assert cli(8, 4, 7, 6, "--coupler", "5:30", "--frames", 12, "--out", page).exit_code == 0
    text = page.read_text(encoding="utf-8")
    assert "<svg" in text and "http" not in text
    png = tmp_path / "hw6.png"
    assert cli(8, 4, 7, 6, "--coupler", "5:30", "--theta2", 45, "--out", png).exit_code == 0
    with Image.open(png) as im:
        assert im.format == "PNG" and im.size[0] > 100
    svg = tmp_path / "rocker.svg"
    assert cli(4, 7, 5, 3, "--form", 2, "--out", svg).exit_code == 0  # no coupler: pose only
    assert "<svg" in svg.read_text(encoding="utf-8")


def test_cli_still_pose_is_at_the_requested_angle(cli, tmp_path):
    svg = tmp_path / "pose.svg"
    assert cli(8, 4, 7, 6, "--theta2", 90, "--out", svg).exit_code == 0
    text = svg.read_text(encoding="utf-8")
    assert "θ2 = 90°, form 1" in text  # matplotlib keeps each text as a comment


@pytest.mark.parametrize(
    ("args", "field", "needle"),
    [
        ((8, 4, 7, 6, "--out", "x.jpg"), "--out", ".gif, .html, .png, .svg"),
        ((8, 4, 7, 6, "--out", "x"), "--out", "unknown file type"),
        ((8, 4, 7, 6, "--form", 3, "--out", "x.gif"), "--form", "1 or 2"),
        ((8, 4, 7, 6, "--frames", 1, "--out", "x.gif"), "--frames", "at least 2"),
        ((8, 4, 7, 6, "--coupler", "5", "--out", "x.gif"), "--coupler", "P:DELTA_DEG"),
        (("--out", "x.gif", "--", 8, -4, 7, 6), "r2", "positive"),
    ],
)
def test_cli_bad_input_names_the_field(cli, tmp_path, monkeypatch, args, field, needle):
    monkeypatch.chdir(tmp_path)
    result = cli(*args)
    assert isinstance(result.exception, InputError)
    assert result.exception.field == field and needle in str(result.exception)
    assert not list(tmp_path.iterdir())  # nothing written


def test_model_methods_delegate_to_the_front_end():
    import matplotlib

    matplotlib.use("Agg")
    from machdyn import FourBar, SliderCrank

    fb = FourBar(8, 4, 7, 6, coupler=(5, 0.5))
    m = fb.solve(np.radians(np.arange(0, 360, 10)), omega2=1.0)
    assert m.plot() is not None
    ax = fb.draw(np.radians(30))
    xs = np.concatenate([line.get_xdata() for line in ax.get_lines()])
    assert np.any(np.isclose(xs, 4 * np.cos(np.radians(30))))  # joint A is drawn
    assert fb.plot_coupler_curve() is not None
    assert "<svg" in fb.to_html(n=24)
    sc = SliderCrank(2, 6)
    assert sc.draw(0.3) is not None
    assert sc.solve(np.linspace(0, 6, 20), omega2=1.0).plot() is not None
