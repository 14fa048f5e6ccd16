"""Global interference of a cam surface: the sampled outline crossing itself.

The fast crossing search (grid buckets, orientation tests) is checked against a
brute-force test of every pair of segments written here with the parametric
line-line formula, against closed-form curves, and against what the follower
itself does: a surface point on a loop is cut away by some roller position (or
pokes through some face position), a point of the real surface is not.
"""

import math

import numpy as np
import pytest

from machdyn import InputError
from machdyn.cams import (
    CamProgram,
    OscillatingRoller,
    Segment,
    TranslatingFlatFace,
    TranslatingRoller,
)
from machdyn.cams import _interference as interference
from machdyn.cams._interference import loop_pieces, polyline_crossings, winding_number
from machdyn.cams.geometry import surface_self_intersection

deg = np.radians


def brute_force_crossings(z):
    """Every pair of non-adjacent segments of the closed polyline, solved as two lines.

    a_i + t e_i = a_j + u e_j; a crossing when 0 < t < 1 and 0 < u < 1.
    Returns sorted (tau_i, tau_j) pairs (vertex units) and the points.
    """
    n = z.size
    a, e = z, np.roll(z, -1) - z
    i, j = np.triu_indices(n, k=2)
    keep = ~((i == 0) & (j == n - 1))
    i, j = i[keep], j[keep]
    gap = a[j] - a[i]
    den = (np.conj(e[i]) * e[j]).imag
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (np.conj(gap) * e[j]).imag / den
        u = (np.conj(gap) * e[i]).imag / den
    hit = (den != 0) & (t > 0) & (t < 1) & (u > 0) & (u < 1)
    tau = np.stack((i[hit] + t[hit], j[hit] + u[hit]), axis=1)
    order = np.argsort(tau[:, 0])
    return tau[order], (a[i] + t * e[i])[hit][order]


def double_dwell_example():
    # docs/cams.md example: cycloidal rise and modified-sine fall of 1 over 60°, dwells of 120°.
    return CamProgram(
        [
            Segment("rise", deg(60), 1.0, "cycloidal"),
            Segment("dwell", deg(120)),
            Segment("fall", deg(60), 1.0, "modified_sine"),
            Segment("dwell", deg(120)),
        ]
    )


def steep(rise=30):
    return CamProgram.double_dwell(1.0, deg(rise), deg(rise))


# --------------------------------------------------------------------------
# The crossing search on curves with known crossings
# --------------------------------------------------------------------------


def test_figure_of_eight_crosses_once_at_the_centre():
    # Lissajous figure of eight x = sin 2t, y = sin t: one crossing, at the origin,
    # passed at t = 0 and t = π.
    n = 997  # no vertex at the origin
    t = 2 * np.pi * (np.arange(n) + 0.3) / n
    z = np.sin(2 * t) + 1j * np.sin(t)
    tau_a, tau_b, point = polyline_crossings(z)
    assert point.size == 1
    assert abs(point[0]) < 1e-4
    # τ = k + fraction: t(τ) = 2π(τ + 0.3)/n.
    t_at = 2 * np.pi * (np.array([tau_a[0], tau_b[0]]) + 0.3) / n
    np.testing.assert_allclose(t_at, [np.pi, 2 * np.pi], atol=2 * np.pi / n)


def test_limacon_inner_loop_is_a_loop_though_it_turns_the_same_way(monkeypatch):
    # Limaçon r = 1 + 2 cos t: it passes the origin at t = 2π/3 and 4π/3; between them
    # r < 0 traces the inner loop, wound the same way, so the winding number inside it is 2.
    n = 1000
    t = 2 * np.pi * np.arange(n) / n
    z = (1 + 2 * np.cos(t)) * np.exp(1j * t)
    tau_a, tau_b, point = polyline_crossings(z)
    assert point.size == 1
    assert abs(point[0]) < 1e-4  # the chords miss the curve by O(step²)
    np.testing.assert_allclose(
        2 * np.pi * np.array([tau_a[0], tau_b[0]]) / n, [2 * np.pi / 3, 4 * np.pi / 3], atol=1e-4
    )
    assert winding_number(z, np.array([0.5 + 0j, 2.0 + 0j, 5.0 + 0j])).tolist() == [2, 1, 0]
    monkeypatch.setattr(interference, "_BLOCK", 1)  # one point per block: the same answer
    assert winding_number(z, np.array([0.5 + 0j, 2.0 + 0j, 5.0 + 0j])).tolist() == [2, 1, 0]
    start, end, in_loop = loop_pieces(z, tau_a, tau_b)
    [(lo, hi)] = [(a, b) for a, b, bad in zip(start, end, in_loop, strict=True) if bad]
    np.testing.assert_allclose([lo, hi], [n / 3, 2 * n / 3], atol=0.1)
    loops = surface_self_intersection(t, z)
    inner = (t > 2 * np.pi / 3) & (t < 4 * np.pi / 3)
    np.testing.assert_array_equal(loops.in_loop, inner)


