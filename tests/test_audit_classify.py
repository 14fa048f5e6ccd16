"""Audit: Grashof/Barker classification, mobility, ranges, toggles and extrema.

Expected values come from this file's own reading of the notes (lecture 9-1-10
"Barker classification"; review lecture 1 "CLASSIFICATION OF FOUR-BAR
MECHANISMS", Table 2; "KUTZBACH-GRUBLER MOBILITY EQUATION") and from brute
force: which links turn fully is decided by sweeping each link's angle and
asking whether the rest of the chain can still close (two circles meet), and
angle extrema by dense sweeps of a circle-intersection solver that include the
exact toggle poses.
"""

from __future__ import annotations

import numpy as np
import pytest

import machdyn
from machdyn import FourBar, classify, is_grashof, mobility, mobility_of
from machdyn.classify import barker_class, is_assemblable

GRASHOF = ("GCCC", "GCRR", "GRCR", "GRRC")
NON_GRASHOF = ("RRR1", "RRR2", "RRR3", "RRR4")
CHANGE_POINT = ("CPCCC", "CPCRR", "CPRCR", "CPRRC")


def barker_by_hand(r):
    """The notes' Table 2 read directly: sign of s + l − (p + q), then which link is s or l."""
    s, p, q, l = sorted(r)  # noqa: E741
    excess = s + l - (p + q)
    if abs(excess) <= 1e-12 * sum(r):
        if s == l:
            return "CP3X"
        if s == p or q == l:  # s + l = p + q with a tie: two equal pairs
            return "CP2X"
        return CHANGE_POINT[r.index(s)]
    if excess < 0:
        return GRASHOF[r.index(s)]
    return NON_GRASHOF[r.index(l)]


# One linkage per row of the notes' Table 2 (rows 1-14), chosen here.
TABLE_2 = [
    ((2, 7, 6, 5), "GCCC", 1),
    ((7, 2, 6, 5), "GCRR", 2),
    ((7, 6, 2, 5), "GRCR", 3),
    ((7, 6, 5, 2), "GRRC", 4),
    ((9, 4, 5, 6), "RRR1", 5),
    ((4, 9, 5, 6), "RRR2", 6),
    ((4, 5, 9, 6), "RRR3", 7),
    ((4, 5, 6, 9), "RRR4", 8),
    ((2, 6, 4, 4), "CPCCC", 9),  # 2 + 6 = 4 + 4, ground shortest
    ((6, 2, 5, 3), "CPCRR", 10),  # 2 + 6 = 5 + 3
    ((6, 5, 2, 3), "CPRCR", 11),
    ((6, 5, 3, 2), "CPRRC", 12),
    ((3, 5, 3, 5), "CP2X", 13),  # parallelogram
    ((3, 3, 5, 5), "CP2X", 13),  # deltoid (kite)
    ((4, 4, 4, 4), "CP3X", 14),
]


@pytest.mark.parametrize(("lengths", "code", "number"), TABLE_2)
def test_barker_table_rows(lengths, code, number):
    """Notes' Table 2, every row (the change-point equality s + l = p + q included)."""
    c = classify(*lengths)
    assert barker_by_hand(list(lengths)) == code
    assert (c.code, c.number) == (code, number)
    assert barker_class(*lengths) == code
    assert c.is_grashof == (code in GRASHOF)
    assert is_grashof(*lengths) == (code in GRASHOF)


def test_notes_homework_and_exam_linkages():
    """HW 3: GRCR {6, 9, 3, 8}; HW 6: GCRR {8, 4, 7, 6}; final exam 2: {8, 4, 9, 6} is GCRR
    (4 + 9 = 13 < 8 + 6 = 14, input shortest)."""
    assert classify(6, 9, 3, 8).code == "GRCR"
    assert classify(8, 4, 7, 6).code == "GCRR"
    assert classify(8, 4, 9, 6).code == "GCRR"


def test_random_integer_lengths_match_the_table(rng):
    """Integer lengths make the change-point equality frequent: 3000 draws."""
    seen = set()
    for _ in range(3000):
        r = [int(x) for x in rng.integers(1, 13, 4)]
        if not max(r) < sum(r) - max(r):
            with pytest.raises(machdyn.AssemblyError):
                classify(*r)
            assert not is_assemblable(*r)
            continue
        code = classify(*r).code
        assert code == barker_by_hand(r), r
        seen.add(code)
    assert seen == set(GRASHOF + NON_GRASHOF + CHANGE_POINT + ("CP2X", "CP3X"))


