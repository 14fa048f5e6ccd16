"""Barker's table, row by row: one linkage per class, the code derived by hand."""

from __future__ import annotations

import pytest

from machdyn import AssemblyError, InputError
from machdyn.classify import BARKER_CLASSES, classify, is_assemblable, is_grashof

# (R1, R2, R3, R4), expected code, links that turn fully relative to the ground.
# Grashof rows: s + l < p + q, named by which link is s; non-Grashof: s + l > p + q,
# named by which link is l; change point: s + l = p + q.
ROWS = [
    ((2, 4, 5, 6), "GCCC", (2, 3, 4)),  # 2 + 6 < 4 + 5, ground shortest: double crank
    ((4, 2, 5, 6), "GCRR", (2,)),  # input shortest: crank-rocker
    ((4, 5, 2, 6), "GRCR", (3,)),  # coupler shortest: double rocker, coupler turns
    ((4, 5, 6, 2), "GRRC", (4,)),  # output shortest: rocker-crank
    ((7, 3, 4, 5), "RRR1", ()),  # 3 + 7 > 4 + 5, ground longest
    ((3, 7, 4, 5), "RRR2", ()),
    ((3, 4, 7, 5), "RRR3", ()),
    ((3, 4, 5, 7), "RRR4", ()),
    ((2, 4, 5, 7), "CPCCC", (2, 3, 4)),  # 2 + 7 = 4 + 5, ground shortest
    ((4, 2, 5, 7), "CPCRR", (2,)),
    ((4, 5, 2, 7), "CPRCR", (3,)),
    ((4, 5, 7, 2), "CPRRC", (4,)),
    ((3, 5, 3, 5), "CP2X", (2, 3, 4)),  # parallelogram: two equal pairs
    ((3, 3, 5, 5), "CP2X", (2, 3, 4)),  # kite (deltoid)
    ((4, 4, 4, 4), "CP3X", (2, 3, 4)),  # rhombus: all equal
]


@pytest.mark.parametrize(("lengths", "code", "cranks"), ROWS)
def test_every_row_of_barkers_table(lengths, code, cranks):
    c = classify(*lengths)
    assert c.code == code
    assert c.number == BARKER_CLASSES[code][0]
    assert c.cranks == cranks
    assert c.is_grashof == code.startswith("G") == is_grashof(*lengths)


def test_all_fourteen_classes_are_covered():
    assert {code for _, code, _ in ROWS} == set(BARKER_CLASSES)
    assert sorted(n for n, _ in BARKER_CLASSES.values()) == list(range(1, 15))


def test_change_point_tolerates_decimal_input():
    # 0.1 + 0.7 and 0.3 + 0.5 differ in binary; the user means a change point.
    assert classify(0.1, 0.3, 0.5, 0.7).condition == "change point"


def test_assemblability():
    assert is_assemblable(1, 1, 1, 2.9)
    assert not is_assemblable(1, 1, 1, 3.0)  # closes only flat: a structure
    with pytest.raises(AssemblyError, match="must be shorter than the sum of the other three"):
        classify(1, 1, 1, 3.5)
    with pytest.raises(InputError, match="r3"):
        classify(1, 1, -1, 1)


def test_fourbar_loops_of_drawn_linkages():
    import numpy as np

    from closed_forms import circle_meet
    from machdyn.classify import fourbar_loops
    from machdyn.errors import InputError
    from machdyn.linkage import Linkage

    # Watt II: crank-rocker 8-2-7-6 whose ternary rocker (O4, B, C) drives C-D-O6
    O4, O6 = 8.0 + 0j, 12.0 + 6.0j
    A = 2.0 * np.exp(1j * np.pi / 6)
    B = circle_meet(A, 7.0, O4, 6.0)
    C = O4 + 4.0 * (B - O4) / abs(B - O4) * np.exp(1j * np.radians(-35))
    D = circle_meet(C, 6.0, O6, 5.0, -1.0)
    lk = Linkage({"O2": 0j, "O4": O4, "O6": O6, "A": A, "B": B, "C": C, "D": D})
    lk.ground("O2", "O4", "O6").link("2", "O2", "A").link("3", "A", "B")
    lk.link("4", "O4", "B", "C").link("5", "C", "D").link("6", "O6", "D").drive("2")
    loops = {loop.links: loop for loop in fourbar_loops(lk)}
    assert set(loops) == {("ground", "2", "3", "4"), ("ground", "4", "5", "6")}
    first = loops["ground", "2", "3", "4"]
    assert first.lengths == pytest.approx((8.0, 2.0, 7.0, 6.0))
    assert first.classification.code == classify(8, 2, 7, 6).code == "GCRR"
    second = loops["ground", "4", "5", "6"]
    assert second.lengths == pytest.approx((abs(O6 - O4), 4.0, 6.0, 5.0))
    links, lengths, c = second  # unpacks as the studio reads it
    assert links == ("ground", "4", "5", "6")
    assert c.code == classify(*lengths).code
    # a slider-crank has no four-bar loop
    sc = Linkage({"O2": (0, 0), "A": (2, 0), "B": (8, 0)}).ground("O2")
    sc.link("crank", "O2", "A").link("rod", "A", "B").link("block", "B")
    sc.slider("block", "ground", "B", 0.0).drive("crank")
    assert fourbar_loops(sc) == ()
    with pytest.raises(InputError, match="lk"):
        fourbar_loops("not a linkage")


# Barker's table (the notes' Table 2, rows 9–14; Norton, Design of Machinery, Table 2-4):
# s + l = p + q is its own row group, "change point", apart from Grashof (<) and
# non-Grashof (>). Norton's §2.14 writes Grashof's condition s + l ≤ p + q and calls the
# equality "special-case Grashof"; machdyn follows the notes' three rows, and every place
# that names the condition must say the same of the same lengths, also when they are typed
# with decimals whose sums differ in binary (0.4 + 0.5 ≠ 0.2 + 0.7 by one unit in the last
# place).
@pytest.mark.parametrize("scale", [1.0, 0.1, 0.01, 0.3])
@pytest.mark.parametrize(("lengths", "code", "cranks"), ROWS)
def test_every_place_names_the_condition_of_barkers_row(lengths, code, cranks, scale):
    from machdyn import FourBar

    L = tuple(scale * r for r in lengths)
    want = {"G": "grashof", "R": "non-grashof", "C": "change point"}[code[0]]
    c = classify(*L)
    assert (c.code, c.condition, c.cranks) == (code, want, cranks)
    assert c.is_grashof == is_grashof(*L) == (want == "grashof")
    fb = FourBar(*L)
    assert (fb.barker_class, fb.is_grashof, fb.cranks) == (code, want == "grashof", cranks)


@pytest.mark.parametrize(
    ("lengths", "shown"),
    [
        ((0.4, 0.2, 0.5, 0.7), "special Grashof (change point)"),  # 0.2 + 0.7 vs 0.4 + 0.5
        ((0.3, 0.2, 0.4, 0.5), "special Grashof (change point)"),  # the 2, 3, 4, 5 of §2.14
        ((0.4, 0.2, 0.5, 0.69), "Grashof"),
        ((0.4, 0.2, 0.5, 0.71), "non-Grashof"),
    ],
)
def test_the_four_bar_report_names_the_condition_barkers_table_gives(lengths, shown):
    import re

    from machdyn import FourBar
    from machdyn.report import report

    html = report(FourBar(*lengths))
    row = re.search(r"s \+ l = [^<]*", html)[0]
    assert row.endswith(f": {shown}"), row
    assert classify(*lengths).code in html