def test_simple_curves_do_not_cross():
    n = 3600
    t = 2 * np.pi * np.arange(n) / n
    ellipse = 3 * np.cos(t) - 1j * np.sin(t)  # clockwise, as cam outlines run
    assert polyline_crossings(ellipse)[0].size == 0
    loops = surface_self_intersection(t, ellipse)
    assert not loops.found
    assert loops.ranges() == []
    assert not loops.in_loop.any()
    assert loops.theta_crossing.shape == (0, 2)


def test_fast_search_agrees_with_brute_force_on_random_polygons(rng):
    # Random closed polylines cross themselves many times, at every angle and scale.
    for n in (5, 12, 40, 150):
        for _ in range(5):
            z = rng.normal(size=n) + 1j * rng.normal(size=n)
            z *= 10.0 ** rng.uniform(-3, 3)
            tau_a, tau_b, point = polyline_crossings(z)
            tau, expected = brute_force_crossings(z)
            assert point.size == len(tau)
            np.testing.assert_allclose(np.stack((tau_a, tau_b), axis=1), tau, atol=1e-9)
            np.testing.assert_allclose(point, expected, rtol=1e-9, atol=1e-12 * np.abs(z).max())


def test_a_few_long_segments_among_many_short_ones(rng):
    # a finely sampled wavy arc closed by a few long chords that cut across it: the long
    # segments are paired with every other one instead of filling a huge grid
    t = np.linspace(0.0, np.radians(40.0), 1500, endpoint=False)
    arc = np.exp(1j * t) * (1.0 + 0.02 * np.sin(60 * t))
    chords = np.array([0.3 + 2.0j, -1.5 + 0.1j, 2.0 + 0.6j, 0.97 + 0.05j])
    for z in (np.r_[arc, chords], np.r_[arc, chords] * (0.3 + 4j)):
        tau_a, tau_b, point = polyline_crossings(z)
        tau, expected = brute_force_crossings(z)
        assert len(tau) > 0 and point.size == len(tau)
        np.testing.assert_allclose(np.stack((tau_a, tau_b), axis=1), tau, atol=1e-9)
        np.testing.assert_allclose(point, expected, rtol=1e-9, atol=1e-12 * np.abs(z).max())


def test_repeated_vertices_and_a_crossing_through_a_vertex():
    # A bow-tie whose crossing is a vertex of one pass; repeated vertices in the other.
    z = np.array([0, 0, 2 + 2j, 2, 1 + 1j, 0 + 2j, 0 + 2j])
    # Path: 0→2+2j (through 1+1j), →2, →1+1j (vertex on the first segment), →2j, →0.
    tau_a, tau_b, point = polyline_crossings(z)
    assert point.size == 1
    assert point[0] == pytest.approx(1 + 1j)
    # Without the vertex exactly on the line: a plain crossing, the same count.
    z2 = z.copy()
    z2[4] = 1.0 + 1.01j
    assert polyline_crossings(z2)[2].size == 1
    # Two corners touching without crossing (an hourglass of two triangles): the touch
    # counts an even number of times and no piece is a loop (both triangles are solid).
    touch = np.array([0, 2, 1 + 1j, 2 + 2j, 2j, 1 + 1j])
    tau_a, tau_b, point = polyline_crossings(touch)
    assert point.size % 2 == 0
    assert not loop_pieces(touch, tau_a, tau_b)[2].any()


