"""Gear trains: simple, compound, reverted, planetary (Willis vs tabular), belts and chains.

References: Norton, *Design of Machinery*, Examples 9-6/9-7 (sun 40, planet 20,
ring 80; arm -200 rpm, sun +100 rpm -> ring -350 rpm); classical closed forms
for a sun-planet-ring train; pitch-point velocity matching (no slip at each
mesh, the notes' "gear relationship") as a check that shares no code with
either planetary method; brute-force loops for the reverted-train search.
"""

import itertools
import math
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from machdyn import InputError
from machdyn.gears import (
    PlanetaryTrain,
    belt_ratio,
    chain_ratio,
    max_gear_teeth,
    reverted_compound,
    simple_train_value,
    sprocket_pitch_diameter,
    stage_ratio,
    train_value,
    willis,
)

DEG = math.pi / 180


# --------------------------------------------------------------------------
# Simple and compound trains, belts and chains
# --------------------------------------------------------------------------
@given(st.lists(st.integers(8, 120), min_size=2, max_size=7))
def test_simple_train_idlers_only_change_sign(teeth):
    expected = Fraction(teeth[0], teeth[-1]) * (-1) ** (len(teeth) - 1)
    assert simple_train_value(teeth) == pytest.approx(float(expected), rel=1e-12)


def test_compound_train_value_with_exact_fractions():
    stages = [(12, 48), (15, 45, "internal"), (20, 80), (100, 250, "crossed_belt")]
    expected = Fraction(-12, 48) * Fraction(15, 45) * Fraction(-20, 80) * Fraction(-100, 250)
    assert train_value(stages) == pytest.approx(float(expected), rel=1e-12)
    assert expected < 0


def test_rolling_pairs():
    assert belt_ratio(100, 300) == pytest.approx(1 / 3)
    assert belt_ratio(100, 300, crossed=True) == pytest.approx(-1 / 3)
    assert chain_ratio(15, 45) == pytest.approx(1 / 3)
    assert stage_ratio(20, 60) == pytest.approx(-1 / 3)
    with pytest.raises(InputError, match="external, internal, open_belt"):
        stage_ratio(20, 60, "bevel")


@pytest.mark.parametrize("teeth", [9, 17, 30])
def test_sprocket_pitch_diameter_chord(teeth):
    # Independent: N rollers on the pitch circle are one chain pitch apart (chord).
    d = sprocket_pitch_diameter(0.625, teeth)
    angles = 2 * np.pi * np.arange(teeth + 1) / teeth
    pts = d / 2 * np.exp(1j * angles)
    assert np.allclose(np.abs(np.diff(pts)), 0.625)


# --------------------------------------------------------------------------
# Reverted compound trains
# --------------------------------------------------------------------------
def _brute_best(target, lo, hi, phi=20 * DEG):
    limit = {n: max_gear_teeth(n, phi) for n in range(lo, hi + 1)}
    best = math.inf
    for n2, n3, n4 in itertools.product(range(lo, hi + 1), repeat=3):
        n5 = n2 + n3 - n4
        if not lo <= n5 <= hi:
            continue
        if limit[min(n2, n3)] < max(n2, n3):
            continue
        if limit[min(n4, n5)] < max(n4, n5):
            continue
        best = min(best, abs(n3 * n5 / (n2 * n4) / target - 1))
    return best


@pytest.mark.parametrize("target", [5.5, 7.0, 1 / 3.3])
def test_reverted_search_matches_brute_force(target):
    t = reverted_compound(target, min_teeth=14, max_teeth=40, tolerance=0.05)
    n2, n3, n4, n5 = t.teeth
    assert n2 + n3 == n4 + n5
    assert t.ratio == pytest.approx(n3 * n5 / (n2 * n4))
    assert abs(t.error) == pytest.approx(_brute_best(target, 14, 40), abs=1e-12)
    assert all(14 <= n <= 40 for n in t.teeth)


def test_reverted_18_to_1_exact_and_coaxial():
    t = reverted_compound(18)
    n2, n3, n4, n5 = t.teeth
    assert Fraction(n3 * n5, n2 * n4) == 18
    assert t.center_distance(2.0) == pytest.approx((n2 + n3) * 2.0 / 2)
    assert t.center_distance(2.0) == pytest.approx((n4 + n5) * 2.0 / 2)
    assert t.train_value == pytest.approx(1 / 18)
    # Free of interference in both meshes (20 deg full depth).
    assert max_gear_teeth(n2, 20 * DEG) >= n3 and max_gear_teeth(n4, 20 * DEG) >= n5
    # Review finding 12: the result has to_pandas like the other results.
    row = t.to_pandas()
    assert [row[k] for k in ("N2", "N3", "N4", "N5")] == [n2, n3, n4, n5]
    assert row["ratio"] == pytest.approx(n3 * n5 / (n2 * n4))
    assert row["tooth_sum"] == n2 + n3 and row["error"] == t.error


def test_impossible_train_targets_rejected():
    with pytest.raises(InputError, match="impossible"):
        reverted_compound(1000, max_teeth=60)
    with pytest.raises(InputError, match="cannot be reached"):
        reverted_compound(1.2345, min_teeth=20, max_teeth=24, tolerance=1e-9)
    with pytest.raises(InputError, match="ratio"):
        reverted_compound(-2)


