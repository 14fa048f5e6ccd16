"""Mobility (degrees of freedom) of planar mechanisms: the Kutzbach–Gruebler count.

``M = 3 (L − 1) − 2 J1 − J2`` (Norton, *Design of Machinery*, eq. 2.1c; the
notes' "Kutzbach–Gruebler mobility equation"), with ``L`` links including the
ground, ``J1`` full (one-freedom) joints and ``J2`` half (two-freedom) joints.
A joint that pins ``k`` links together counts as ``k − 1`` joints.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass

from ._validate import integer
from .errors import InputError

__all__ = ["FULL_JOINTS", "HALF_JOINTS", "Joint", "count_joints", "mobility", "mobility_of"]

#: Joint types with one relative freedom (counted in J1).
FULL_JOINTS = ("R", "P", "rolling")
#: Joint types with two relative freedoms (counted in J2).
HALF_JOINTS = ("half", "pin-in-slot", "cam", "roll-slide")


def mobility(links: int, full_joints: int, half_joints: int = 0) -> int:
    """Kutzbach–Gruebler mobility ``M = 3(L − 1) − 2 J1 − J2``.

    Parameters
    ----------
    links : int
        Number of links ``L``, the ground included.
    full_joints : int
        Number of full joints ``J1`` (revolute, prismatic, rolling without slip).
    half_joints : int, optional
        Number of half joints ``J2`` (pin-in-slot, cam contact, rolling with slip).

    Returns
    -------
    int
        The mobility. Zero is a structure, negative a preloaded structure.

    Examples
    --------
    A four-bar (4 links, 4 pins) has one degree of freedom:

    >>> mobility(4, 4)
    1

    The notes' review lecture 1 examples:

    >>> mobility(6, 7, 1)
    0
    >>> mobility(10, 12)
    3
    """
    L = integer("links", links, minimum=1)
    J1 = integer("full_joints", full_joints, minimum=0)
    J2 = integer("half_joints", half_joints, minimum=0)
    return 3 * (L - 1) - 2 * J1 - J2


@dataclass(frozen=True)
class Joint:
    """A joint of a planar mechanism.

    Parameters
    ----------
    kind : str
        One of :data:`FULL_JOINTS` or :data:`HALF_JOINTS`.
    links : tuple of hashable
        The links it joins (two, or more for a multiple pin joint).
    """

    kind: str
    links: tuple

    def __post_init__(self) -> None:
        if not isinstance(self.kind, str) or self.kind not in FULL_JOINTS + HALF_JOINTS:
            valid = ", ".join(FULL_JOINTS + HALF_JOINTS)
            raise InputError("kind", f"unknown joint type {self.kind!r}; valid types: {valid}")
        if isinstance(self.links, str | bytes):
            raise InputError("links", f"expected a sequence of link names, got {self.links!r}")
        try:
            links = tuple(self.links)
            distinct = set(links)  # link names must be hashable (numbers or strings)
        except TypeError:
            raise InputError(
                "links", f"expected a sequence of link names, got {self.links!r}"
            ) from None
        if len(links) < 2:
            raise InputError("links", f"a joint joins at least two links, got {links!r}")
        if len(distinct) != len(links):
            raise InputError("links", f"a joint cannot join a link to itself, got {links!r}")
        if self.kind in HALF_JOINTS and len(links) != 2:
            raise InputError("links", f"a half joint joins exactly two links, got {links!r}")
        object.__setattr__(self, "links", links)

    @property
    def order(self) -> int:
        """Number of joints this one counts as (links joined − 1)."""
        return len(self.links) - 1


def _as_joint(item: Joint | Sequence) -> Joint:
    if isinstance(item, Joint):
        return item
    try:
        kind, links = item
    except (TypeError, ValueError):
        raise InputError("joints", f"each joint is (kind, links), got {item!r}") from None
    return Joint(kind, tuple(links))


def count_joints(joints: Iterable[Joint | Sequence]) -> tuple[int, int, int]:
    """Count ``(L, J1, J2)`` from a joint list.

    Links are counted from the names the joints use; a joint joining ``k``
    links counts ``k − 1`` times.

    Examples
    --------
    >>> count_joints([("R", (1, 2)), ("R", (2, 3)), ("R", (3, 4)), ("R", (4, 1))])
    (4, 4, 0)
    """
    try:
        parsed = [_as_joint(j) for j in joints]
    except TypeError:
        raise InputError("joints", f"expected a list of (kind, links), got {joints!r}") from None
    names = {link for j in parsed for link in j.links}
    j1 = sum(j.order for j in parsed if j.kind in FULL_JOINTS)
    j2 = sum(j.order for j in parsed if j.kind in HALF_JOINTS)
    return len(names), j1, j2


def mobility_of(joints: Iterable[Joint | Sequence], links: int | None = None) -> int:
    """Mobility from a joint list ``[(kind, (link, link, ...)), ...]``.

    Parameters
    ----------
    joints : iterable of Joint or (kind, links)
        ``kind`` is ``"R"``, ``"P"``, ``"rolling"`` (full) or ``"half"``,
        ``"pin-in-slot"``, ``"cam"``, ``"roll-slide"`` (half).
    links : int, optional
        The number of links, if some link carries no joint; by default the
        number of distinct link names in ``joints``.

    Examples
    --------
    A slider-crank: ground 1, crank 2, rod 3, slider 4.

    >>> mobility_of([("R", (1, 2)), ("R", (2, 3)), ("R", (3, 4)), ("P", (4, 1))])
    1

    Three links pinned at one point count as two joints: a four-bar 1-2-3-4
    with a dyad 5-6 hung from the crank pin, which joins links 2, 3 and 5:

    >>> mobility_of([("R", (1, 2)), ("R", (2, 3, 5)), ("R", (3, 4)), ("R", (4, 1)),
    ...              ("R", (5, 6)), ("R", (6, 1))])
    1
    """
    count, j1, j2 = count_joints(joints)
    if links is not None:
        given = integer("links", links, minimum=1)
        if given < count:
            raise InputError("links", f"the joints name {count} distinct links, more than {given}")
        count = given
    return mobility(count, j1, j2)
