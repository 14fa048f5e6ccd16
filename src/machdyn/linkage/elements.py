"""Springs and dampers of a drawn linkage: known loads, no joints.

:class:`_ElementMethods` holds the :class:`~machdyn.linkage.Linkage` builder
methods :meth:`~machdyn.linkage.Linkage.spring` and
:meth:`~machdyn.linkage.Linkage.torsion_spring`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, NoReturn

from .._validate import finite_scalar, nonnegative, positive
from ..errors import InputError, ModelError
from ._common import GROUND, _link_pair


@dataclass(frozen=True)
class _Spring:
    """A linear spring–damper: tension ``k (L − L0) + c dL/dt + preload`` (pulls the ends in)."""

    start: str
    end: str
    link_a: str  # '' = the default carrier
    link_b: str
    stiffness: float
    free_length: float
    damping: float
    preload: float


@dataclass(frozen=True)
class _Torsion:
    """A torsional spring–damper at a pin: torque ``kt (φ − φ0) + ct dφ/dt + preload``."""

    at: str
    links: tuple[str, str] | None
    stiffness: float
    free_angle: float
    damping: float
    preload: float


if TYPE_CHECKING:
    from .builder import Linkage


class _ElementMethods:
    """The spring builders of :class:`~machdyn.linkage.Linkage` (a mixin)."""

    def spring(
        self,
        name: str,
        start: str,
        end: str,
        *,
        stiffness: float,
        free_length: float,
        damping: float = 0.0,
        preload: float = 0.0,
        links: Sequence[str] = (),
    ) -> Linkage:
        """Add a linear spring–damper between two points (a gas spring, a return spring).

        A massless two-force element along the line from ``start`` to ``end``
        with the **tension** (positive when it pulls its ends together)

        ``T = stiffness (L − free_length) + damping dL/dt + preload``,

        ``L`` the distance between the two points. It adds no joint and no loop
        (the motion is the same with or without it); in :meth:`forces` it is a
        known load ``+T û`` on the link at ``start`` and ``−T û`` on the link at
        ``end`` (``û`` the unit vector from ``start`` to ``end``), and its
        power on the mechanism is ``−T dL/dt``. A compression spring (a gas
        spring pushing a lid open) has ``L < free_length``, so ``T < 0``.

        Parameters
        ----------
        name : str
            Its name (the key of ``LinkageForces.elements``).
        start, end : str
            Points where it is attached (on the ground or on moving links).
        stiffness : float
            ``k ≥ 0`` (force per length).
        free_length : float
            ``L0 > 0``, its length where the spring force is ``preload``.
        damping : float
            ``c ≥ 0`` (force per velocity).
        preload : float
            A constant tension added to the spring law (any sign).
            ``preload = k L0`` makes a zero-free-length spring, ``T = k L``.
        links : (link_a, link_b), optional
            The links carrying ``start`` and ``end`` when a point is a pin of
            several links. Default: the first carriers (ground first, then the
            links in the order they were defined) that are two different links.

        Examples
        --------
        A lid O2–A held open by a gas spring S–A: its telescope is an undriven
        actuator (a free strut: it gives the lid its second joint and carries
        no force) and the spring acts between the same points. At θ2 = 0 the
        spring is 5 long, 1 longer than free, so ``T = 100``:

        >>> from machdyn.linkage import Linkage
        >>> lk = (Linkage({"O2": (0, 0), "A": (3, 0), "S": (0, 4)}).ground("O2", "S")
        ...       .link("lid", "O2", "A").actuator("strut", "S", "A").drive("lid")
        ...       .spring("k", "S", "A", stiffness=100.0, free_length=4.0))
        >>> f = lk.forces(lk.solve([0.0], velocity=0.0))
        >>> float(f.elements["k"][0]), float(f.element_length["k"][0])
        (100.0, 5.0)
        """
        name = self._element_name("spring", name)
        self._need_points(f"spring {name!r}", (start, end))
        if start == end:
            raise ModelError(f"spring {name!r} joins point {start!r} to itself; give two points")
        k = nonnegative(f"{name}.stiffness", stiffness)
        L0 = positive(f"{name}.free_length", free_length)
        c = nonnegative(f"{name}.damping", damping)
        T0 = finite_scalar(f"{name}.preload", preload)
        ends = _link_pair(f"{name}.links", links)
        for point, link in zip((start, end), ends, strict=False):
            self._owner(point, link)
        if ends and ends[0] == ends[1]:
            _same_link("spring", name, ends[0])
        self._springs[name] = _Spring(
            start, end, ends[0] if ends else "", ends[1] if ends else "", k, L0, c, T0
        )
        return self._changed()

    def torsion_spring(
        self,
        name: str,
        at: str,
        *,
        stiffness: float,
        free_angle: float,
        damping: float = 0.0,
        preload: float = 0.0,
        links: Sequence[str] | None = None,
    ) -> Linkage:
        """Add a torsional spring–damper at pin ``at`` between two links (or a link and ground).

        With ``phi = theta_b − theta_a`` the relative angle of the two links
        (CCW positive, radians, each ``theta`` as in :meth:`link`; the ground's
        is 0), the element's torque

        ``tau = stiffness (phi − free_angle) + damping dphi/dt + preload``

        acts as ``−tau`` on link *b* and ``+tau`` on link *a* (positive ``tau``
        winds ``phi`` back down), so its power is ``−tau dphi/dt``. It adds no
        joint; ``phi`` is not wrapped (a spring wound a full turn has
        ``phi − free_angle = 2π``).

        Parameters
        ----------
        name : str
            Its name (the key of ``LinkageForces.elements``).
        at : str
            The pin it sits on: a point of both links.
        stiffness : float
            ``kt ≥ 0`` (torque per radian).
        free_angle : float
            ``phi`` (radians) where the spring torque is ``preload``.
        damping : float
            ``ct ≥ 0`` (torque per rad/s).
        preload : float
            A constant torque added to the law (any sign).
        links : (link_a, link_b), optional
            The two links; needed when the pin joins more than two. Default:
            the two carriers of ``at`` (ground first, then in the order the
            links were defined).

        Examples
        --------
        A lid pinned to the ground at O2 (a free strut S–A gives it its second
        joint) with a torsional spring, free at θ2 = 0: at θ2 = 0.5 rad the
        driver holds ``2 × 0.5 = 1``:

        >>> from machdyn.linkage import Linkage
        >>> lk = (Linkage({"O2": (0, 0), "A": (3, 0), "S": (0, 4)}).ground("O2", "S")
        ...       .link("lid", "O2", "A").actuator("strut", "S", "A").drive("lid")
        ...       .torsion_spring("coil", "O2", stiffness=2.0, free_angle=0.0))
        >>> f = lk.forces(lk.solve([0.5], velocity=0.0))
        >>> float(f.elements["coil"][0]), float(f.driver["lid"][0])
        (1.0, 1.0)
        """
        name = self._element_name("torsion spring", name)
        self._need_points(f"torsion spring {name!r}", [at])
        kt = nonnegative(f"{name}.stiffness", stiffness)
        phi0 = finite_scalar(f"{name}.free_angle", free_angle)
        ct = nonnegative(f"{name}.damping", damping)
        tau0 = finite_scalar(f"{name}.preload", preload)
        pair: tuple[str, str] | None = None
        if links is not None:
            given = _link_pair(f"{name}.links", links)
            if len(given) != 2:
                raise InputError(f"{name}.links", f"give two link names, got {links!r}")
            for n in given:
                self._owner(at, n)
            if given[0] == given[1]:
                _same_link("torsion spring", name, given[0])
            pair = (given[0], given[1])
        self._torsions[name] = _Torsion(at, pair, kt, phi0, ct, tau0)
        return self._changed()

    def _element_name(self, what: str, name: Any) -> str:
        if not isinstance(name, str) or not name:
            raise InputError(what, f"a name is a non-empty string, got {name!r}")
        if name in self._links or name == GROUND or self._joint_named(name):
            raise ModelError(f"{what} {name!r}: the name is used twice (by a link or joint)")
        return name

    def _element_links(self, name: str) -> tuple[str, str]:
        """The links ``(a, b)`` a spring or torsion spring acts on, checked."""
        if name in self._springs:
            s = self._springs[name]
            if s.link_a:
                return self._owner(s.start, s.link_a), self._owner(s.end, s.link_b)
            for point in (s.start, s.end):
                if not self._carriers(point):
                    raise ModelError(
                        f"spring {name!r}: point {point!r} is on no link; attach it to points "
                        "of links (or of the ground)"
                    )
            pairs = [(a, b) for a in self._carriers(s.start) for b in self._carriers(s.end)]
            what = "spring"
        else:
            t = self._torsions[name]
            if t.links:
                return self._owner(t.at, t.links[0]), self._owner(t.at, t.links[1])
            pairs, what = [self._pin_pair(f"torsion spring {name!r}", t.at)], "torsion spring"
        pair = next((p for p in pairs if p[0] != p[1]), None)
        if pair is None:
            _same_link(what, name, pairs[0][0])
        return pair


def _same_link(what: str, name: str, link: str) -> NoReturn:
    """Refuse a spring whose two ends are on one link: its load would be internal."""
    raise ModelError(
        f"{what} {name!r}: both ends are on link {link!r}, so its load is internal to that "
        "rigid link and does nothing (its length or angle never changes); attach it to two "
        "different links (or a link and the ground)"
    )
