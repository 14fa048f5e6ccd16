"""Inversions of a four-bar (the notes' HW 3 #2: Barker tables of GRCR {6, 9, 3, 8})."""

from __future__ import annotations

import json

import numpy as np
import pytest

from closed_forms import circle_meet
from machdyn import FourBar
from machdyn.inversions import PHI_NAMES, AngleRange

CHAIN = (6.0, 9.0, 3.0, 8.0)  # HW 3: GRCR {6, 9, 3, 8}
# Norton sec. 2.11: a Grashof chain's inversions are two crank-rockers (the
# shortest link's neighbours grounded), a double crank (shortest grounded) and a
# double rocker (the link opposite the shortest grounded).
EXPECTED_CLASSES = {1: "GRCR", 2: "GCRR", 3: "GCCC", 4: "GRRC"}


def _wrap(a):
    return np.pi - np.mod(np.pi - a, 2 * np.pi)


def _chain_poses(n=400_000):
    """Every pose of the chain, both circuits, by brute force.

    The chain is parametrised by the angle psi between links 2 and 3 at their
    joint: link 3 is the shortest of a Grashof chain, so it turns fully relative
    to link 2 and no toggle interrupts the sweep (no square-root end points).
    Returns the joints J12, J23, J34, J41 (complex) and the circuit (+1/-1).
    """
    r1, r2, r3, r4 = CHAIN
    psi = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    j23 = np.zeros(n, complex)
    j12 = np.full(n, r2 + 0j)
    j34 = r3 * np.exp(1j * psi)
    poses = []
    for side in (1.0, -1.0):
        # the circles (J12, R1) and (J34, R4) meet at J41: circle_meet, vectorised
        d = np.abs(j34 - j12)
        a = (r1**2 - r4**2 + d**2) / (2 * d)
        h = np.sqrt(r1**2 - a**2)
        u = (j34 - j12) / d
        j41 = j12 + a * u + side * h * 1j * u
        assert abs(j41[0] - circle_meet(j12[0], r1, j34[0], r4, side)) < 1e-12
        poses.append((j12, j23, j34, j41, side))
    return poses


def _phis(joints, order):
    """The notes' six φ of the inversion whose links 1..4 are the chain's ``order``."""
    joint = {}
    j12, j23, j34, j41 = joints
    for (a, b), z in {(1, 2): j12, (2, 3): j23, (3, 4): j34, (4, 1): j41}.items():
        joint[frozenset((a, b))] = z
    n1, n2, n3, n4 = order
    o2 = joint[frozenset((n1, n2))]
    a = joint[frozenset((n2, n3))]
    b = joint[frozenset((n3, n4))]
    o4 = joint[frozenset((n4, n1))]
    ground = np.angle(o4 - o2)
    t2 = np.angle(a - o2) - ground
    t3 = np.angle(b - a) - ground
    t4 = np.angle(b - o4) - ground
    return {
        "phi12": _wrap(t4 - t3),
        "phi13": _wrap(t2 - t4),
        "phi14": _wrap(np.pi - t2 + t3),
        "phi23": _wrap(np.pi - t4),
        "phi24": _wrap(t3),
        "phi34": _wrap(t2),
    }


def _arc_of_samples(values):
    """The arc covered by samples on the circle: (lo, hi) or None for a full turn."""
    v = np.sort(np.mod(values, 2 * np.pi))
    gaps = np.diff(np.append(v, v[0] + 2 * np.pi))
    k = int(np.argmax(gaps))
    if gaps[k] < 0.01:
        return None
    lo = v[(k + 1) % v.size]
    hi = v[k]
    if hi < lo:
        hi += 2 * np.pi
    return lo, hi


@pytest.fixture(scope="module")
def table():
    return FourBar(*CHAIN).inversions()


@pytest.fixture(scope="module")
def poses():
    return _chain_poses()


def test_inversions_are_the_four_cyclic_renumberings_with_their_barker_classes(table):
    assert [inv.grounded for inv in table] == [1, 2, 3, 4]
    for inv in table:
        k = inv.grounded
        expected = tuple(CHAIN[(k - 1 + i) % 4] for i in range(4))
        assert inv.lengths == expected
        assert inv.code == EXPECTED_CLASSES[k]
        assert inv.form_rule == ("phi34" if inv.code in ("GRCR", "GRRC") else "phi12")