def test_change_point_scaled_lengths_still_change_point():
    """s + l = p + q survives scaling by awkward factors (lengths typed in mm or in)."""
    for k in (0.1, 1 / 3, 25.4, 1e-3, 7e4):
        assert classify(2 * k, 6 * k, 4 * k, 4 * k).code == "CPCCC"
        assert classify(6 * k, 2 * k, 5 * k, 3 * k).code == "CPCRR"


def _turns_fully(fixed_lo, fixed_hi, v):
    return bool(np.all((v >= fixed_lo - 1e-12) & (v <= fixed_hi + 1e-12)))


def test_cranks_and_input_range_by_brute_force(rng):
    """A link turns fully relative to the ground iff, for every angle it takes, the
    other two moving links can still close the loop (|d − ...| within their reach)."""
    n = 0
    while n < 300:
        r1, r2, r3, r4 = rng.uniform(0.5, 10, 4)
        try:
            fb = FourBar(r1, r2, r3, r4)
        except machdyn.AssemblyError:
            continue
        a, b, c, d = r2, r3, r4, r1
        e = np.exp(1j * np.linspace(0, 2 * np.pi, 20001))
        turns = {
            2: _turns_fully(abs(b - c), b + c, np.abs(a * e - d)),
            3: _turns_fully(abs(a - c), a + c, np.abs(d - b * e)),
            4: _turns_fully(abs(a - b), a + b, np.abs(d + c * e)),
        }
        assert fb.cranks == tuple(k for k in (2, 3, 4) if turns[k]), fb
        rng_in = fb.input_range(1)
        assert rng_in.full_turn == turns[2]
        if not rng_in.full_turn:
            # at each end of the range links 3 and 4 are collinear: |A − O4| = b ± c
            for t in (rng_in.lo, rng_in.hi):
                f = abs(a * np.exp(1j * t) - d)
                assert min(abs(f - (b + c)), abs(f - abs(b - c))) < 1e-9 * (a + b + c + d)
        n += 1


def test_mobility_examples_from_the_notes():
    """Notes 8-23 (M = 3(L − 1) − 2J1 − J2); review lecture 1: L=6, J1=7, J2=1 → 0;
    L=10, J1=12 → 3; the cam-follower L=3, J1=2, J2=1 → 1; a gear pair the same."""
    assert mobility(6, 7, 1) == 0
    assert mobility(10, 12, 0) == 3
    assert mobility(3, 2, 1) == 1
    cam = [("R", ("ground", "cam")), ("P", ("follower", "ground")), ("cam", ("cam", "follower"))]
    assert mobility_of(cam) == 1
    gears = [("R", (1, 2)), ("R", (1, 3)), ("half", (2, 3))]
    assert mobility_of(gears) == 1
    # a wheel rolling without slip on the ground is a full joint (M = 1); with slip a half
    assert mobility_of([("rolling", ("wheel", "ground"))]) == 1
    assert mobility_of([("roll-slide", ("wheel", "ground"))]) == 2
    # a six-bar of 7 pins: 3·5 − 2·7 = 1; one more pin: 3·5 − 2·8 = −1 (preloaded structure)
    watt = [("R", (1, 2)), ("R", (2, 3)), ("R", (3, 4)), ("R", (4, 1))]
    watt += [("R", (3, 5)), ("R", (5, 6)), ("R", (6, 4))]
    assert mobility_of(watt) == 1
    assert mobility_of([*watt, ("R", (5, 4))]) == -1


