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