def test_crossings_do_not_depend_on_rotation_or_starting_sample(rng):
    cam = TranslatingRoller(1.5, 1.0).profile(steep(), n=720)
    base = surface_self_intersection(cam.theta, cam.surface)
    rotated = surface_self_intersection(cam.theta, cam.surface * np.exp(1j * 0.7) + 3 - 2j)
    np.testing.assert_allclose(rotated.theta_crossing, base.theta_crossing, atol=1e-9)
    np.testing.assert_array_equal(rotated.in_loop, base.in_loop)
    shift = 100
    rolled = surface_self_intersection(cam.theta, np.roll(cam.surface, -shift))
    back = np.mod(rolled.theta_crossing + cam.theta[shift], 2 * np.pi)
    np.testing.assert_allclose(np.sort(back, axis=None), np.sort(base.theta_crossing, axis=None))
    np.testing.assert_array_equal(np.roll(rolled.in_loop, shift), base.in_loop)


# --------------------------------------------------------------------------
# Cams
# --------------------------------------------------------------------------


def _cut_by_a_roller(cam):
    """Depth by which some roller position (on a fine pitch curve) overlaps each surface point."""
    follower = TranslatingRoller(cam.prime_radius, cam.roller_radius)
    fine = follower.profile(steep(), n=7200)
    gap = np.abs(cam.surface[:, None] - fine.pitch[None, :]).min(axis=1)
    return cam.roller_radius - gap


def test_roller_larger_than_the_convex_radius_loops_where_the_local_test_fires():
    # Rp = 1.5, Rf = 1.0 on 30° cycloidal rise and fall: min convex ρ_pitch < Rf.
    cam = TranslatingRoller(1.5, 1.0).profile(steep(), n=720)
    assert cam.is_undercut and cam.rho_min < 1.0
    loops = cam.self_intersection
    assert loops.found and cam.has_surface_loop
    # One swallowtail in the rise, one in the fall, each around the local undercut range.
    ranges = cam.surface_loop_ranges()
    local = cam.undercut_ranges()
    assert len(ranges) == len(local) == 2
    for (lo, hi), (a, b) in zip(ranges, local, strict=True):
        assert lo < a <= b < hi
        assert hi - lo < deg(45)
    # The crossings lie in the rise (0–30°) and the fall (150–180°) plus the loops' reach.
    assert np.all((loops.theta_crossing < deg(50)) | (loops.theta_crossing > deg(150)))
    # What the roller does: it cuts every loop sample, and leaves every other one.
    depth = _cut_by_a_roller(cam)
    ends = np.concatenate([[lo, hi] for lo, hi in ranges])
    away = np.abs(cam.theta[:, None] - ends[None, :]).min(axis=1) > deg(1.5)
    assert np.all(depth[cam.surface_loop & away] > 1e-3)
    assert np.all(depth[~cam.surface_loop & away] < 1e-6)
    # Reported in the design check, with the angles.
    [check] = [c for c in cam.checks() if c.name == "undercut"]
    assert not check.passed
    assert check.detail.startswith("undercut at θ = ")
    lo, hi = np.degrees(ranges[0])
    assert f"loops cut away θ = {lo:.1f}°–{hi:.1f}°" in check.detail


def test_coarse_sampling_the_global_test_finds_a_loop_the_local_test_misses():
    # 40° rises, Rp = 1.5, Rf = 0.525 sampled every 5°: no sample has ρ_pitch < Rf,
    # but the polyline through the samples still folds over.
    follower = TranslatingRoller(1.5, 0.525)
    coarse = follower.profile(steep(40), n=72)
    assert not coarse.is_undercut
    assert coarse.has_surface_loop
    [check] = [c for c in coarse.checks() if c.name == "undercut"]
    assert not check.passed
    assert "no sample fails the local ρ test" in check.detail
    # Sampled finely, the local test fires inside the loops found on the coarse polyline.
    fine = follower.profile(steep(40), n=7200)
    for (a, b), (lo, hi) in zip(fine.undercut_ranges(), coarse.surface_loop_ranges(), strict=True):
        assert lo < a <= b < hi


