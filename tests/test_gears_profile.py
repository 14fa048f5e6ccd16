"""Tooth profiles: involute properties, rack generation, undercut, export and plots.

Checks that do not share the profile code path: finite-difference normals of
the sampled flank against the base circle (the notes: "the normal to the
involute is always tangent to the base circle"), the spacing of successive
flanks along a line of action against p_b (Figure 9-9), the tooth thickness
read off the polygon, and polygon-overlap tests of a meshing pair.
"""

import math
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from machdyn import InputError
from machdyn.gears import Gear, GearPair, min_profile_shift, min_teeth_rack, undercut
from machdyn.gears.profile import (
    cutter_teeth_range,
    default_cutter_teeth,
    default_tip_radius,
    gear_outline,
    mesh_outlines,
    plot_mesh,
)

DEG = math.pi / 180


def _one_flank(out):
    """The upper involute flank of the first tooth (positive polar angle), tip to form."""
    psi = np.arctan2(out.y, out.x)
    sel = (out.segment == "involute") & (psi > 0) & (psi < math.pi / out.teeth)
    return out.x[sel], out.y[sel]


@given(
    teeth=st.integers(12, 80),
    phi_deg=st.sampled_from([14.5, 20.0, 25.0]),
    shift=st.floats(-0.2, 0.6),
)
def test_involute_normal_is_tangent_to_base_circle(teeth, phi_deg, shift):
    g = Gear(teeth, module=1.0, pressure_angle=phi_deg * DEG, profile_shift=shift)
    assume(g.tip_thickness > 0.05)
    out = gear_outline(g, points=400, single_tooth=True)
    x, y = _one_flank(out)
    assert x.size == 400
    # Central differences: tangent t, the normal line through p has distance |p . t| from O.
    tx, ty = x[2:] - x[:-2], y[2:] - y[:-2]
    norm = np.hypot(tx, ty)
    distance = np.abs(x[1:-1] * tx + y[1:-1] * ty) / norm
    assert np.allclose(distance, g.base_radius, rtol=2e-4)


@pytest.mark.parametrize(
    ("teeth", "phi_deg", "shift"), [(20, 20, 0), (33, 14.5, 0.2), (40, 25, 0.4)]
)
def test_successive_flanks_along_line_of_action_are_one_base_pitch_apart(teeth, phi_deg, shift):
    g = Gear(teeth, module=2.0, pressure_angle=phi_deg * DEG, profile_shift=shift)
    out = gear_outline(g, points=300)
    alpha = 0.3  # tangent point on the base circle, any angle
    t_hat = np.array([math.cos(alpha), math.sin(alpha)])
    d = np.array([-math.sin(alpha), math.cos(alpha)])
    p0 = g.base_radius * t_hat
    # Intersections of the line p0 + s d with the polygon edges on involute flanks.
    x, y = out.x, out.y
    x2, y2 = np.roll(x, -1), np.roll(y, -1)
    both = (out.segment == "involute") & (np.roll(out.segment, -1) == "involute")
    ex, ey = x2 - x, y2 - y
    denom = d[0] * ey - d[1] * ex
    ok = both & (np.abs(denom) > 1e-15)
    wx, wy = x - p0[0], y - p0[1]
    s = (wx * ey - wy * ex) / np.where(ok, denom, 1.0)
    u = (wx * d[1] - wy * d[0]) / np.where(ok, denom, 1.0)
    hit = ok & (u >= 0) & (u < 1)
    # Keep the flanks that the line crosses at right angles (one hand of involutes).
    perpendicular = np.abs(ex * d[0] + ey * d[1]) / np.hypot(ex, ey) < 1e-2
    params = np.sort(s[hit & perpendicular & (s > 0)])
    assert params.size >= 2
    assert np.allclose(np.diff(params), g.base_pitch, rtol=1e-6)