def _dense_poses(fb, n=20001):
    """Every assembled pose of both assemblies on a dense θ2 grid plus the exact
    input limits (where links 3 and 4 toggle)."""
    a, b, c, d = fb.r2, fb.r3, fb.r4, fb.r1
    t2 = list(np.linspace(0, 2 * np.pi, n))
    for f in (b + c, abs(b - c)):
        cs = (a * a + d * d - f * f) / (2 * a * d)
        if abs(cs) <= 1:
            t2 += [np.arccos(cs), 2 * np.pi - np.arccos(cs)]
    t2 = np.sort(np.array(t2))
    A = a * np.exp(1j * t2)
    f = np.abs(d - A)
    u = (d - A) / f
    x = (b * b - c * c + f * f) / (2 * f)
    h2 = b * b - x * x
    ok = h2 >= -1e-9 * b * b
    h = np.sqrt(np.clip(h2, 0, None))
    out = []
    for s in (1, -1):
        B = A + u * (x + 1j * s * h)
        out.append((t2[ok], np.angle(B - A)[ok], np.angle(B - d)[ok]))
    return out


def _wrap(x):
    return np.angle(np.exp(1j * x))


def test_extrema_and_minimum_transmission_angle_by_brute_force(rng):
    """FourBar.extrema / transmission_angle vs a dense sweep of both assemblies, split
    into the notes' forms (sign of φ12; of φ34 for GRCR, GRRC; toggles belong to both)."""
    n = 0
    while n < 12:
        try:
            fb = FourBar(*rng.uniform(0.5, 10, 4))
        except machdyn.AssemblyError:
            continue
        if fb.classification.condition == "change point":
            continue
        n += 1
        poses = _dense_poses(fb)
        for form in (1, 2):
            chunks = []
            for t2, t3, t4 in poses:
                p12 = _wrap(t4 - t3)
                toggle = (np.abs(p12) < 1e-6) | (np.abs(p12) > np.pi - 1e-6)
                key = p12 if fb.form_rule == "phi12" else _wrap(t2)
                keep = ((key > 0) == (form == 1)) | (toggle & (fb.form_rule == "phi12"))
                chunks.append((t2[keep], t3[keep], t4[keep]))
            t2, t3, t4 = (np.concatenate(z) for z in zip(*chunks, strict=True))
            if t2.size == 0:
                continue
            angles = {
                "theta3": t3,
                "theta4": t4,
                "phi12": t4 - t3,
                "phi13": t2 - t4,
                "phi14": np.pi - t2 + t3,
                "phi23": np.pi - t4,
                "phi24": t3,
                "phi34": t2,
            }
            ex = fb.extrema(form)
            for name, values in angles.items():
                e = ex[name]
                if e.full_turn:
                    hist, _ = np.histogram(_wrap(values), bins=36, range=(-np.pi, np.pi))
                    assert (hist > 0).all(), (fb, form, name)
                    continue
                mid = 0.5 * (e.min + e.max)
                v = mid + _wrap(values - mid)
                assert v.min() == pytest.approx(e.min, abs=2e-4), (fb, form, name)
                assert v.max() == pytest.approx(e.max, abs=2e-4), (fb, form, name)
            p12 = np.abs(_wrap(t4 - t3))
            mu = np.minimum(p12, np.pi - p12)
            assert fb.transmission_angle(form).min == pytest.approx(mu.min(), abs=2e-4)


def test_toggles_are_collinear_poses_and_all_found(rng):
    """Each toggle has its two links collinear; the count of 2-3 toggles equals the
    number of sign changes of sin(θ3 − θ2) along a dense sweep of both assemblies."""
    n = 0
    while n < 60:
        try:
            fb = FourBar(*rng.uniform(0.5, 10, 4))
        except machdyn.AssemblyError:
            continue
        if fb.classification.condition == "change point":
            continue
        n += 1
        toggles = fb.toggles()
        for t in toggles:
            pose = fb.solve(np.array([t.theta2]), form=1 if t.branch >= 0 else 2, order=0)
            if t.links == (3, 4):
                f = abs(fb.r2 * np.exp(1j * t.theta2) - fb.r1)
                target = fb.r3 + fb.r4 if t.kind == "extended" else abs(fb.r3 - fb.r4)
                assert f == pytest.approx(target, rel=1e-9)
            elif fb.form_rule == "phi12":
                assert abs(np.sin(pose.theta3[0] - t.theta2)) < 1e-7
        sign_changes = 0
        for t2, t3, _ in _dense_poses(fb, 40001):
            s = np.sin(t3 - t2)
            keep = np.abs(s) > 1e-12
            sign_changes += int(np.sum(np.diff(np.sign(s[keep])) != 0))
        found = sum(1 for t in toggles if t.links == (2, 3))
        if fb.form_rule == "phi12" and fb.input_range().full_turn:
            assert found == sign_changes, (fb, toggles)