def test_well_designed_double_dwell_cams_have_no_loop():
    program = double_dwell_example()
    roller = TranslatingRoller(prime_radius=3.0, roller_radius=0.5, eccentricity=0.2)
    rocker = OscillatingRoller(2.0, 0.3, pivot_distance=4.0, arm_length=3.5)
    for cam in (
        roller.profile(program),
        TranslatingFlatFace(base_radius=8.0).profile(program),
        rocker.profile(CamProgram.double_dwell(deg(15), deg(90), deg(90))),
    ):
        assert not cam.has_surface_loop
        assert not cam.surface_loop.any()
        assert cam.surface_loop_ranges() == []
        [check] = [c for c in cam.checks() if c.name == "undercut"]
        assert check.passed
    # The brute force agrees on a coarse version of the same cam.
    coarse = roller.profile(program, n=360)
    assert brute_force_crossings(coarse.surface)[1].size == 0


@pytest.mark.parametrize(
    "make",
    [
        lambda: TranslatingRoller(1.5, 1.0, eccentricity=0.3).profile(steep(), n=240),
        lambda: TranslatingFlatFace(2.0).profile(steep(), n=240),
        lambda: OscillatingRoller(2.0, 1.2, 4.0, 3.5).profile(
            CamProgram.double_dwell(deg(25), deg(30), deg(30)), n=240
        ),
    ],
    ids=["roller", "flat-face", "oscillating"],
)
def test_cam_crossings_agree_with_brute_force_on_coarse_profiles(make):
    cam = make()
    found = cam.self_intersection
    tau, points = brute_force_crossings(cam.surface)
    assert found.found and points.size == found.point.size
    np.testing.assert_allclose(found.point, points, atol=1e-12)
    step = 2 * np.pi / cam.theta.size
    np.testing.assert_allclose(found.theta_crossing, np.mod(tau * step, 2 * np.pi), atol=1e-12)


def test_flat_face_loops_are_where_the_cam_pokes_through_a_face_position():
    # Rb = 2 on 30° cycloidal rises: Rb + s + a < 0 in the rise and fall.
    cam = TranslatingFlatFace(2.0).profile(steep(), n=720)
    assert cam.is_undercut and cam.has_surface_loop
    for (lo, hi), (a, b) in zip(cam.surface_loop_ranges(), cam.undercut_ranges(), strict=True):
        assert lo < a <= b < hi
    # Height of each surface point above the lowest face it meets (cam frame normals).
    normal = 1j * np.exp(-1j * cam.theta)
    height = (cam.surface[:, None] * np.conj(normal[None, :])).real - (2.0 + cam.s)[None, :]
    poke = height.max(axis=1)
    ends = np.concatenate(cam.surface_loop_ranges())
    away = np.abs(cam.theta[:, None] - ends[None, :]).min(axis=1) > deg(1.5)
    assert np.all(poke[cam.surface_loop & away] > 1e-3)
    assert np.all(poke[~cam.surface_loop & away] < 1e-9)


def test_flat_face_width_from_the_surface_itself():
    # Norton eq. 8.28: the contact point sits v - ε along the face; a cycloidal rise and
    # fall take v from -2h/β to 2h/β, so the least width is 4h/β. Found here from the
    # sampled surface alone: at each angle, the surface point that reaches the face.
    eps = 0.2
    cam = TranslatingFlatFace(8.0, eccentricity=eps).profile(steep(60), n=3600)
    normal = 1j * np.exp(-1j * cam.theta)
    contact = cam.surface[np.argmax((cam.surface[None, :] * np.conj(normal[:, None])).real, axis=1)]
    along_face = (contact * np.exp(1j * cam.theta)).real - eps  # fixed frame x from the axis
    step = 2 * np.pi / 3600
    peak = 2.0 / deg(60)
    np.testing.assert_allclose(cam.face_position, along_face, atol=peak * step * 2)
    assert cam.face_width == pytest.approx(np.ptp(along_face), abs=peak * step * 2)
    assert cam.face_width == pytest.approx(4 / deg(60), rel=1e-5)  # closed form 4h/β


def test_profile_tables_carry_the_loop_flag(tmp_path):
    cam = TranslatingRoller(1.5, 1.0).profile(steep(), n=72)
    frame = cam.to_pandas()
    np.testing.assert_array_equal(frame["surface_loop"].to_numpy(), cam.surface_loop)
    path = tmp_path / "cam.csv"
    cam.to_csv(path)
    header = path.read_text().splitlines()[0].split(",")
    assert header[-2:] == ["undercut", "surface_loop"]