def test_tooth_thickness_read_from_polygon():
    g = Gear(24, module=3.0, profile_shift=0.25, thickness_reduction=0.1)
    out = gear_outline(g, points=400, single_tooth=True)
    r = np.hypot(out.x, out.y)
    psi = np.arctan2(out.y, out.x)
    # Crossings of the pitch circle on both flanks, linear interpolation.
    above = r >= g.pitch_radius
    idx = np.flatnonzero(above[1:] != above[:-1])
    assert idx.size == 2
    w = (g.pitch_radius - r[idx]) / (r[idx + 1] - r[idx])
    angles = psi[idx] + w * (psi[idx + 1] - psi[idx])
    arc = (angles.max() - angles.min()) * g.pitch_radius
    expected = 3.0 * (math.pi / 2 + 2 * 0.25 * math.tan(20 * DEG)) - 0.1
    assert arc == pytest.approx(expected, rel=1e-5)


def test_outline_radii_and_segments():
    g = Gear(30, module=1.5)
    out = gear_outline(g, points=50)
    r = np.hypot(out.x, out.y)
    assert r.min() == pytest.approx(g.root_radius, rel=1e-12)
    assert r.max() == pytest.approx(g.addendum_radius, rel=1e-12)
    assert set(out.segment.tolist()) == {"root", "fillet", "involute", "tip"}
    # A closed, simple chain: gaps between neighbours are small against the module.
    gaps = np.hypot(np.diff(np.append(out.x, out.x[0])), np.diff(np.append(out.y, out.y[0])))
    assert gaps.max() < 0.25 * g.module
    # Fillet points stay between the root circle and the start of the involute.
    fil = out.segment == "fillet"
    assert r[fil].min() >= g.root_radius - 1e-12
    assert r[fil].max() <= out.form_radius + 1e-12


def test_fillet_meets_involute_tangentially():
    g = Gear(40, module=1.0)
    out = gear_outline(g, points=2000, single_tooth=True)
    x, y, seg = out.x, out.y, out.segment
    # The junction on the upper flank: last involute point followed by a fillet point.
    j = np.flatnonzero((seg[:-1] == "involute") & (seg[1:] == "fillet"))[-1]
    t_inv = np.array([x[j] - x[j - 1], y[j] - y[j - 1]])
    t_fil = np.array([x[j + 2] - x[j + 1], y[j + 2] - y[j + 1]])
    cos = t_inv @ t_fil / np.linalg.norm(t_inv) / np.linalg.norm(t_fil)
    assert cos > 0.999


@pytest.mark.parametrize("teeth", [8, 10, 12, 14, 16, 18, 20, 25, 40])
def test_generated_undercut_agrees_with_rack_relation(teeth):
    # The profile finds undercut from where the trochoid crosses the involute; the relation
    # (k - x) > N sin^2(phi)/2 comes from the cutter flank passing the interference point.
    # (At N = 17, 20 deg, the undercut is below 1e-5 m and not resolved; not tested here.)
    g = Gear(teeth, module=1.0)
    assert gear_outline(g, points=40).undercut == undercut(teeth, 20 * DEG)


@pytest.mark.parametrize("teeth", [8, 10, 12, 15])
def test_min_profile_shift_puts_the_involute_start_on_the_base_circle(teeth):
    x = min_profile_shift(teeth, 20 * DEG)
    g = Gear(teeth, module=1.0, profile_shift=x)
    out = gear_outline(g, points=40)
    assert not out.undercut
    assert out.form_radius == pytest.approx(g.base_radius, rel=1e-9)


def test_default_tip_radius_is_iso_038():
    assert default_tip_radius(Gear(20, module=1.0)) == pytest.approx(0.38, abs=5e-3)


def test_sharp_cutter_makes_deeper_fillet_start():
    g = Gear(30, module=1.0)
    round_tip = gear_outline(g, points=40)
    sharp = gear_outline(g, points=40, tip_radius=0.0)
    # A sharp-cornered cutter's straight flank reaches deeper: involute starts lower.
    assert sharp.form_radius < round_tip.form_radius


def test_too_large_tip_radius_rejected():
    with pytest.raises(InputError, match="tip_radius"):
        gear_outline(Gear(30, module=1.0), tip_radius=1.0)


