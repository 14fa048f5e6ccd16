"""The read-only topology view of a :class:`~machdyn.linkage.Linkage`.

Everything the builder was given, as small frozen values: the drawn
:attr:`~machdyn.linkage.Linkage.points`, the :attr:`~machdyn.linkage.Linkage.links`
(:class:`Link`), the :attr:`~machdyn.linkage.Linkage.joints` (:class:`Joint`),
the :attr:`~machdyn.linkage.Linkage.drivers` and the
:attr:`~machdyn.linkage.Linkage.elements` (:class:`Spring`,
:class:`TorsionSpring`). Spec files, drawings, the studio and instant-centre
analyses read a linkage through it; a linkage is rebuilt exactly from it (see
``docs/linkage.md``, "Reading a linkage back").
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..errors import ModelError
from ._common import GROUND

if TYPE_CHECKING:
    from .builder import Linkage

__all__ = ["JOINT_KINDS", "Joint", "Link", "Spring", "TorsionSpring"]

#: The kinds of :class:`Joint`, in the order :attr:`Linkage.joints` lists them.
JOINT_KINDS = ("pin", "slider", "slot", "actuator", "roll", "motor")


@dataclass(frozen=True)
class Link:
    """A moving link as given to :meth:`Linkage.link <machdyn.linkage.Linkage.link>`.

    Attributes
    ----------
    name : str
    points : tuple of str
        Its points, in the order given (the first two fix its frame and ``theta``).
    mass, inertia : float
        ``m`` and ``I_G`` (both 0 for a massless link; ``inertia`` 0 for a point mass).
    cg : complex, str or None
        Centre of mass in the link frame, or the name of one of its points;
        None for the first point (and for a massless link).

    Examples
    --------
    >>> from machdyn.linkage import Linkage
    >>> lk = Linkage({"O2": (0, 0), "A": (2, 0)}).link("crank", "O2", "A", mass=1.0,
    ...                                                 inertia=0.5, cg=1.0)
    >>> lk.links["crank"]
    Link(name='crank', points=('O2', 'A'), mass=1.0, inertia=0.5, cg=(1+0j))
    """

    name: str
    points: tuple[str, ...]
    mass: float
    inertia: float
    cg: complex | str | None


@dataclass(frozen=True)
class Joint:
    """One joint of a linkage, with the parameters its builder method took.

    Attributes
    ----------
    kind : str
        ``"pin"`` (a point shared by links), ``"slider"``, ``"slot"``,
        ``"actuator"``, ``"roll"`` or ``"motor"``.
    name : str
        Its name (a pin's is ``"pin P"``, P its point; the name a driver or a
        result table uses).
    links : tuple of str
        The links it joins: a pin's carriers (the ground first, then the links
        in the order they were defined; more than two for a pin joining
        several); ``(block, on)`` of a slider and ``(link, on)`` of a slot (the
        first moves along a line fixed in the second); ``(link_a, link_b)`` of
        an actuator, a rolling contact and a motor (resolved where the builder
        was given no ``links=``).
    points : tuple of str
        A pin's point; ``(at,)`` of a slider, ``(pin,)`` of a slot;
        ``(start, end)`` of an actuator; ``(centre_a, centre_b)`` of a rolling
        contact; ``(at,)`` of a motor.
    direction : complex or None
        Unit vector of a slider's or slot's line in the drawing.
    through : str or None
        The point of ``on`` the slide line was checked to pass through (it
        also sets where a slider's displacement is measured from).
    radii : (float, float) or None
        ``(radius_a, radius_b)`` of a rolling contact (``radius_b`` may be inf).
    internal : bool
        A rolling contact inside a ring.
    radius : float or None
        Radius of curvature of a curved slider's guide or a curved slot.
    centre : str or None
        The point of ``on`` at its centre of curvature (``direction`` and
        ``through`` are then None).

    Examples
    --------
    >>> import numpy as np
    >>> from machdyn.linkage import Linkage
    >>> lk = (Linkage({"O2": (0, 0), "A": (2, 0), "B": (8, 0)}).ground("O2")
    ...       .link("crank", "O2", "A").link("rod", "A", "B").link("block", "B")
    ...       .slider("block", "ground", "B", 0.0, name="guide").drive("crank"))
    >>> [(j.kind, j.name, j.links) for j in lk.joints]  # doctest: +NORMALIZE_WHITESPACE
    [('pin', 'pin O2', ('ground', 'crank')), ('pin', 'pin A', ('crank', 'rod')),
     ('pin', 'pin B', ('rod', 'block')), ('slider', 'guide', ('block', 'ground'))]
    >>> lk.joints[-1].direction
    (1+0j)
    """

    kind: str
    name: str
    links: tuple[str, ...]
    points: tuple[str, ...]
    direction: complex | None = None
    through: str | None = None
    radii: tuple[float, float] | None = None
    internal: bool = False
    radius: float | None = None
    centre: str | None = None


@dataclass(frozen=True)
class Spring:
    """A linear spring–damper as given to :meth:`Linkage.spring <machdyn.linkage.Linkage.spring>`.

    ``points`` is ``(start, end)``; ``links`` the two links it acts on
    (resolved where the builder was given none). ``kind`` is ``"spring"``.
    """

    name: str
    points: tuple[str, str]
    links: tuple[str, str]
    stiffness: float
    free_length: float
    damping: float
    preload: float
    kind: str = "spring"


@dataclass(frozen=True)
class TorsionSpring:
    """A torsion spring as given to :meth:`Linkage.torsion_spring`.

    ``points`` is ``(at,)``; ``links`` the two links ``(a, b)`` whose relative
    angle ``theta_b − theta_a`` it resists. ``kind`` is ``"torsion"``.
    """

    name: str
    points: tuple[str]
    links: tuple[str, str]
    stiffness: float
    free_angle: float
    damping: float
    preload: float
    kind: str = "torsion"


def _resolved(lk: Linkage, resolve, fallback: tuple[str, ...]) -> tuple[str, ...]:
    """Links resolved by the builder's own rule, or as given while they cannot be yet."""
    try:
        return tuple(resolve())
    except ModelError:
        return fallback


def joints_of(lk: Linkage) -> tuple[Joint, ...]:
    """Every joint of ``lk``: pins (point order), sliders, slots, actuators, rolls, motors."""
    out: list[Joint] = []
    carriers: dict[str, list[str]] = {}
    for p in lk._ground:
        carriers.setdefault(p, []).append(GROUND)
    for ln in lk._links.values():
        for p in ln.points:
            carriers.setdefault(p, []).append(ln.name)
    out += [Joint("pin", f"pin {p}", tuple(c), (p,)) for p, c in carriers.items() if len(c) > 1]
    for kind, table in (("slider", lk._sliders), ("slot", lk._slots)):
        for name, (moving, on, at, u, through) in table.items():
            out.append(Joint(kind, name, (moving, on), (at,), direction=u, through=through))
    for name, (kind, moving, on, at, centre, r) in lk._curved.items():
        out.append(Joint(kind, name, (moving, on), (at,), radius=r, centre=centre))
    for name, (start, end, la, lb) in lk._actuators.items():
        links = _resolved(
            lk, lambda s=start, e=end, a=la, b=lb: (lk._owner(s, a), lk._owner(e, b)), (la, lb)
        )
        out.append(Joint("actuator", name, links, (start, end)))
    for name, (a, ca, r_a, b, cb, r_b, internal) in lk._rolls.items():
        out.append(Joint("roll", name, (a, b), (ca, cb), radii=(r_a, r_b), internal=internal))
    for name, (at, pair) in lk._motors.items():
        links = _resolved(lk, lambda n=name: lk._motor_links(n), pair or ())
        out.append(Joint("motor", name, links, (at,)))
    return tuple(out)


def elements_of(lk: Linkage) -> tuple[Spring | TorsionSpring, ...]:
    """The springs, then the torsion springs, of ``lk`` in the order they were added."""
    out: list[Spring | TorsionSpring] = []
    for name, s in lk._springs.items():
        links = _resolved(lk, lambda n=name: lk._element_links(n), (s.link_a, s.link_b))
        out.append(
            Spring(name, (s.start, s.end), links, s.stiffness, s.free_length, s.damping, s.preload)
        )
    for name, t in lk._torsions.items():
        links = _resolved(lk, lambda n=name: lk._element_links(n), t.links or ("", ""))
        out.append(
            TorsionSpring(name, (t.at,), links, t.stiffness, t.free_angle, t.damping, t.preload)
        )
    return tuple(out)


def rebuilt(lk: Linkage, points: dict[str, complex], turn: dict[str, complex]) -> Linkage:
    """The same linkage drawn at ``points``; the links turned by ``turn`` (unit complex each).

    Slide directions are fixed in their guides, so they turn with them.
    """
    from ..massprops import MassProperties
    from .builder import Linkage

    out = Linkage(points)
    if lk._ground:
        out.ground(*lk._ground)
    for ln in lk._links.values():
        if ln.mass == 0:
            out.link(ln.name, *ln.points)
        elif isinstance(ln.cg, str):
            out.link(ln.name, *ln.points, mass=ln.mass, inertia=ln.inertia, cg=ln.cg)
        else:
            cg = 0j if ln.cg is None else ln.cg
            out.link(ln.name, *ln.points, body=MassProperties(ln.mass, cg, ln.inertia))
    for j in joints_of(lk):
        if j.kind in ("slider", "slot") and j.centre is not None:  # a curved guide: its centre
            if j.kind == "slider":
                out.slider(j.links[0], j.links[1], j.points[0], centre=j.centre, name=j.name)
            else:
                out.slot(j.points[0], j.links[0], j.links[1], centre=j.centre, name=j.name)
        elif j.kind in ("slider", "slot"):
            u = j.direction * turn[j.links[1]]
            if j.kind == "slider":
                out.slider(j.links[0], j.links[1], j.points[0], u, through=j.through, name=j.name)
            else:
                out.slot(j.points[0], j.links[0], j.links[1], u, through=j.through, name=j.name)
        elif j.kind == "actuator":
            out.actuator(j.name, *j.points, links=j.links)
        elif j.kind == "roll":
            a, b = j.links
            ra, rb = j.radii
            out.roll(a, j.points[0], ra, b, j.points[1], rb, internal=j.internal, name=j.name)
        elif j.kind == "motor":
            out.motor(j.name, j.points[0], links=j.links)
    out.drive(*lk._drivers)
    for e in elements_of(lk):
        if e.kind == "spring":
            out.spring(e.name, *e.points, stiffness=e.stiffness, free_length=e.free_length,
                       damping=e.damping, preload=e.preload, links=e.links)  # fmt: skip
        else:
            out.torsion_spring(e.name, e.points[0], stiffness=e.stiffness,
                               free_angle=e.free_angle, damping=e.damping, preload=e.preload,
                               links=e.links)  # fmt: skip
    return out