def test_self_intersection_is_computed_once_per_profile_and_tabulated():
    cam = TranslatingRoller(3.0, 0.5).profile(double_dwell_example(), n=360)
    assert cam.self_intersection is cam.self_intersection
    undercut = TranslatingRoller(1.5, 1.0).profile(steep(), n=720)
    table = undercut.self_intersection.to_pandas()
    assert len(table) == 2
    np.testing.assert_allclose(table["theta_b_deg"], np.degrees(table["theta_b"]))
    # Each tabulated crossing lies on the surface polyline at both of its angles.
    for angle in ("theta_a", "theta_b"):
        at = np.interp(
            table[angle],
            np.append(undercut.theta, 2 * np.pi),
            np.append(undercut.surface, undercut.surface[0]),
        )
        np.testing.assert_allclose(at, table["x"] + 1j * table["y"], atol=1e-12)


@pytest.mark.parametrize(
    ("theta", "surface", "field"),
    [
        (np.linspace(0, 6, 5), np.zeros(4, complex), "surface"),
        (np.linspace(0, 6, 5), np.array([0, 1, np.nan, 1j, 2j]), "surface"),
        (np.array([0.0, 2.0, 1.0, 3.0]), np.array([0, 1, 1 + 1j, 1j]), "theta"),
        (np.linspace(0, 7, 4), np.array([0, 1, 1 + 1j, 1j]), "theta"),
        (np.array([0.0, np.inf, 1.0, 3.0]), np.array([0, 1, 1 + 1j, 1j]), "theta"),
        (np.array([0.0, 1.0]), np.array([0, 1j]), "theta"),
        (np.array([]), np.array([], complex), "theta"),
    ],
    ids=["shapes", "nan-point", "not-increasing", "more-than-a-turn", "inf-angle", "two", "none"],
)
def test_bad_input(theta, surface, field):
    with pytest.raises(InputError) as info:
        surface_self_intersection(theta, surface)
    assert info.value.field == field


def test_degenerate_outlines():
    # Too few distinct points to cross, and a point repeated: no crossing, no error.
    assert not surface_self_intersection([0.0, 1.0, 2.0], [0, 1, 1j]).found
    assert not surface_self_intersection(np.linspace(0, 6, 6), np.full(6, 1 + 1j)).found
    assert math.isclose(winding_number(np.array([0, 1, 1j]), np.array([5.0]))[0], 0)


def test_random_cams_agree_with_brute_force(rng):
    # Seeded random designs, many of them undercut: the same crossings, found both ways.
    laws = ["cycloidal", "modified_sine", "poly345", "simple_harmonic"]
    found = 0
    for _ in range(24):
        rise = rng.uniform(20, 90)
        program = CamProgram.double_dwell(
            rng.uniform(0.3, 1.5), deg(rise), deg(rng.uniform(20, 90)), law=rng.choice(laws)
        )
        rp = rng.uniform(1.0, 3.0)
        follower = (
            TranslatingRoller(rp, rng.uniform(0.1, 0.9) * rp, rng.uniform(-0.4, 0.4) * rp)
            if rng.random() < 0.7
            else TranslatingFlatFace(rp)
        )
        cam = follower.profile(program, n=int(rng.integers(60, 300)))
        tau, points = brute_force_crossings(cam.surface)
        loops = cam.self_intersection
        assert loops.point.size == points.size
        np.testing.assert_allclose(loops.point, points, atol=1e-12)
        step = 2 * np.pi / cam.theta.size
        np.testing.assert_allclose(loops.theta_crossing, np.mod(tau * step, 2 * np.pi), atol=1e-9)
        found += points.size > 0
    assert 4 <= found <= 20  # the sample holds cams with loops and without


def test_the_plot_marks_loops_and_a_passing_cam_has_no_refusal():
    import matplotlib

    matplotlib.use("Agg")
    from machdyn.cams.io import undercut_refusal

    coarse = TranslatingRoller(1.5, 0.525).profile(steep(40), n=72)  # global test only
    ax = coarse.plot()
    labels = [line.get_label() for line in ax.get_lines()]
    assert "surface loop" in labels and "undercut" not in labels
    assert "its outline crosses itself" in undercut_refusal(coarse)
    good = TranslatingRoller(prime_radius=3.0, roller_radius=0.5).profile(double_dwell_example())
    with pytest.raises(ValueError, match="passes both undercut tests"):
        undercut_refusal(good)