def test_extreme_profile_shift_rejected():
    with pytest.raises(InputError, match="profile_shift"):
        gear_outline(Gear(60, module=1.0, profile_shift=0.95))


@pytest.mark.parametrize(("teeth", "cutter"), [(60, None), (40, 24), (120, 30), (300, 25)])
def test_internal_gear_outline_generated_by_shaper_cutter(teeth, cutter):
    ring = Gear(teeth, module=1.0, internal=True)
    out = gear_outline(ring, points=400, single_tooth=True, cutter_teeth=cutter)
    r = np.hypot(out.x, out.y)
    psi = np.arctan2(out.y, out.x)
    assert out.fillet == "trochoid"
    assert r.min() == pytest.approx(ring.addendum_radius, rel=1e-12)
    assert r.max() == pytest.approx(ring.root_radius, rel=1e-12)
    # The fillet ends on the ring's involute, whose tooth half-angle is
    # pi/N - (e/(2R) + inv(phi) - inv(phi_r)).
    fil = (out.segment == "fillet") & (psi > 0)
    space0 = ring.space_width / (2 * ring.pitch_radius) + math.tan(20 * DEG) - 20 * DEG
    r_top = r[fil].min()
    phi_r = math.acos(ring.base_radius / r_top)
    expected = math.pi / teeth - (space0 - (math.tan(phi_r) - phi_r))
    assert psi[fil][np.argmin(r[fil])] == pytest.approx(expected, abs=2e-4 / teeth)
    assert out.form_radius < ring.root_radius
    # Involute and fillet join smoothly: tangents turn by less than 10 degrees per step.
    flank = (psi > 0) & np.isin(out.segment, ["involute", "fillet"])
    t = np.column_stack([np.diff(out.x[flank]), np.diff(out.y[flank])])
    t /= np.linalg.norm(t, axis=1)[:, None]
    assert np.min(np.sum(t[1:] * t[:-1], axis=1)) > math.cos(math.radians(10))


def test_shaper_cutter_bad_input():
    with pytest.raises(InputError, match=r"cutter_teeth: must be from 24 to 32 .* got 35"):
        gear_outline(Gear(40, module=1.0, internal=True), cutter_teeth=35)
    with pytest.raises(InputError, match="got 18: a smaller cutter has pointed teeth"):
        gear_outline(Gear(40, module=1.0, internal=True), cutter_teeth=18)
    with pytest.raises(InputError, match="cutter_teeth: must be a whole number"):
        gear_outline(Gear(40, module=1.0, internal=True), cutter_teeth=25.5)
    with pytest.raises(InputError, match="only an internal gear"):
        cutter_teeth_range(Gear(40, module=1.0))
    with pytest.raises(InputError, match="tip_radius"):
        gear_outline(Gear(40, module=1.0, internal=True), tip_radius=1.2)


def _near_pitch_point(out, x_pitch, window):
    near = np.hypot(out.x - x_pitch, out.y) < window
    return np.column_stack([out.x[near], out.y[near]])


def _overlap(a, b, x_pitch=None, window=np.inf):
    """Whether any vertex of outline ``a`` (near the pitch point) lies inside outline ``b``."""
    from matplotlib.path import Path

    pts = _near_pitch_point(a, x_pitch or 0.0, window)
    return bool(Path(np.column_stack([b.x, b.y])).contains_points(pts).any())


@pytest.mark.parametrize("internal", [False, True])
def test_meshing_pair_does_not_overlap_through_a_pitch(internal):
    p = Gear(18, module=1.0, thickness_reduction=0.02)
    g = Gear(54 if internal else 41, module=1.0, thickness_reduction=0.02, internal=internal)
    pair = GearPair(p, g)
    x_pitch, window = pair.operating_pitch_radii[0], 4.0
    for angle in np.linspace(0, 2 * math.pi / 18, 7):
        pin, gear = mesh_outlines(pair, angle, points=40)
        if internal:
            # The pinion must stay inside the ring's bore (the ring's outline polygon).
            from matplotlib.path import Path

            bore = Path(np.column_stack([gear.x, gear.y]))
            assert bore.contains_points(_near_pitch_point(pin, x_pitch, window)).all()
        else:
            assert not _overlap(pin, gear, x_pitch, window)
            assert not _overlap(gear, pin, x_pitch, window)


