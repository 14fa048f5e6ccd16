"""Mobility: the notes' Kutzbach–Gruebler examples and the joint-list form."""

import pytest

import machdyn
from machdyn import InputError, Joint, mobility, mobility_of


@pytest.mark.parametrize(
    ("links", "j1", "j2", "expected", "source"),
    [
        (3, 2, 1, 1, "notes 8-27: cam-follower, L=3 J1=2 J2=1"),
        (6, 7, 1, 0, "review lecture 1: L=6 J1=7 J2=1 -> structure"),
        (10, 12, 0, 3, "review lecture 1: L=10 J1=12 -> M=3"),
        (4, 4, 0, 1, "loader example 1: M = 3(4-1) - 2(4) - 0 = 1"),
    ],
)
def test_notes_examples(links, j1, j2, expected, source):
    assert mobility(links, j1, j2) == expected, source


def test_exported_at_top_level():
    assert machdyn.mobility is mobility


def test_joint_list_counts_multiple_pins_k_minus_1_times():
    # Four-bar with a dyad 5-6 hung from the crank pin A (links 2, 3, 5 at one pin).
    joints = [
        ("R", (1, 2)),
        ("R", (2, 3, 5)),
        ("R", (3, 4)),
        ("R", (4, 1)),
        ("R", (5, 6)),
        ("R", (6, 1)),
    ]
    assert mobility_of(joints) == 3 * (6 - 1) - 2 * 7 == 1


def test_joint_list_with_half_joint_matches_counts():
    # Cam and flat follower: cam 2 on ground, follower 3 slides on ground, cam contact.
    joints = [Joint("R", (1, 2)), Joint("P", (3, 1)), Joint("cam", (2, 3))]
    assert mobility_of(joints) == mobility(3, 2, 1) == 1


def test_extra_unjointed_links_can_be_declared():
    assert mobility_of([("R", (1, 2))], links=3) == mobility(3, 1) == 4


@pytest.mark.parametrize(
    ("call", "field"),
    [
        (lambda: mobility(2.5, 1), "links"),
        (lambda: mobility(4, -1), "full_joints"),
        (lambda: mobility(0, 0), "links"),
        (lambda: Joint("weld", (1, 2)), "kind"),
        (lambda: Joint("R", (1,)), "links"),
        (lambda: Joint("R", (1, 1)), "links"),
        (lambda: Joint("half", (1, 2, 3)), "links"),
        (lambda: mobility_of([("R", (1, 2)), ("R", (2, 3))], links=2), "links"),
    ],
)
def test_bad_input_names_the_field(call, field):
    with pytest.raises(InputError) as info:
        call()
    assert info.value.field == field


def test_unknown_joint_type_lists_valid_types():
    with pytest.raises(InputError, match="valid types: R, P, rolling"):
        Joint("weld", (1, 2))


@pytest.mark.parametrize(
    ("call", "field"),
    [
        (lambda: mobility("4", "4"), "links"),
        (lambda: mobility(True, 0), "links"),
        (lambda: mobility_of(None), "joints"),
        (lambda: mobility_of([("R", ([1], 2))]), "links"),
    ],
)
def test_non_numbers_are_refused(call, field):
    with pytest.raises(InputError) as info:
        call()
    assert info.value.field == field
