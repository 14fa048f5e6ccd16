"""The link graph of a drawn linkage: links are the nodes, joints the edges (:class:`_Edge`).

:func:`edges_of` lists the joints as edges; :class:`_Model` is a validated
linkage: its edges, its Assur groups (:mod:`machdyn.linkage.groups`), their
program and, on demand, the whole linkage compiled into vector loops
(:mod:`machdyn.linkage.loopcompile`).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import ModelError
from ._common import GROUND

if TYPE_CHECKING:
    from .builder import Linkage

_IDENT = re.compile(r"\W")


@dataclass(frozen=True)
class _Edge:
    """A joint seen as an edge of the link graph, from link ``a`` to link ``b``.

    ``pa``/``pb`` are point keys on each side; the crossing vector runs from
    ``pa`` (on a) to ``pb`` (on b): zero for a pin, ``d e^{jφ}`` for a slider or
    slot (φ fixed in ``a``), ``L e^{jφ}`` for an actuator.
    """

    kind: str  # "R", "P", "slot", "act", "roll", "arc" (curved slot), "arcP" (curved slider)
    name: str
    a: str
    b: str
    pa: str
    pb: str
    direction: complex = 1 + 0j  # unit vector of the slide in the drawing (P, slot)
    # rolling contact: signed radii (rho_a, rho_b) with contact = centre + rho e^{j phi},
    # phi the angle of centre_a -> centre_b (rho_b = inf: a straight profile on b whose
    # normal toward centre_a is ``direction`` in the drawing); ``carried``: both centres
    # sit on one link, so their distance is fixed already and only no-slip is added
    radii: tuple[float, float] = (0.0, 0.0)
    carried: bool = False


class _Model:
    """A validated linkage: its joints, Assur groups, closed-form program, and loops on demand."""

    def __init__(self, lk: Linkage, edges: list[_Edge], groups: tuple, program) -> None:
        self.lk = lk
        self.edges = edges
        self.groups = groups
        self.program = program  # None when a group needs the vector-loop core
        self._loops: Any = None
        self.cache: dict[str, object] = {}

    def loops(self) -> Any:
        """The whole linkage compiled into vector loops (built at the first call)."""
        from .loopcompile import compile_loops

        if self._loops is None:
            self._loops = compile_loops(self.lk, self.edges)
        return self._loops


def edges_of(lk: Linkage) -> list[_Edge]:
    """The joints of ``lk`` as edges of its link graph (pins first, in point order)."""
    edges: list[_Edge] = []
    carriers: dict[str, list[str]] = {}
    for p in lk._ground:
        carriers.setdefault(p, []).append(GROUND)
    for ln in lk._links.values():
        for p in ln.points:
            carriers.setdefault(p, []).append(ln.name)
    for p, links in carriers.items():
        for other in links[1:]:
            edges.append(_Edge("R", f"pin {p}", links[0], other, p, p))
    for kind, table in (("P", lk._sliders), ("slot", lk._slots)):
        for jn, (moving, on, at, u, through) in table.items():
            ref = lk._points[through] if through else lk._first_point(on)
            foot = lk._points[at] + u * ((ref - lk._points[at]) * u.conjugate()).real
            key = f"{jn}:line"
            lk._points_extra[key] = foot
            edges.append(_Edge(kind, jn, on, moving, key, at, u))
    for jn, (kind, moving, on, at, centre, r) in lk._curved.items():
        edges.append(
            _Edge("arc" if kind == "slot" else "arcP", jn, on, moving, centre, at, radii=(r, 0.0))
        )
    for jn, (start, end, la, lb) in lk._actuators.items():
        a, b = lk._owner(start, la), lk._owner(end, lb)
        if a == b:
            raise ModelError(f"actuator {jn!r} joins link {a!r} to itself")
        edges.append(_Edge("act", jn, a, b, start, end))
    for jn, (a, ca, r_a, b, cb, r_b, internal) in lk._rolls.items():
        z = lk._points[cb] - lk._points[ca]
        if np.isinf(r_b):
            n0 = -z / abs(z)  # normal of the straight profile toward centre_a
            edges.append(
                _Edge("roll", jn, a, b, ca, cb, n0, (r_a, np.inf), _rack_guided(lk, ca, b, n0))
            )
            continue
        if not internal:
            radii = (r_a, -r_b)
        elif r_a < r_b:
            radii = (-r_a, -r_b)
        else:
            radii = (r_a, r_b)
        carriers = [lk._ground, *(ln.points for ln in lk._links.values())]
        carried = any(ca in pts and cb in pts for pts in carriers)
        edges.append(_Edge("roll", jn, a, b, ca, cb, radii=radii, carried=carried))
    return edges


def _rack_guided(lk: Linkage, centre: str, rack: str, normal: complex) -> bool:
    """True when ``centre`` is on a link on which ``rack`` slides parallel to its profile.

    Then the distance from the centre to the straight profile is fixed by that
    slider already (a pinion on a fixed pivot, its rack on a guide), like two
    centres on one carrier.
    """
    carriers = {GROUND} if centre in lk._ground else set()
    carriers |= {n for n, ln in lk._links.items() if centre in ln.points}
    for block, on, _, u, _ in lk._sliders.values():
        pair = {block, on}
        if (
            rack in pair
            and (pair - {rack}) & carriers
            and abs((u * normal.conjugate()).real) < 1e-9
        ):
            return True
    return False