def test_meshing_without_backlash_overlaps_when_pushed_together():
    # Control for the overlap test: rotate the gear a little against the pinion.
    pair = GearPair(Gear(18, module=1.0), Gear(41, module=1.0))
    pin, _ = mesh_outlines(pair, 0.0, points=40)
    turned = gear_outline(
        pair.gear, 40, rotation=math.pi + math.pi / 41 + 0.02, center=(pair.center_distance, 0)
    )
    x_pitch = pair.operating_pitch_radii[0]
    assert _overlap(pin, turned, x_pitch, 4.0) or _overlap(turned, pin, x_pitch, 4.0)


def test_exports(tmp_path):
    out = gear_outline(Gear(15, module=2.0, profile_shift=0.2), points=20)
    csv_path = out.to_csv(tmp_path / "g.csv")
    data = np.genfromtxt(csv_path, delimiter=",", skip_header=1, usecols=(0, 1))
    assert np.allclose(data[:, 0], out.x) and np.allclose(data[:, 1], out.y)

    svg = out.to_svg(tmp_path / "g.svg")
    root = ET.fromstring((tmp_path / "g.svg").read_text())
    poly = root.find("{http://www.w3.org/2000/svg}polygon")
    assert svg.startswith("<svg")
    assert len(poly.get("points").split()) == out.x.size

    import ezdxf

    out.to_dxf(tmp_path / "g.dxf")
    doc = ezdxf.readfile(tmp_path / "g.dxf")
    (pl,) = doc.modelspace().query("LWPOLYLINE")
    assert pl.closed and len(pl) == out.x.size

    df = out.to_pandas()
    assert list(df.columns) == ["x", "y", "segment"] and len(df) == out.x.size


def test_plots():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ax = gear_outline(Gear(20, module=1.0)).plot()
    assert ax.patches
    pair = GearPair(Gear(18, module=1.0), Gear(40, module=1.0))
    ax = plot_mesh(pair, pinion_angle=0.1)
    assert "m_p" in ax.get_title()
    assert len(ax.lines) >= 1
    plt.close("all")


@pytest.mark.parametrize("internal", [False, True])
@pytest.mark.parametrize("driver", ["pinion", "gear"])
def test_plot_mesh_marks_first_contact_on_the_driven_tip_circle(internal, driver):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    gear = Gear(72 if internal else 40, module=1.0, internal=internal)
    pair = GearPair(Gear(18, module=1.0), gear, driver=driver)
    ax = plot_mesh(pair, points=8)
    lines = {line.get_label(): line.get_xydata() for line in ax.lines}
    plt.close("all")
    (first,) = lines["first contact"]
    approach, recess = lines[f"approach ({driver} drives)"], lines["recess"]
    gear_centre = np.array([-pair.center_distance if internal else pair.center_distance, 0.0])
    # Norton: contact starts on the driven member's tip circle and ends on the driver's.
    on_circle = {
        "pinion": lambda q: np.hypot(*q) - pair.pinion.addendum_radius,
        "gear": lambda q: np.hypot(*(q - gear_centre)) - gear.addendum_radius,
    }
    driven = "gear" if driver == "pinion" else "pinion"
    assert on_circle[driven](first) == pytest.approx(0.0, abs=1e-9)
    assert on_circle[driver](recess[-1]) == pytest.approx(0.0, abs=1e-9)
    assert approach[0] == pytest.approx(first) and approach[-1] == pytest.approx(recess[0])
    # Both parts meet at the pitch point, on the line of centres.
    assert recess[0][1] == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize(("phi_deg", "rack"), [(14.5, 32), (20.0, 18), (25.0, 12)])