@pytest.mark.parametrize(
    "lengths",
    [(2, 6, 4, 4), (6, 2, 5, 3), (3, 5, 3, 5), (3, 3, 5, 5), (5, 3, 3, 5), (4, 4, 4, 4)],
)
def test_change_point_input_range_agrees_with_cranks(lengths):
    """A change-point input that turns fully (it just reaches the flat pose at one
    angle, cos θ2 = ±1 exactly) has a full-turn input range, as `cranks` says; before
    the fix round-off made e.g. the parallelogram's input a 'rocker' over (2e-8, 2π − 2e-8)."""
    fb = FourBar(*lengths)
    assert 2 in fb.cranks
    assert fb.input_range(1).full_turn and fb.input_range(2).full_turn
    # every θ2 of a full sweep assembles in some form, or is flagged as the
    # indeterminate pose where A lands on O4 (kite, rhombus: B is then anywhere)
    t2 = np.linspace(0, 2 * np.pi, 3601)
    m1, m2 = fb.solve(t2, form=1), fb.solve(t2, form=2)
    flagged = np.char.startswith(m1.reason.astype(str), "indeterminate")
    assert (m1.assembled | m2.assembled | flagged).all()


@pytest.mark.parametrize(
    ("lengths", "expected"),
    [
        ((3, 5, 3, 5), [(0.0, "folded"), (180.0, "extended")]),  # parallelogram
        ((4, 4, 4, 4), [(0.0, "folded"), (180.0, "extended")]),  # rhombus
        ((2, 6, 4, 4), [(180.0, "extended")]),  # CPCCC: |A − O4| = 8 = R3 + R4 at θ2 = π
        ((3, 3, 5, 5), [(0.0, "folded")]),  # kite: A on O4 at θ2 = 0, |R3 − R4| = 0
    ],
)
def test_change_point_toggles_of_links_3_and_4_listed_once(lengths, expected):
    """At a change point links 3 and 4 fall in line at θ2 = 0 or π only; the law of cosines
    (|A − O4|² = R2² + R1² − 2R1R2 cos θ2 = (R3 ± R4)², notes 8-30) gives cos θ2 = ±1, one
    angle — before the fix it was listed twice, as 0° and 360° (or π ± 1e-8)."""
    toggles = [t for t in FourBar(*lengths).toggles() if t.links == (3, 4)]
    got = [(round(float(np.degrees(t.theta2)), 6) % 360, t.kind) for t in toggles]
    assert got == expected


def test_notes_toggle_theorems_for_phi12_of_crank_input_linkages(rng):
    """Review lecture 1: "if two adjacent links are toggled [extended] the internal angle
    between the other two links has its maximum; if they overlap, its minimum" — links 1
    and 2 extended at θ2 = π, overlapped at θ2 = 0, so over form 1 of any linkage whose
    input turns fully, cos φ12 ranges between (R3² + R4² − (R1 ∓ R2)²)/(2 R3 R4)
    (final exam 2: {8, 4, 9, 6} → min φ12 = 20.74°)."""
    cases = [(8, 4, 9, 6)]
    while len(cases) < 12:
        r = tuple(rng.uniform(0.5, 10, 4))
        try:
            fb = FourBar(*r)
        except machdyn.AssemblyError:
            continue
        if fb.classification.code in ("GCRR", "GCCC"):
            cases.append(r)
    for r1, r2, r3, r4 in cases:
        ex = FourBar(r1, r2, r3, r4).extrema(form=1)["phi12"]
        lo = np.arccos((r3**2 + r4**2 - (r1 - r2) ** 2) / (2 * r3 * r4))
        hi = np.arccos((r3**2 + r4**2 - (r1 + r2) ** 2) / (2 * r3 * r4))
        assert ex.min == pytest.approx(lo, abs=1e-9)
        assert ex.max == pytest.approx(hi, abs=1e-9)
        assert np.cos(ex.theta2_at_min) == pytest.approx(1.0)
        assert np.cos(ex.theta2_at_max) == pytest.approx(-1.0)
    assert np.degrees(FourBar(8, 4, 9, 6).extrema(1)["phi12"].min) == pytest.approx(
        20.7419, abs=1e-4
    )
