"""Motion generation: the notes' three-position tables, round trips, defects, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest

from machdyn.errors import AssemblyError, InputError
from machdyn.fourbar import FourBar
from machdyn.synthesis import (
    circumcentre,
    driving_dyad,
    rotopole_link,
    three_position,
    three_position_fixed_pivots,
    two_position,
)

# The notes' three-position table (end of the main course notes, "c1 .. d3").
C = [0 + 5.086j, 2.019 + 3.181j, 3.933 + 4.051j]
D = [0.741 + 2.703j, 4.428 + 2.529j, 6.304 + 4.83j]


def _line_intersection(m1, b1, m2, b2):
    """y = m x + b lines, as the notes intersect them (not the library's code path)."""
    x = (b2 - b1) / (m1 - m2)
    return x, m1 * x + b1


# --------------------------------------------------------------------------------------
# the notes' three-position table


def test_notes_c_pivot_and_link2_to_printed_precision():
    s = three_position(C, D)
    assert round(s.O2.real, 3) == 2.178
    assert round(s.O2.imag, 3) == 5.372
    assert round(s.r2, 3) == 2.197


def test_notes_d_pivot_corrected():
    """The notes' D pivot (2.740, 5.911) carries an arithmetic slip.

    Its own table gives the bisectors of D1D2 (slope 21.190, intercept −52.149) and
    D2D3 (slope −0.815, intercept 8.054); the written equation uses −8.82 for the second
    slope, and its x = 2.740 (instead of 2.736) put into the steep first line (slope 21.19)
    turns an x error of 0.004 into a y error of 0.087. Intersecting the table's own lines
    gives (2.736, 5.824); so link 4 is 3.704 (not 3.780) and the ground 0.718 (not 0.779).
    The coupler |C1D1| = 2.496 does not depend on the pivots and agrees with the notes.
    """
    x, y = _line_intersection(21.190, -52.149, -0.815, 8.054)
    s = three_position(C, D)
    # the table's slopes and intercepts are rounded to 3 decimals: agree to ~2e-3
    assert abs(s.O4.real - x) < 2e-3
    assert abs(s.O4.imag - y) < 2e-3
    assert round(s.O4.real, 3) == 2.736
    assert round(s.O4.imag, 3) == 5.824
    # O4 is equidistant from D1, D2, D3 (the definition of the pivot)
    dist = [abs(s.O4 - d) for d in D]
    assert max(dist) - min(dist) < 1e-9
    assert round(s.r4, 3) == 3.704
    assert round(s.r3, 3) == 2.496  # as printed in the notes
    assert round(s.r1, 3) == 0.718
    # and the notes' own (slipped) pivot is 0.087 away in y, as explained above
    assert abs(s.O4.imag - 5.911) > 0.08


def test_notes_c_lines_from_their_table():
    """The C pivot also follows from the notes' printed bisector lines."""
    x, y = _line_intersection(1.060, 3.064, -2.200, 10.163)
    s = three_position(C, D)
    assert abs(s.O2 - complex(x, y)) < 2e-3


def test_notes_three_position_linkage_does_the_job():
    s = three_position(C, D)
    assert s.ok, s.defects
    # the placed linkage, driven to each position's theta2, puts C and D where asked
    _A, B, P, ok = s.linkage.pose(s.theta2)
    assert ok.all()
    np.testing.assert_allclose(P, C, atol=1e-3)  # the table has 3 decimals
    np.testing.assert_allclose(B, D, atol=1e-3)
    # ground pivots and angle of the placement
    assert abs(s.linkage.O4 - s.O4) < 1e-12
    assert math.isclose(s.theta1, math.atan2((s.O4 - s.O2).imag, (s.O4 - s.O2).real))
    assert 0 < s.mu_min <= math.pi / 2


# --------------------------------------------------------------------------------------
# the notes' inversion table (O2, O2', O2'', O4, O4', O4'')

NOTES_O2, NOTES_O4 = 0.995 + 0j, 5.298 + 0j
NOTES_O2P, NOTES_O2PP = -3.1405 + 3.9436j, 5.124 + 0.929j
NOTES_O4P, NOTES_O4PP = -0.927 + 0.612j, 8.4205 + 3.195j


def _carry_relation(point, frm, to):
    """Copy the position of `point` relative to C_frm D_frm onto C_to D_to (angles via atan2)."""
    c0, d0, c1, d1 = C[frm], D[frm], C[to], D[to]
    turn = math.atan2((d1 - c1).imag, (d1 - c1).real) - math.atan2((d0 - c0).imag, (d0 - c0).real)
    return c1 + (point - c0) * complex(math.cos(turn), math.sin(turn))


def test_notes_inversion_table_circle_centres():
    """The notes' centres (1.996, 5.190) and (2.711, 5.652) of their own points."""
    g = complex(circumcentre(NOTES_O2P, NOTES_O2, NOTES_O2PP))
    h = complex(circumcentre(NOTES_O4P, NOTES_O4, NOTES_O4PP))
    assert (round(g.real, 3), round(g.imag, 3)) == (1.996, 5.190)
    assert (round(h.real, 3), round(h.imag, 3)) == (2.711, 5.652)


def test_notes_inversion_table_is_not_self_consistent():
    """Why the notes' inversion numbers cannot all be trusted.

    * O4' is right: O4 placed relative to C1D1 as it is to C2D2 (Norton Ex. 3-7).
    * O4'' is O4 carried the other way, from C2D2 onto C3D3, not from C3D3 onto C1D1.
    * O2' and O2'' are 4.000 from O4' and O4'', but |O2 O4| = 4.303: an inversion is a rigid
      motion, so they were made from another O2, about (1.299, −0.082).
    * the lengths "coupler 4.303, ground 0.851" are those of the inverted linkage: in the
      real one the ground is |O2O4| = 4.303.
    """
    inv = three_position_fixed_pivots(C, D, NOTES_O2, NOTES_O4, reference=0)
    assert abs(inv.inverted_O4[1] - NOTES_O4P) < 2e-3
    assert abs(_carry_relation(NOTES_O4, 1, 0) - NOTES_O4P) < 2e-3
    assert abs(inv.inverted_O4[2] - NOTES_O4PP) > 1.0
    assert abs(_carry_relation(NOTES_O4, 1, 2) - NOTES_O4PP) < 2e-3
    assert round(abs(NOTES_O2P - NOTES_O4P), 3) == 4.000
    assert round(abs(NOTES_O2PP - NOTES_O4PP), 3) == 4.000
    assert round(abs(NOTES_O2 - NOTES_O4), 3) == 4.303
    assert round(inv.r1, 3) == 4.303


@pytest.mark.parametrize("reference", [0, 1, 2])
def test_inversion_moves_through_the_positions(reference):
    """The correct inverted solution: fixed pivots as given, rigid coupler, constant cranks."""
    inv = three_position_fixed_pivots(C, D, NOTES_O2, NOTES_O4, reference=reference)
    assert inv.O2 == NOTES_O2
    assert abs(inv.O4 - NOTES_O4) < 1e-12
    for pivots, fixed in ((inv.A, NOTES_O2), (inv.B, NOTES_O4)):
        radii = np.abs(pivots - fixed)
        assert np.ptp(radii) < 1e-9 * radii.max()
    # A and B ride on the coupler: their distances to C and D are the same in each position
    for pivots in (inv.A, inv.B):
        for pts in (C, D):
            d = np.abs(pivots - np.asarray(pts))
            assert np.ptp(d) < 5e-4  # the table's |CD| varies by 1.4e-4
    # and the answer does not depend on the reference position
    other = three_position_fixed_pivots(C, D, NOTES_O2, NOTES_O4, reference=(reference + 1) % 3)
    np.testing.assert_allclose(inv.A, other.A, atol=2e-3)


# --------------------------------------------------------------------------------------
# round trips from known linkages (poses from FourBar.solve, a separate code path)


def _poses(fb, theta2, form, O2=1.5 - 0.5j, theta1=0.4):
    m = fb.solve(np.asarray(theta2), form=form)
    place = lambda z: O2 + z * np.exp(1j * theta1)  # noqa: E731
    P = None if m.coupler is None else place(m.coupler)
    return place(m.A), place(m.B), P, O2, O2 + fb.r1 * np.exp(1j * theta1)


def test_round_trip_moving_pivots_give_back_the_fixed_pivots():
    fb = FourBar(8, 4, 7, 6, coupler=(3.0, 0.5))
    A, B, _P, O2, O4 = _poses(fb, np.radians([20, 70, 130]), form=1)
    s = three_position(A, B)
    assert abs(s.O2 - O2) < 1e-9 and abs(s.O4 - O4) < 1e-9
    np.testing.assert_allclose(s.linkage.lengths, fb.lengths, rtol=1e-9)
    assert s.ok and s.direction == 1


def test_round_trip_with_coupler_line_and_chosen_moving_pivots():
    fb = FourBar(8, 4, 7, 6, coupler=(3.0, 0.5))
    theta2 = np.radians([250, 200, 150])  # clockwise
    A, B, P, O2, O4 = _poses(fb, theta2, form=2)
    s = three_position(P, A, A=A[0], B=B[0])  # line from the coupler point to A
    assert abs(s.O2 - O2) < 1e-9 and abs(s.O4 - O4) < 1e-9
    assert s.ok and s.direction == -1
    inv = three_position_fixed_pivots(P, A, O2, O4, reference=2)
    np.testing.assert_allclose(inv.A, A, atol=1e-9)
    np.testing.assert_allclose(inv.B, B, atol=1e-9)


def test_round_trip_random_crank_rockers(rng):
    for _ in range(20):
        a = rng.uniform(0.5, 1.0)
        d, b, c = rng.uniform(2.0, 3.0, size=3)
        fb = FourBar(d, a, b, c)
        if fb.barker_class != "GCRR":
            continue
        theta2 = np.sort(rng.uniform(0, 2 * np.pi, 3))
        A, B, _, O2, O4 = _poses(fb, theta2, form=1, O2=complex(*rng.normal(size=2)))
        s = three_position(A, B)
        assert abs(s.O2 - O2) < 1e-7 and abs(s.O4 - O4) < 1e-7
        assert s.ok


# --------------------------------------------------------------------------------------
# defects


def test_circuit_defect_on_a_crank_rocker():
    fb = FourBar(8, 4, 7, 6)
    A1, B1, *_ = _poses(fb, np.radians([20, 130]), form=1)
    A2, B2, *_ = _poses(fb, np.radians([70]), form=2)
    A = np.array([A1[0], A2[0], A1[1]])
    B = np.array([B1[0], B2[0], B1[1]])
    s = three_position(A, B)
    assert not s.ok
    assert any(d.startswith("circuit defect") for d in s.defects)
    with pytest.raises(AssemblyError, match="circuit defect"):
        three_position(A, B, strict=True)


def test_branch_defect_on_a_non_grashof_linkage():
    fb = FourBar(3, 5, 4, 7)  # RRR4: one circuit, two branches
    A1, B1, *_ = _poses(fb, np.radians([160, 200]), form=1)
    A2, B2, *_ = _poses(fb, np.radians([180]), form=2)
    s = three_position([A1[0], A2[0], A1[1]], [B1[0], B2[0], B1[1]])
    assert any(d.startswith("branch defect") for d in s.defects)


def test_order_defect_on_a_rocker_input():
    fb = FourBar(3, 5, 4, 7)  # input link rocks over [33.6°, 326.4°]
    A, B, *_ = _poses(fb, np.radians([160, 225, 185]), form=1)
    s = three_position(A, B)
    assert any(d.startswith("order defect") for d in s.defects)
    good = three_position(*_poses(fb, np.radians([160, 185, 225]), form=1)[:2])
    assert good.ok and good.direction == 1


# --------------------------------------------------------------------------------------
# two positions, rotopole, driving dyad


@pytest.mark.parametrize(("s2", "s4"), [(3.0, 4.0), (-2.0, 5.0), (10.0, -1.0)])
def test_two_position_pivots_on_the_bisectors(s2, s4):
    c = [0 + 5.086j, 2.019 + 3.181j]
    d = [0.741 + 2.703j, 4.428 + 2.529j]
    s = two_position(c, d, s2=s2, s4=s4)
    assert abs(abs(s.O2 - c[0]) - abs(s.O2 - c[1])) < 1e-12
    assert abs(abs(s.O4 - d[0]) - abs(s.O4 - d[1])) < 1e-12
    assert math.isclose(abs(s.O2 - 0.5 * (c[0] + c[1])), abs(s2))
    if s.ok:
        _A, _B, P, _ok = s.linkage.pose(s.theta2)
        np.testing.assert_allclose(P, c, atol=1e-9)


def test_rotopole_link_carries_c1d1_to_c2d2():
    c = [0 + 5.086j, 2.019 + 3.181j]
    d = [0.741 + 2.703j, 4.428 + 2.529j]
    link = rotopole_link(c, d)
    turn = complex(math.cos(link.rotation), math.sin(link.rotation))
    assert abs(link.pole + (c[0] - link.pole) * turn - c[1]) < 1e-9
    # D2 only to the table's precision (|CD| differs by 1.2e-4 between the positions)
    assert abs(link.pole + (d[0] - link.pole) * turn - d[1]) < 1e-3


def test_driving_dyad_swing_from_fourbar_extrema():
    pivot, b1 = 1 + 1j, 1 + 1j + 3 * np.exp(1j * 0.3)
    b2 = pivot + (b1 - pivot) * np.exp(1j * np.radians(50))
    dy = driving_dyad(pivot, b1, b2, distance=4.0)
    fb = dy.linkage.fourbar
    assert fb.barker_class == "GCRR"
    ex = fb.extrema(form=1 if dy.linkage.branch == 1 else 2)["theta4"]
    assert math.isclose(ex.max - ex.min, np.radians(50), abs_tol=1e-9)
    assert math.isclose(dy.swing, np.radians(50))
    # the rocker's extreme pin positions are b1 and b2 (in the plane)
    th = np.array([ex.theta2_at_min, ex.theta2_at_max])
    _, B, _, ok = dy.linkage.pose(th)
    assert ok.all()
    assert min(abs(B - b1)) < 1e-6 and min(abs(B - b2)) < 1e-6
    # time ratio 1: the two output limits are half a turn of the crank apart
    gap = abs(ex.theta2_at_max - ex.theta2_at_min)
    assert math.isclose(gap, math.pi, abs_tol=1e-6)


def test_motion_driving_dyad_from_two_position():
    c = [0 + 5.086j, 2.019 + 3.181j]
    d = [0.741 + 2.703j, 4.428 + 2.529j]
    s = two_position(c, d, s2=3.0, s4=4.0)
    dy = s.driving_dyad(distance=3.0)
    expected = abs(np.angle((c[1] - s.O2) / (c[0] - s.O2)))
    assert math.isclose(dy.swing, expected)


# --------------------------------------------------------------------------------------
# bad input


def test_coincident_positions():
    with pytest.raises(InputError, match="coincide"):
        three_position([0, 0, 1 + 1j], [1j, 1j, 2 + 1j])


def test_collinear_positions():
    with pytest.raises(InputError, match="collinear"):
        three_position([0, 1, 2], [1j, 1 + 1j, 2 + 1j])


def test_non_rigid_coupler():
    with pytest.raises(InputError, match="rigid"):
        three_position(C, [D[0], D[1], D[2] + 1])


def test_wrong_number_of_positions():
    with pytest.raises(InputError, match="expected 3 points"):
        three_position(C[:2], D[:2])


def test_translation_has_no_rotopole():
    with pytest.raises(InputError, match="translation"):
        rotopole_link([0, 1], [1j, 1 + 1j])


def test_driving_dyad_bad_input():
    with pytest.raises(InputError, match="same distance"):
        driving_dyad(0, 1, 2j, distance=2.0)
    with pytest.raises(InputError, match="distance"):
        driving_dyad(0, 1, 1j, distance=-1.0)


def test_grcr_circuits_and_branches():
    """HW 3's GRCR {6, 9, 3, 8}: the input rocks on one side of the ground (a circuit);
    within it the two signs of phi12 meet at the rocker's limits (branches)."""
    fb = FourBar(6, 9, 3, 8)
    assert fb.barker_class == "GRCR"
    up = fb.solve(np.radians([40.0, 60.0, 85.0]), form=1, branch=1)
    other_branch = fb.solve(np.radians([60.0]), form=1, branch=-1)
    other_circuit = fb.solve(np.radians([300.0]), form=2, branch=1)

    def place(z):
        return 2 + 1j + np.asarray(z) * np.exp(0.2j)

    good = three_position(place(up.A), place(up.B))
    assert good.ok, good.defects
    a = place([up.A[0], other_branch.A[0], up.A[2]])
    b = place([up.B[0], other_branch.B[0], up.B[2]])
    assert any(d.startswith("branch defect") for d in three_position(a, b).defects)
    a = place([up.A[0], other_circuit.A[0], up.A[2]])
    b = place([up.B[0], other_circuit.B[0], up.B[2]])
    assert any(d.startswith("circuit defect") for d in three_position(a, b).defects)


def test_points_as_xy_array():
    xy = np.column_stack([np.real(C), np.imag(C)])
    dxy = np.column_stack([np.real(D), np.imag(D)])
    s = three_position(xy, dxy)
    assert round(s.O2.real, 3) == 2.178