# --------------------------------------------------------------------------
# Planetary trains
# --------------------------------------------------------------------------
def test_norton_examples_9_6_and_9_7():
    train = PlanetaryTrain.simple(sun=40, planet=20, ring=80)
    assert train.train_value == pytest.approx(-0.5)
    # Formula method (Example 9-7) and tabular method (Example 9-6): ring at -350 rpm.
    assert float(willis(train.train_value, first=100, arm=-200)) == pytest.approx(-350)
    table = train.table(arm=-200, sun=100)
    assert table["ring"] == pytest.approx(-350)
    assert np.allclose(table.with_arm, -200)
    assert table.to_pandas().loc["ring", "total"] == pytest.approx(-350)


@pytest.mark.parametrize(("sun", "planet"), [(20, 30), (40, 20), (17, 23)])
def test_sun_planet_ring_closed_forms(sun, planet):
    ring = sun + 2 * planet
    train = PlanetaryTrain.simple(sun=sun, planet=planet, ring=ring)
    assert train.ratio("sun", "arm", fixed="ring") == pytest.approx(sun / (sun + ring))
    assert train.ratio("ring", "arm", fixed="sun") == pytest.approx(ring / (sun + ring))
    assert train.ratio("sun", "ring", fixed="arm") == pytest.approx(-sun / ring)


@given(
    sun=st.integers(12, 60),
    planet=st.integers(12, 40),
    w_a=st.floats(-500, 500),
    w_s=st.floats(-500, 500),
)
def test_pitch_point_velocities_match(sun, planet, w_a, w_s):
    # No slip at either mesh, from plain kinematics (module 1: r = N/2).
    ring = sun + 2 * planet
    s = PlanetaryTrain.simple(sun=sun, planet=planet, ring=ring).speeds(arm=w_a, sun=w_s)
    rs, rp, rr = sun / 2, planet / 2, ring / 2
    v_centre = s["arm"] * (rs + rp)
    scale = 1 + abs(w_a) + abs(w_s)
    assert v_centre - s["planet"] * rp == pytest.approx(s["sun"] * rs, abs=1e-9 * scale * rr)
    assert v_centre + s["planet"] * rp == pytest.approx(s["ring"] * rr, abs=1e-9 * scale * rr)


@given(
    teeth=st.lists(st.integers(12, 90), min_size=4, max_size=4),
    kinds=st.lists(st.sampled_from(["external", "internal", "shaft"]), min_size=3, max_size=3),
    w1=st.floats(-1000, 1000),
    w2=st.floats(-1000, 1000),
)
def test_willis_agrees_with_tabular_method(teeth, kinds, w1, w2):
    chain = [("g0", teeth[0])] + [(f"g{i + 1}", teeth[i + 1], k) for i, k in enumerate(kinds)]
    train = PlanetaryTrain(chain)
    r = train.train_value
    scale = 1 + abs(w1) + abs(w2)
    # first and arm known -> last
    last = train.speeds(g0=w1, arm=w2)["g3"]
    assert float(willis(r, first=w1, arm=w2)) == pytest.approx(last, abs=1e-9 * scale)
    if abs(r - 1) > 1e-6:
        # first and last known -> arm
        arm = train.speeds(g0=w1, g3=w2)["arm"]
        assert float(willis(r, first=w1, last=w2)) == pytest.approx(arm, abs=1e-6 * scale)
    if abs(r) > 1e-6:
        first = train.speeds(g3=w1, arm=w2)["g0"]
        assert float(willis(r, last=w1, arm=w2)) == pytest.approx(first, abs=1e-6 * scale / abs(r))


def test_compound_planet():
    train = PlanetaryTrain(
        [("sun", 20), ("p1", 30, "external"), ("p2", 15, "shaft"), ("ring", 65, "internal")]
    )
    assert train.train_value == pytest.approx(-20 / 30 * 15 / 65)
    s = train.speeds(ring=0, sun=1)
    assert s["p1"] == s["p2"]
    assert float(willis(train.train_value, first=1, last=0)) == pytest.approx(s["arm"])


def test_willis_vectorised():
    out = willis(-0.5, first=np.array([100.0, 0.0]), arm=np.array([-200.0, 10.0]))
    assert out.shape == (2,)
    assert out[0] == pytest.approx(-350)


def test_planetary_bad_input():
    train = PlanetaryTrain.simple(sun=40, planet=20, ring=80)
    with pytest.raises(InputError, match="exactly two"):
        train.table(sun=1)
    with pytest.raises(InputError, match="sun, planet, ring, arm"):
        train.table(sun=1, moon=0)
    with pytest.raises(InputError, match="N_s \\+ 2 N_p"):
        PlanetaryTrain.simple(sun=40, planet=20, ring=81)
    with pytest.raises(InputError, match="whole number"):
        PlanetaryTrain.simple(sun=40.5, planet=20, ring=80)
    with pytest.raises(InputError, match="exactly two"):
        willis(-0.5, first=1)
    with pytest.raises(InputError, match="turn together"):
        PlanetaryTrain([("a", 20), ("b", 30, "external"), ("c", 20, "external")]).table(a=1, c=2)


def test_trains_reject_nan_with_input_error():
    # Review finding 10: NaN used to pass through willis (and the stage ratios).
    from machdyn import gears

    with pytest.raises(InputError, match="train_value"):
        willis(np.nan, first=100.0, arm=-200.0)
    with pytest.raises(InputError, match="arm"):
        willis(-0.5, first=100.0, arm=np.nan)
    with pytest.raises(InputError, match="driven"):
        gears.stage_ratio(20, np.nan)
    with pytest.raises(InputError, match="pitch"):
        gears.sprocket_pitch_diameter(np.nan, 17)