def test_cutter_for_a_very_large_ring_is_the_minimum_pinion_against_a_rack(phi_deg, rack):
    # Norton Table 9-4: a full-depth pinion meshing with a rack without interference needs
    # 32, 18, 12 teeth at 14.5, 20, 25 deg; a ring of many teeth is nearly a rack.
    ring = Gear(20000, module=1.0, internal=True, pressure_angle=phi_deg * DEG)
    assert cutter_teeth_range(ring)[0] == rack
    assert cutter_teeth_range(ring)[0] == min_teeth_rack(phi_deg * DEG)


@pytest.mark.parametrize("teeth", [40, 47, 60, 90, 150])
@pytest.mark.parametrize("system", ["full_depth", "stub"])
def test_fewest_cutter_teeth_is_where_the_cutter_as_a_pinion_stops_interfering(teeth, system):
    # The cutter meshing with the ring at the standard centre distance is an internal pair;
    # GearPair's tip-interference check (its own line-of-action construction) must flip
    # exactly at the smallest accepted cutter. The cutter's tip does not matter for that.
    ring = Gear(teeth, module=2.0, internal=True, system=system)
    low, high = cutter_teeth_range(ring)
    assert high == teeth - 8
    assert low <= default_cutter_teeth(ring) <= high

    def ring_tip_interferes(n_c):
        cutter = Gear(n_c, module=2.0, system=system)
        return GearPair(cutter, ring, ring.pitch_radius - cutter.pitch_radius).interference[0]

    assert not ring_tip_interferes(low)
    assert ring_tip_interferes(low - 1)


def test_no_cutter_fits_a_small_ring():
    # 25 deg full depth, 24 teeth: generating the flanks to the tip needs 17 cutter teeth,
    # the ring allows at most 24 - 8 = 16.
    ring = Gear(24, module=1.0, internal=True, pressure_angle=25 * DEG)
    with pytest.raises(InputError, match="no shaper cutter can cut this 24-tooth ring"):
        cutter_teeth_range(ring)
    with pytest.raises(InputError, match="teeth: no shaper cutter") as raised:
        gear_outline(ring)
    assert raised.value.field == "teeth"  # the ring's, not a cutter count nobody gave


def test_pointed_cutter_teeth_are_refused():
    # 25 deg, a ring of 80 teeth with addendum 1.0 m and a deep dedendum 1.3 m: the cutter
    # carries 1.3 m as its addendum and a tooth as thick as the ring's space, pi m / 2.
    # By hand for N_c = 14: r_c = 7, r_b = 6.34415, tip 8.3, phi_tip = 40.15 deg,
    # inv = 0.14282; the tip half-angle pi/28 + 0.029975 - 0.14282 = -0.0006 < 0: pointed.
    # N_c = 15: r_b = 6.79731, tip 8.8, phi_tip = 39.428 deg, inv = 0.13408;
    # pi/30 + 0.029975 - 0.13408 = +0.0006. Interference alone would allow 12 (the rack's
    # 25 deg minimum, Norton Table 9-4, as the ring's tip circle is the standard one).
    ring = Gear(80, module=1.0, internal=True, pressure_angle=25 * DEG, addendum=1.0,
                dedendum=1.3)  # fmt: skip
    assert cutter_teeth_range(ring)[0] == 15
    standard = Gear(80, module=1.0, internal=True, pressure_angle=25 * DEG)
    assert cutter_teeth_range(standard)[0] == 12
    gear_outline(ring, points=10, cutter_teeth=15)  # cuts
    with pytest.raises(InputError, match="cutter_teeth: must be from 15 to 72"):
        gear_outline(ring, points=10, cutter_teeth=14)


# --------------------------------------------------------------------------
# Profile-shifted internal gears
# --------------------------------------------------------------------------
def _pitch_circle_crossings(out, radius):
    """Polar angles where a one-tooth outline crosses the circle ``radius``."""
    r = np.hypot(out.x, out.y)
    psi = np.arctan2(out.y, out.x)
    above = r >= radius
    idx = np.flatnonzero(above[1:] != above[:-1])
    w = (radius - r[idx]) / (r[idx + 1] - r[idx])
    return psi[idx] + w * (psi[idx + 1] - psi[idx])