@pytest.mark.parametrize("grounded", [1, 2, 3, 4])
def test_inversion_table_matches_a_brute_force_sweep(table, poses, grounded):
    inv = table[grounded]
    order = inv.links
    rule = "phi34" if EXPECTED_CLASSES[grounded] in ("GRCR", "GRRC") else "phi12"
    samples = {1: {}, 2: {}}
    for *joints, _side in poses:
        phis = _phis(joints, order)
        sign = np.sign(phis[rule])
        for form, mask in ((1, sign > 0), (2, sign < 0)):
            for name in PHI_NAMES:
                samples[form].setdefault(name, []).append(phis[name][mask])
    grid = np.linspace(-np.pi, np.pi, 7201)
    for name in PHI_NAMES:
        arcs = {}
        for form in (1, 2):
            values = np.concatenate(samples[form][name])
            arc = _arc_of_samples(values)
            arcs[form] = arc
            got = inv.ranges[name][f"form{form}"]
            if arc is None:
                assert got.full_turn, (grounded, name, form, got.text())
                continue
            assert not got.full_turn and len(got.arcs) == 1, (grounded, name, form)
            lo, hi = got.arcs[0]
            assert abs(_wrap(lo - arc[0])) < 1e-7, (grounded, name, form, lo, arc)
            assert abs(_wrap(hi - arc[1])) < 1e-7, (grounded, name, form, hi, arc)

        # common to both: a direction is common when it lies in both forms' arcs
        def inside(arc, g):
            if arc is None:
                return np.ones(g.shape, bool)
            return np.mod(g - arc[0], 2 * np.pi) <= arc[1] - arc[0]

        expected = inside(arcs[1], grid) & inside(arcs[2], grid)
        assert np.array_equal(inv.ranges[name]["common"].contains(grid), expected), name


@pytest.mark.parametrize("grounded", [1, 2, 3, 4])
def test_phi_map_relates_the_inversion_angles_to_the_original_ones(table, poses, grounded):
    inv = table[grounded]
    for *joints, _side in poses[:1]:
        original = _phis(joints, (1, 2, 3, 4))
        inverted = _phis(joints, inv.links)
        for name, (sign, old) in inv.phi_map.items():
            diff = _wrap(inverted[name] - sign * original[old])
            assert np.max(np.abs(diff)) < 1e-9, (grounded, name)


def test_non_grashof_chain_gives_four_triple_rockers():
    codes = [inv.code for inv in FourBar(3, 5, 4, 7).inversions(n=201)]
    # the longest link (7) moves through positions 4, 3, 2, 1
    assert codes == ["RRR4", "RRR3", "RRR2", "RRR1"]


def test_angle_range_intersection_across_pi_and_in_two_pieces():
    deg = np.radians
    a = AngleRange(((deg(100.0), deg(260.0)),))  # through 180°
    b = AngleRange(((deg(-120.0), deg(120.0)),))  # through 0°
    common = a.intersection(b)
    assert len(common.arcs) == 2
    got = sorted(
        (round(np.degrees(lo) % 360, 9), round(np.degrees(hi) % 360, 9)) for lo, hi in common.arcs
    )
    assert got == [(100.0, 120.0), (240.0, 260.0)]
    assert AngleRange(((0.0, 1.0),)).intersection(AngleRange(((2.0, 3.0),))).empty
    full = AngleRange.every_direction()
    assert full.intersection(a) == a and a.intersection(full) == a


def test_inversion_table_bad_index(table):
    from machdyn.errors import InputError

    with pytest.raises(InputError, match="grounded"):
        table[5]


def test_cli_prints_the_inversion_table(capsys):
    from machdyn.cli import main

    assert main(["fourbar", "6", "9", "3", "8", "--inversions"]) == 0
    out = capsys.readouterr().out
    for k, code in EXPECTED_CLASSES.items():
        assert f"Link {k} grounded" in out and code in out
    assert "form 1: phi34 > 0" in out and "common to both" in out
    assert main(["fourbar", "6", "9", "3", "8", "--inversions", "--json"]) == 0
    payload = json.loads(capsys.readouterr().out)
    library = FourBar(*CHAIN).inversions()
    for row, inv in zip(payload["inversions"], library, strict=True):
        assert row["class"]["code"] == inv.code
        for name in PHI_NAMES:
            for which, r in inv.ranges[name].items():
                shown = row["ranges_deg"][name][which]
                if r.full_turn:
                    assert shown == "full turn"
                else:
                    assert np.allclose(np.radians(shown).reshape(-1, 2), r.arcs or np.empty((0, 2)))


def test_cli_inversions_of_an_unassemblable_chain_is_one_line(capsys):
    from machdyn.cli import main

    assert main(["fourbar", "20", "9", "3", "8", "--inversions"]) != 0
    err = capsys.readouterr().err
    assert "cannot be assembled" in err and "Traceback" not in err


def test_change_point_chain_forms_meet_only_where_the_links_fold():
    # the parallelogram {2, 3, 2, 3}: the two forms meet where every link lies on the
    # ground line, phi12 = 0 or 180 degrees; the output (phi23 = pi - theta4) turns fully
    inv = FourBar(2, 3, 2, 3).inversions(n=401)[1]
    assert inv.code == "CP2X"
    common = inv.ranges["phi12"]["common"]
    assert [round(np.degrees(lo) % 360, 6) for lo, hi in common.arcs] == [0.0, 180.0]
    assert all(hi == lo for lo, hi in common.arcs)
    assert inv.ranges["phi23"]["form1"].full_turn and inv.ranges["phi23"]["common"].full_turn
    assert common.text() == "0.00, 180.00"