@pytest.mark.parametrize("shift", [-0.4, -0.1, 0.0, 0.25, 0.6])
@pytest.mark.parametrize(("teeth", "phi_deg"), [(60, 20.0), (45, 25.0), (120, 14.5)])
def test_internal_tooth_thickness_read_from_polygon(teeth, phi_deg, shift):
    # Sign convention (ISO 21771, KHK, SDP/SI): +x moves the profile x m away from the axis;
    # the ring's pitch-circle tooth is s = m (pi/2 - 2 x tan phi), its tip circle
    # r - (1 - x) m, its root circle r + (1.25 + x) m.
    m, phi = 2.0, phi_deg * DEG
    ring = Gear(teeth, module=m, internal=True, profile_shift=shift, pressure_angle=phi)
    out = gear_outline(ring, points=400, single_tooth=True)
    r_pitch = m * teeth / 2
    angles = _pitch_circle_crossings(out, r_pitch)
    assert angles.size == 2
    arc = (angles.max() - angles.min()) * r_pitch
    assert arc == pytest.approx(m * (math.pi / 2 - 2 * shift * math.tan(phi)), rel=1e-5)
    r = np.hypot(out.x, out.y)
    assert r.min() == pytest.approx(r_pitch - (1 - shift) * m, rel=1e-12)
    assert r.max() == pytest.approx(r_pitch + (1.25 + shift) * m, rel=1e-12)


def test_shifted_ring_meshes_without_overlap_and_jams_when_turned():
    # A shifted pinion in a shifted ring at the tight-mesh distance of the involute relation:
    # with a little thinning the pinion stays in the ring's bore through a whole pitch, and
    # without it, turning the ring 0.01 rad against the pinion makes them overlap. A wrong
    # sign of the ring's shift would misplace the flanks by 2 x m tan(phi) = 0.36 mm.
    from matplotlib.path import Path

    p = Gear(18, module=1.0, profile_shift=0.3, thickness_reduction=0.02)
    ring = Gear(54, module=1.0, internal=True, profile_shift=0.5, thickness_reduction=0.02)
    pair = GearPair(p, ring)
    assert pair.center_distance != pytest.approx(18.0)  # not the standard distance
    x_pitch, window = pair.operating_pitch_radii[0], 4.0
    for angle in np.linspace(0, 2 * math.pi / 18, 7):
        pin, gear = mesh_outlines(pair, angle, points=40)
        bore = Path(np.column_stack([gear.x, gear.y]))
        assert bore.contains_points(_near_pitch_point(pin, x_pitch, window)).all()
    tight = GearPair(Gear(18, module=1.0, profile_shift=0.3),
                     Gear(54, module=1.0, internal=True, profile_shift=0.5))  # fmt: skip
    pin, _ = mesh_outlines(tight, 0.0, points=40)
    for turn in (0.01, -0.01):
        turned = gear_outline(
            tight.gear, 40, rotation=math.pi / 54 + turn, center=(-tight.center_distance, 0)
        )
        bore = Path(np.column_stack([turned.x, turned.y]))
        assert not bore.contains_points(_near_pitch_point(pin, x_pitch, window)).all()


def test_internal_shift_bad_input():
    with pytest.raises(InputError, match="profile_shift: 2 closes the spaces"):
        Gear(60, module=1.0, internal=True, profile_shift=2.0)
    with pytest.raises(InputError, match="tip circle inside its base circle"):
        Gear(40, module=1.0, internal=True, profile_shift=-0.4)


def test_an_external_gear_refuses_a_shaper_cutter_count():
    with pytest.raises(InputError, match="cutter_teeth: only an internal gear is cut by a shaper"):
        gear_outline(Gear(20, module=1.0), cutter_teeth=18)
