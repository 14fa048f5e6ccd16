"""Linkages described as drawn: links, joints and drivers, compiled into vector loops.

A :class:`Linkage` is given the way a mechanism is sketched: named points with
their coordinates in one assembled pose, the links (rigid bodies) that carry
them, the joints and the driver(s). Every point shared by two or more links is
a revolute joint (a pin joining several links counts once per extra link);
prismatic joints, pin-in-slot half joints, linear actuators (hydraulic
cylinders, collapsed into one variable-length vector) and rolling contacts
without slip (:meth:`Linkage.roll`) are added by name; a rotary motor at a
pin between two moving links (:meth:`Linkage.motor`) drives their relative
angle. Springs and dampers between two points (:meth:`Linkage.spring`) or at
a pin (:meth:`Linkage.torsion_spring`) add no joint: they are known loads in
the force analysis.

The linkage is compiled into the core's vector loops the way the notes teach
(review lecture 3; Norton, *Design of Machinery*, §4.5 and §4.13):

* links are the nodes and joints the edges of the *link graph*; a spanning
  tree grown from the ground gives one independent loop per remaining joint
  (a fundamental cycle basis), so every joint sits on at least one loop;
* in each loop every link contributes the vector from the joint where the loop
  enters it to the joint where it leaves (constant length, angle variable),
  sliders and actuators a variable-length vector;
* vectors of one link that sit in different loops are tied by a
  constant-angle constraint (``theta_b = theta_a + alpha``); links joined by a
  prismatic joint turn together, so they share one angle variable; a link is
  never given three vectors in one loop (no redundancy);
* the drawn pose seeds the Newton–Raphson guesses and selects the circuit: the
  solver marches from the drawn input to the first requested input, so a user
  never types angle guesses.

Angles: ``theta`` of a link is the absolute angle (CCW from +x) of the line
from its first listed point to its second, like θ2, θ3, θ4 of a four-bar; an
angle driver is given in that convention (absolute, radians). Angles are not
wrapped: along a sweep they are continuous.

Newton–Euler force analysis (:meth:`Linkage.forces`) follows the notes' matrix
method (Norton §11.4–11.8): three equations per moving link, the unknown joint
forces ``F_ap`` (force on link *p* from link *a*), prismatic normal forces and
couples, and the driver torque or force, solved for every sample at once.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any, NoReturn

import numpy as np

from ._validate import finite_array, finite_scalar, magnitude, nonnegative, positive
from .errors import AssemblyError, InputError, ModelError
from .loops import LoopSystem, lu_factor, lu_solve
from .loops.result import Motion
from .massprops import MassProperties
from .mobility import mobility_of

__all__ = ["Linkage", "LinkageForces", "LinkageMotion"]

GROUND = "ground"
_IDENT = re.compile(r"\W")


def _complex_point(field: str, value: Any) -> complex:
    if isinstance(value, complex):
        z = value
    else:
        try:
            if np.ndim(value) == 0:
                z = complex(value)
            else:
                x, y = value
                z = complex(finite_scalar(f"{field} x", x), finite_scalar(f"{field} y", y))
        except (TypeError, ValueError):
            raise InputError(field, f"a point is (x, y) or x + yj, got {value!r}") from None
    if not (np.isfinite(z.real) and np.isfinite(z.imag)):
        raise InputError(field, f"coordinates must be finite, got {value!r}")
    return z


def _frozen(d: dict[str, np.ndarray]) -> Mapping[str, np.ndarray]:
    for v in d.values():
        v.flags.writeable = False
    return MappingProxyType(d)


@dataclass(frozen=True)
class _Link:
    name: str
    points: tuple[str, ...]
    mass: float
    inertia: float
    cg: complex | str | None  # link frame (complex) or a point name


@dataclass(frozen=True)
class _Edge:
    """A joint seen as an edge of the link graph, from link ``a`` to link ``b``.

    ``pa``/``pb`` are point keys on each side; the crossing vector runs from
    ``pa`` (on a) to ``pb`` (on b): zero for a pin, ``d e^{jφ}`` for a slider or
    slot (φ fixed in ``a``), ``L e^{jφ}`` for an actuator.
    """

    kind: str  # "R", "P", "slot", "act", "roll"
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


@dataclass(frozen=True)
class _Compiled:
    system: LoopSystem
    driver_vars: tuple[str, ...]  # loop variable of each driver
    driver_offsets: tuple[float, ...]  # driver value = var + offset
    drawn: dict[str, float]  # drawn value of every loop variable
    rot_var: dict[str, str | None]  # link -> angle variable of its rotation class
    rot_offset: dict[str, float]  # link theta = var + offset (ground: offset 0)
    tree: tuple[tuple[str, _Edge, bool], ...]  # (child link, edge, child is edge.b) in BFS order
    # joint -> (length variable, angle variable or None, constant angle when None)
    cross_vars: dict[str, tuple[str, str | None, float]]
    # rolling joint -> crossing vector centre_a -> centre_b (or contact line point) as
    # signed parts (sign, length constant or variable, angle constant or variable)
    roll_parts: dict[str, tuple[tuple[float, float | str, float | str], ...]] = field(
        default_factory=dict
    )


class Linkage:
    """A planar linkage given by its drawing: points, links, joints and drivers.

    Parameters
    ----------
    points : mapping of str to (x, y) or complex, optional
        Drawn coordinates of named points in one assembled pose (any consistent
        length unit). More can be added with :meth:`point`.

    Examples
    --------
    The notes' HW 6 four-bar (GCRR 8-4-7-6) drawn at θ2 = 0, with B found by
    hand from ``|B − A| = 7`` and ``|B − O4| = 6``: ``x_B = 61/8``:

    >>> import numpy as np
    >>> lk = Linkage({"O2": (0, 0), "O4": (8, 0), "A": (4, 0),
    ...               "B": (7.625, np.sqrt(49 - 3.625**2))})
    >>> lk = lk.ground("O2", "O4").link("crank", "O2", "A").link("coupler", "A", "B")
    >>> lk = lk.link("rocker", "O4", "B").drive("crank")
    >>> m = lk.solve(np.radians([0.0, 45.0, 90.0]), velocity=10.0)
    >>> np.degrees(m.theta["coupler"]).round(2).tolist()
    [58.81, 25.98, 15.47]
    >>> bool(m.ok.all())
    True
    """

    def __init__(self, points: Mapping[str, Any] | None = None) -> None:
        self._points: dict[str, complex] = {}
        self._links: dict[str, _Link] = {}
        self._ground: tuple[str, ...] = ()
        self._sliders: dict[str, tuple[str, str, str, complex, str | None]] = {}
        self._slots: dict[str, tuple[str, str, str, complex, str | None]] = {}
        self._actuators: dict[str, tuple[str, str, str, str]] = {}
        self._rolls: dict[str, tuple[str, str, float, str, str, float, bool]] = {}
        self._motors: dict[str, tuple[str, tuple[str, str] | None]] = {}  # name -> (pin, links)
        self._springs: dict[str, _Spring] = {}
        self._torsions: dict[str, _Torsion] = {}
        self._drivers: list[str] = []
        self._compiled: _Compiled | None = None
        self._points_extra: dict[str, complex] = {}
        for name, xy in (points or {}).items():
            self.point(name, xy)

    # ------------------------------------------------------------------ building
    def _changed(self) -> Linkage:
        self._compiled = None
        return self

    def point(self, name: str, xy: Any) -> Linkage:
        """Give (or move) the drawn coordinates of point ``name``.

        Examples
        --------
        >>> Linkage().point("A", (3.0, 4.0)).position("A")
        (3+4j)
        """
        if not isinstance(name, str) or not name:
            raise InputError("point", f"a point name is a non-empty string, got {name!r}")
        self._points[name] = _complex_point(f"point {name}", xy)
        return self._changed()

    def position(self, name: str) -> complex:
        """Drawn coordinates of point ``name`` as ``x + yj``.

        Examples
        --------
        >>> Linkage({"O4": (8, 0)}).position("O4")
        (8+0j)
        """
        if name not in self._points:
            raise ModelError(f"unknown point {name!r}; known points: {', '.join(self._points)}")
        return self._points[name]

    def _need_points(self, owner: str, names: Iterable[str]) -> None:
        missing = [p for p in names if p not in self._points]
        if missing:
            raise ModelError(
                f"{owner} names point(s) {', '.join(map(repr, missing))} without coordinates; "
                f"give them with point(name, (x, y)); known points: "
                f"{', '.join(self._points) or '(none)'}"
            )

    def ground(self, *points: str) -> Linkage:
        """Name the points fixed to the ground (link ``"ground"``): pivots, slide lines.

        Examples
        --------
        >>> lk = Linkage({"O2": (0, 0), "O4": (8, 0)}).ground("O2", "O4")
        """
        self._need_points("ground", points)
        self._ground = tuple(dict.fromkeys(self._ground + tuple(points)))
        return self._changed()

    def link(
        self,
        name: str,
        *points: str,
        mass: float | None = None,
        inertia: float | None = None,
        cg: complex | str | Sequence[float] | None = None,
        body: MassProperties | None = None,
    ) -> Linkage:
        """Add a rigid moving link carrying the named points (at least two joints).

        The link's own frame has its origin at the first point and its x axis
        toward the second, as for :func:`machdyn.dynamics.fourbar_dynamics`;
        ``theta`` of the link is the angle of that axis.

        Parameters
        ----------
        name : str
            Link name (not ``"ground"``).
        *points : str
            Names of points on the link (joints, coupler points).
        mass, inertia : float, optional
            Mass ``m > 0`` and moment of inertia about the centre of mass
            ``I_G > 0``; omit both for a massless link.
        cg : complex, (x, y) or str, optional
            Centre of mass in the link frame, or the name of a point; default
            the first point.
        body : MassProperties, optional
            Mass properties instead of ``mass, inertia, cg`` (``cg`` in the link
            frame, e.g. from :func:`machdyn.massprops.rod`).

        Examples
        --------
        >>> from machdyn.massprops import rod
        >>> lk = Linkage({"O2": (0, 0), "A": (2, 0)})
        >>> lk = lk.link("crank", "O2", "A", body=rod(0.5, 2.0))
        """
        if not isinstance(name, str) or not name:
            raise InputError("link", f"a link name is a non-empty string, got {name!r}")
        if name == GROUND:
            raise InputError("link", "'ground' is the fixed link; use ground(...) for its points")
        if name in self._links:
            raise ModelError(f"link {name!r} is defined twice")
        points = tuple(dict.fromkeys(points))
        if not points:
            raise ModelError(
                f"link {name!r} has no points; list its joints, e.g. link('crank', 'O2', 'A')"
            )
        self._need_points(f"link {name!r}", points)
        if body is not None:
            if mass is not None or inertia is not None or cg is not None:
                raise InputError(f"{name}.body", "give either body= or mass/inertia/cg, not both")
            if not isinstance(body, MassProperties):
                raise InputError(f"{name}.body", f"must be a MassProperties, got {body!r}")
            m, i_g, c = body.mass, body.inertia, body.cg
        elif mass is None and inertia is None:
            if cg is not None:
                raise InputError(f"{name}.cg", "a centre of mass needs mass and inertia")
            m, i_g, c = 0.0, 0.0, None
        else:
            if mass is None or inertia is None:
                raise InputError(
                    f"{name}.mass", "give both mass and inertia (or neither: massless link)"
                )
            m = finite_scalar(f"{name}.mass", mass)
            if m <= 0:
                raise InputError(
                    f"{name}.mass", f"must be positive, got {m:g} (omit it for a massless link)"
                )
            i_g = finite_scalar(f"{name}.inertia", inertia)
            if i_g <= 0:
                raise InputError(
                    f"{name}.inertia",
                    f"I_G must be positive, got {i_g:g} (a point mass: body=point_mass(...))",
                )
            if cg is None or isinstance(cg, str):
                c = cg
                if isinstance(cg, str) and cg not in points:
                    raise ModelError(
                        f"link {name!r}: cg point {cg!r} is not one of its points "
                        f"({', '.join(points)})"
                    )
            else:
                c = _complex_point(f"{name}.cg", cg)
        self._links[name] = _Link(name, points, m, i_g, c)
        return self._changed()

    def _line(self, field: str, direction: Any, at: complex, through: str | None) -> complex:
        if isinstance(direction, str):
            self._need_points(field, [direction])
            u = self._points[direction] - at
            if abs(u) == 0:
                raise AssemblyError(f"{field}: direction point {direction!r} coincides with it")
        elif np.ndim(direction) == 0 and not isinstance(direction, complex):
            ang = finite_scalar(f"{field}.direction", direction)
            u = complex(np.cos(ang), np.sin(ang))
        else:
            u = _complex_point(f"{field}.direction", direction)
            if abs(u) == 0:
                raise InputError(f"{field}.direction", "must be a non-zero vector")
        u = u / abs(u)
        if through is not None:
            self._need_points(field, [through])
            off = self._points[through] - at
            miss = abs((off * u.conjugate()).imag)
            scale = max(abs(off), 1.0)
            if miss > 1e-9 * scale:
                raise AssemblyError(
                    f"{field}: the slide line through {through!r} with direction "
                    f"{np.degrees(np.angle(u)):.4g} deg misses the sliding point by {miss:.4g} "
                    "(the drawing cannot be assembled: the points must be collinear)"
                )
        return u

    def slider(
        self,
        block: str,
        on: str,
        at: str,
        direction: float | complex | Sequence[float] | str = 0.0,
        *,
        through: str | None = None,
        name: str | None = None,
    ) -> Linkage:
        """Add a prismatic joint: link ``block`` slides on link ``on`` (or ``"ground"``).

        The slide line is fixed in ``on``, passes through the drawn position of
        point ``at`` (a point of ``block``), with ``direction`` an angle in
        radians, a vector ``(dx, dy)``, or a point name of ``on`` on the line.
        ``through`` optionally names a point of ``on`` that must lie on the line
        (the drawing is checked). The slider displacement ``d`` is measured
        along the line from the foot of ``on``'s first point (or ``through``).
        The block turns with ``on`` (same angular velocity).

        Examples
        --------
        A slider-crank (crank 2, rod 6, no offset) drawn at θ2 = 0; the block is
        a one-point link (its pin B) sliding on the ground along +x:

        >>> import numpy as np
        >>> lk = (Linkage({"O2": (0, 0), "A": (2, 0), "B": (8, 0)}).ground("O2")
        ...       .link("crank", "O2", "A").link("rod", "A", "B").link("block", "B")
        ...       .slider("block", "ground", "B", 0.0, name="guide").drive("crank"))
        >>> m = lk.solve(np.radians([0.0, 90.0, 180.0]), velocity=10.0)
        >>> m.lengths["guide"].round(6).tolist()        # SliderCrank(2, 6): 8, √32, 4
        [8.0, 5.656854, 4.0]
        >>> m.length_rate["guide"].round(6).tolist()    # ḋ = −a ω2 at 90°
        [0.0, -20.0, -0.0]
        """
        name = name or f"{block}/{on}"
        if block not in self._links:
            raise ModelError(f"slider {name!r}: unknown link {block!r}; links: {self._names()}")
        if on != GROUND and on not in self._links:
            raise ModelError(f"slider {name!r}: unknown link {on!r}; links: {self._names()}")
        if at not in self._links[block].points:
            raise ModelError(f"slider {name!r}: point {at!r} is not on link {block!r}")
        u = self._line(f"slider {name!r}", direction, self._points[at], through)
        if self._joint_named(name):
            raise ModelError(f"joint name {name!r} is used twice")
        self._sliders[name] = (block, on, at, u, through)
        return self._changed()

    def slot(
        self,
        pin: str,
        link: str,
        on: str,
        direction: float | complex | Sequence[float] | str = 0.0,
        *,
        through: str | None = None,
        name: str | None = None,
    ) -> Linkage:
        """Add a pin-in-slot half joint: point ``pin`` of ``link`` in a straight slot of ``on``.

        The slot is fixed in ``on`` along ``direction`` through the drawn pin
        (as in :meth:`slider`); the pin may turn in it (two freedoms: a half
        joint in the Kutzbach count).

        Examples
        --------
        A Scotch yoke: the crank pin A runs in a vertical slot of a yoke that
        slides horizontally, so the yoke moves ``x = r cos θ2``:

        >>> import numpy as np
        >>> lk = (Linkage({"O2": (0, 0), "A": (2, 0), "Y": (5, 0)}).ground("O2")
        ...       .link("crank", "O2", "A").link("yoke", "Y")
        ...       .slider("yoke", "ground", "Y", 0.0, through="O2", name="guide")
        ...       .slot("A", "crank", "yoke", np.pi / 2).drive("crank"))
        >>> lk.mobility()
        1
        >>> m = lk.solve(np.radians([0.0, 60.0, 90.0]))
        >>> (m.points["Y"].real - 3.0).round(9).tolist()
        [2.0, 1.0, 0.0]
        """
        name = name or f"{pin}@{on}"
        if link not in self._links:
            raise ModelError(f"slot {name!r}: unknown link {link!r}; links: {self._names()}")
        if on != GROUND and on not in self._links:
            raise ModelError(f"slot {name!r}: unknown link {on!r}; links: {self._names()}")
        if pin not in self._links[link].points:
            raise ModelError(f"slot {name!r}: point {pin!r} is not on link {link!r}")
        u = self._line(f"slot {name!r}", direction, self._points[pin], through)
        if self._joint_named(name):
            raise ModelError(f"joint name {name!r} is used twice")
        self._slots[name] = (link, on, pin, u, through)
        return self._changed()

    def actuator(self, name: str, start: str, end: str, *, links: Sequence[str] = ()) -> Linkage:
        """Add a linear actuator (hydraulic cylinder, spring strut) between two points.

        It is pinned at both ends and has a variable length ``L`` (its barrel
        and rod are massless and count as two links, two pins and a prismatic
        joint: no change of mobility). Drive it with :meth:`drive` (length
        driver); an undriven actuator slides freely and carries no force.

        Parameters
        ----------
        name : str
            Its name (also the driver name).
        start, end : str
            Points where it is pinned.
        links : (link_a, link_b), optional
            The links carrying ``start`` and ``end`` when a point is shared by
            several links (default: the first link listing it, ground first).

        Examples
        --------
        >>> lk = Linkage({"C": (0, 0), "D": (3, 4)}).ground("C")
        >>> lk = lk.link("arm", "D", "C").actuator("cyl", "C", "D", links=("ground", "arm"))
        """
        if not isinstance(name, str) or not name:
            raise InputError("actuator", f"a name is a non-empty string, got {name!r}")
        if self._joint_named(name):
            raise ModelError(f"joint name {name!r} is used twice")
        self._need_points(f"actuator {name!r}", (start, end))
        ends = tuple(links)
        if ends and len(ends) != 2:
            raise InputError(f"{name}.links", f"give two link names, got {links!r}")
        for point, link in zip((start, end), ends, strict=False):
            self._owner(point, link)
        self._actuators[name] = (start, end, *(ends or ("", "")))
        return self._changed()

    def roll(
        self,
        link_a: str,
        centre_a: str,
        radius_a: float,
        link_b: str,
        centre_b: str,
        radius_b: float,
        *,
        internal: bool = False,
        name: str | None = None,
    ) -> Linkage:
        """Add a rolling contact without slip between two circular profiles.

        A circle of radius ``radius_a`` about point ``centre_a`` of ``link_a``
        rolls on a circle of radius ``radius_b`` about point ``centre_b`` of
        ``link_b`` (either may be ``"ground"``): friction wheels, a wheel on a
        curved track, a planet in a ring (``internal=True``). With
        ``radius_b = inf`` the profile of ``link_b`` is straight (a wheel on
        the ground, a pinion on a rack): ``centre_b`` is then the point of
        ``link_b`` where the two touch in the drawing, and the straight profile
        is the tangent there.

        The profiles must touch in the drawing: ``|centre_a − centre_b|`` is
        ``radius_a + radius_b`` (external), ``|radius_a − radius_b|``
        (internal), or ``radius_a`` (straight profile). Kinematics: the centre
        distance stays constant (a vector ``d e^{jφ}`` of constant length
        between the centres) and the contact points do not slip,
        ``ρa (θa − φ) = ρb (θb − φ) + const`` with signed radii ``ρ`` (Norton
        §2.3: rolling without slip is a full joint). When both centres are
        points of one link (two wheels on fixed pivots, a planet on its arm)
        that distance is already fixed: the contact then only adds the no-slip
        condition, counts as a half joint, and transmits only its tangential
        force (the normal preload is statically indeterminate and taken as 0).
        Otherwise it transmits a force with normal and tangential components
        at the contact point (see :attr:`LinkageForces.rolling`).

        Parameters
        ----------
        link_a, link_b : str
            The two links (or ``"ground"``).
        centre_a, centre_b : str
            Centre of each circle, a point of that link (for a straight profile
            the drawn contact point on ``link_b``).
        radius_a, radius_b : float
            Radii, positive; ``radius_b`` may be ``inf`` (straight profile).
        internal : bool
            Internal contact (one circle inside the other, like a ring gear).
        name : str, optional
            Joint name (default ``"link_a~link_b"``).

        Examples
        --------
        Two friction wheels on fixed pivots, radii 2 and 3: ``ω3 = −(2/3) ω2``:

        >>> import numpy as np
        >>> lk = (Linkage({"O2": (0, 0), "O3": (5, 0), "P": (2, 0), "Q": (5, 3)})
        ...       .ground("O2", "O3").link("w2", "O2", "P").link("w3", "O3", "Q")
        ...       .roll("w2", "O2", 2.0, "w3", "O3", 3.0).drive("w2"))
        >>> lk.mobility()
        1
        >>> m = lk.solve(np.radians([0.0, 30.0]), velocity=6.0)
        >>> m.omega["w3"].round(12).tolist()
        [-4.0, -4.0]
        """
        name = name or f"{link_a}~{link_b}"
        if not isinstance(name, str) or not name:
            raise InputError("roll", f"a joint name is a non-empty string, got {name!r}")
        if self._joint_named(name):
            raise ModelError(f"joint name {name!r} is used twice")
        for link, centre in ((link_a, centre_a), (link_b, centre_b)):
            if link != GROUND and link not in self._links:
                raise ModelError(f"roll {name!r}: unknown link {link!r}; links: {self._names()}")
            self._need_points(f"roll {name!r}", [centre])
            pts = self._ground if link == GROUND else self._links[link].points
            if centre not in pts:
                raise ModelError(f"roll {name!r}: point {centre!r} is not on link {link!r}")
        if link_a == link_b:
            raise ModelError(f"roll {name!r} joins link {link_a!r} to itself")
        if _is_inf(radius_a):
            raise InputError(
                f"{name}.radius_a",
                "only link_b may have a straight profile: swap the two links (radius_b = inf)",
            )
        r_a = finite_scalar(f"{name}.radius_a", radius_a)
        if r_a <= 0:
            raise InputError(f"{name}.radius_a", f"must be a positive radius, got {r_a:g}")
        r_b = np.inf if _is_inf(radius_b) else finite_scalar(f"{name}.radius_b", radius_b)
        if np.isnan(r_b) or r_b <= 0 or r_b == -np.inf:
            raise InputError(
                f"{name}.radius_b",
                f"must be a positive radius (or inf for a straight profile), got {radius_b!r}",
            )
        internal = bool(internal)
        d = abs(self._points[centre_b] - self._points[centre_a])
        if np.isinf(r_b):
            if internal:
                raise InputError(
                    f"{name}.internal", "a straight profile (radius_b = inf) has no inside"
                )
            want, what = r_a, "radius_a (centre_b is the contact point on the straight profile)"
        elif internal:
            if r_a == r_b:
                raise InputError(
                    f"{name}.radius_b", "internal contact needs different radii (got equal ones)"
                )
            want, what = abs(r_a - r_b), "|radius_a - radius_b| (internal contact)"
        else:
            want, what = r_a + r_b, "radius_a + radius_b (external contact)"
        if abs(d - want) > 1e-9 * max(want, d):
            raise InputError(
                f"{name}.centre_b",
                f"the profiles do not touch in the drawing: |{centre_a} - {centre_b}| = {d:.10g} "
                f"but it must equal {what} = {want:.10g}",
            )
        self._rolls[name] = (link_a, centre_a, r_a, link_b, centre_b, r_b, internal)
        return self._changed()

    def motor(self, name: str, at: str, *, links: Sequence[str] | None = None) -> Linkage:
        """Add a rotary motor at pin ``at`` between two moving links (an elbow, a wrist).

        Driven with :meth:`drive`, its variable is the **relative angle**
        ``phi = theta_b − theta_a`` of the second link to the first (CCW
        positive, radians, each ``theta`` as in :meth:`link`: the angle of the
        line from the link's first point to its second), and its effort is the
        torque ``T`` of link *a* on link *b* (``−T`` acts on *a*). An undriven
        motor is a free pin and carries no torque. A pin on the ground needs no
        motor: drive the link itself (its absolute angle).

        Parameters
        ----------
        name : str
            The motor's name (also the driver name).
        at : str
            The pin: a point shared by two (or more) moving links.
        links : (link_a, link_b), optional
            The two links it joins, ``phi`` being ``b``'s angle relative to
            ``a``'s; needed when the pin joins more than two links. Default:
            the two links carrying ``at``, in the order they were defined.

        Examples
        --------
        The HW 6 four-bar (GCRR 8-4-7-6) driven at its joint A by a motor on
        the crank turning the coupler: drawn at θ2 = 0, where θ3 = 58.81°
        (HW 6), so ``phi = θ3 − θ2`` is 58.81° there and θ2 follows from it:

        >>> import numpy as np
        >>> lk = (Linkage({"O2": (0, 0), "O4": (8, 0), "A": (4, 0),
        ...                "B": (7.625, np.sqrt(49 - 3.625**2))})
        ...       .ground("O2", "O4").link("crank", "O2", "A").link("coupler", "A", "B")
        ...       .link("rocker", "O4", "B").motor("elbow", "A").drive("elbow"))
        >>> m = lk.solve(np.radians([58.81, 30.0]), velocity=1.0)
        >>> np.degrees(m.theta["crank"]).round(2).tolist()[0]
        0.0
        >>> bool(np.allclose(m.omega["coupler"] - m.omega["crank"], 1.0))
        True
        """
        if not isinstance(name, str) or not name:
            raise InputError("motor", f"a motor name is a non-empty string, got {name!r}")
        if name in self._links or name == GROUND:
            raise ModelError(f"motor {name!r}: the name is a link's; give the motor its own name")
        if self._joint_named(name):
            raise ModelError(f"joint name {name!r} is used twice")
        self._need_points(f"motor {name!r}", [at])
        pair: tuple[str, str] | None = None
        if links is not None:
            given = tuple(links) if isinstance(links, list | tuple) else ()
            if len(given) != 2 or not all(isinstance(n, str) for n in given):
                raise InputError(f"{name}.links", f"give two link names, got {links!r}")
            pair = (given[0], given[1])
            for n in pair:
                if n != GROUND and n not in self._links:
                    raise ModelError(f"motor {name!r}: unknown link {n!r}; links: {self._names()}")
            if pair[0] == pair[1]:
                raise ModelError(f"motor {name!r} joins link {pair[0]!r} to itself")
            if GROUND in pair:
                _ground_motor(name, at, pair)
        self._motors[name] = (at, pair)
        return self._changed()

    def _motor_links(self, name: str) -> tuple[str, str]:
        """The links ``(a, b)`` of motor ``name``, checked against its pin."""
        at, pair = self._motors[name]
        carriers = self._carriers(at)
        if pair is None:
            pair = self._pin_pair(f"motor {name!r}", at)
        for n in pair:
            if n not in carriers:
                raise ModelError(
                    f"motor {name!r}: point {at!r} is not on link {n!r} (it is on "
                    f"{', '.join(carriers) or 'no link'})"
                )
        if GROUND in pair:
            _ground_motor(name, at, pair)
        return pair

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
        ends = tuple(links)
        if ends and (len(ends) != 2 or not all(isinstance(n, str) for n in ends)):
            raise InputError(f"{name}.links", f"give two link names, got {links!r}")
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
            given = tuple(links) if isinstance(links, list | tuple) else ()
            if len(given) != 2 or not all(isinstance(n, str) for n in given):
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

    def _carriers(self, point: str) -> list[str]:
        """The ground (if the point is fixed) and the links carrying ``point``, in order."""
        out = [GROUND] if point in self._ground else []
        return out + [n for n, ln in self._links.items() if point in ln.points]

    def _pin_pair(self, what: str, at: str) -> tuple[str, str]:
        """The two links a pin ``at`` joins, for an element ``what`` given no ``links=``."""
        carriers = self._carriers(at)
        if len(carriers) < 2:
            raise ModelError(
                f"{what}: point {at!r} is no pin (it is on {', '.join(carriers) or 'no link'}); "
                "it sits on a point of two links"
            )
        if len(carriers) > 2:
            raise ModelError(
                f"{what}: pin {at!r} joins {len(carriers)} links ({', '.join(carriers)}); "
                "say which two with links=(link_a, link_b)"
            )
        return carriers[0], carriers[1]

    def drive(self, *names: str) -> Linkage:
        """Name the driver(s): a link (angle), a slider/slot (displacement), an actuator (length).

        A motor (:meth:`motor`) drives the relative angle of two moving links.

        The call declares the whole set of drivers; calling it again replaces them.

        Examples
        --------
        >>> lk = Linkage({"O2": (0, 0), "A": (1, 0)}).ground("O2").link("crank", "O2", "A")
        >>> lk = lk.drive("crank")
        """
        for n in names:
            if not isinstance(n, str):
                raise InputError("drive", f"name the drivers by their names (str), got {n!r}")
            known = (self._links, self._sliders, self._slots, self._actuators, self._motors)
            if all(n not in table for table in known):
                joints = [*self._sliders, *self._slots, *self._actuators, *self._motors]
                hint = ""
                if n.startswith("pin ") or n in self._points:
                    hint = " (a pin between two moving links is driven by a motor(name, at=...))"
                raise ModelError(
                    f"driver {n!r} is no link, slider, slot, actuator or motor; links: "
                    f"{self._names()}; joints: {', '.join(joints) or '(none)'}{hint}"
                )
        self._drivers = list(dict.fromkeys(names))
        return self._changed()

    def _joint_named(self, name: str) -> bool:
        tables = (
            self._sliders,
            self._slots,
            self._actuators,
            self._rolls,
            self._motors,
            self._springs,
            self._torsions,
        )
        return any(name in t for t in tables)

    def _names(self) -> str:
        return ", ".join(self._links) or "(none)"

    # ------------------------------------------------------------------ structure
    def _owner(self, point: str, preferred: str = "") -> str:
        if preferred:
            if preferred == GROUND and point in self._ground:
                return GROUND
            if preferred in self._links and point in self._links[preferred].points:
                return preferred
            raise ModelError(f"point {point!r} is not on link {preferred!r}")
        if point in self._ground:
            return GROUND
        for ln in self._links.values():
            if point in ln.points:
                return ln.name
        raise ModelError(
            f"point {point!r} is on no link; the ends of an actuator or a spring must be on links"
        )

    def _edges(self) -> list[_Edge]:
        edges: list[_Edge] = []
        carriers: dict[str, list[str]] = {}
        for p in self._ground:
            carriers.setdefault(p, []).append(GROUND)
        for ln in self._links.values():
            for p in ln.points:
                carriers.setdefault(p, []).append(ln.name)
        for p, links in carriers.items():
            for other in links[1:]:
                edges.append(_Edge("R", f"pin {p}", links[0], other, p, p))
        for kind, table in (("P", self._sliders), ("slot", self._slots)):
            for jn, (moving, on, at, u, through) in table.items():
                ref = self._points[through] if through else self._first_point(on)
                foot = self._points[at] + u * ((ref - self._points[at]) * u.conjugate()).real
                key = f"{jn}:line"
                self._points_extra[key] = foot
                edges.append(_Edge(kind, jn, on, moving, key, at, u))
        for jn, (start, end, la, lb) in self._actuators.items():
            a, b = self._owner(start, la), self._owner(end, lb)
            if a == b:
                raise ModelError(f"actuator {jn!r} joins link {a!r} to itself")
            edges.append(_Edge("act", jn, a, b, start, end))
        for jn, (a, ca, r_a, b, cb, r_b, internal) in self._rolls.items():
            z = self._points[cb] - self._points[ca]
            if np.isinf(r_b):
                n0 = -z / abs(z)  # normal of the straight profile toward centre_a
                edges.append(
                    _Edge("roll", jn, a, b, ca, cb, n0, (r_a, np.inf), self._rack_guided(ca, b, n0))
                )
                continue
            if not internal:
                radii = (r_a, -r_b)
            elif r_a < r_b:
                radii = (-r_a, -r_b)
            else:
                radii = (r_a, r_b)
            carriers = [self._ground, *(ln.points for ln in self._links.values())]
            carried = any(ca in pts and cb in pts for pts in carriers)
            edges.append(_Edge("roll", jn, a, b, ca, cb, radii=radii, carried=carried))
        return edges

    def _rack_guided(self, centre: str, rack: str, normal: complex) -> bool:
        """True when ``centre`` is on a link on which ``rack`` slides parallel to its profile.

        Then the distance from the centre to the straight profile is fixed by that
        slider already (a pinion on a fixed pivot, its rack on a guide), like two
        centres on one carrier.
        """
        carriers = {GROUND} if centre in self._ground else set()
        carriers |= {n for n, ln in self._links.items() if centre in ln.points}
        for block, on, _, u, _ in self._sliders.values():
            pair = {block, on}
            if (
                rack in pair
                and (pair - {rack}) & carriers
                and abs((u * normal.conjugate()).real) < 1e-9
            ):
                return True
        return False

    def _first_point(self, link: str) -> complex:
        if link == GROUND:
            return self._points[self._ground[0]] if self._ground else 0j
        return self._points[self._links[link].points[0]]

    def _xy(self, key: str) -> complex:
        return self._points[key] if key in self._points else self._points_extra[key]

    def mobility(self) -> int:
        """Kutzbach–Gruebler mobility ``M = 3(L − 1) − 2 J1 − J2`` of the drawing.

        An actuator counts as two links, two pins and a prismatic joint.

        Examples
        --------
        >>> lk = Linkage({"O2": (0, 0), "O4": (8, 0), "A": (4, 0), "B": (7, 5)})
        >>> lk.ground("O2", "O4").link("c", "O2", "A").link("k", "A", "B").link(
        ...     "r", "O4", "B").mobility()
        1
        """
        self._points_extra: dict[str, complex] = {}
        joints: list[tuple[str, tuple[str, ...]]] = []
        for e in self._edges():
            if e.kind == "R":
                joints.append(("R", (e.a, e.b)))
            elif e.kind == "P":
                joints.append(("P", (e.a, e.b)))
            elif e.kind == "slot":
                joints.append(("pin-in-slot", (e.a, e.b)))
            elif e.kind == "roll":  # a carried contact only adds the no-slip condition
                joints.append(("half" if e.carried else "rolling", (e.a, e.b)))
            else:
                barrel, rod = f"{e.name}#barrel", f"{e.name}#rod"
                joints += [("R", (e.a, barrel)), ("P", (barrel, rod)), ("R", (rod, e.b))]
        n_links = 1 + len(self._links) + 2 * len(self._actuators)
        if not joints:
            return 3 * (n_links - 1)
        return mobility_of(joints, links=n_links)

    def _compile(self) -> _Compiled:
        if self._compiled is not None:
            return self._compiled
        if not self._ground:
            raise ModelError("no ground points: name the fixed pivots with ground('O2', ...)")
        self._points_extra = {}
        edges = self._edges()
        count = {n: 0 for n in self._links}
        for e in edges:
            for n in (e.a, e.b):
                if n in count:
                    count[n] += 1
        # one joint is enough for a link whose angle is driven (absolutely or by a motor):
        # it hangs on that pin, an open chain
        driven = set(self._drivers) | {
            ln for mn in self._motors if mn in self._drivers for ln in self._motor_links(mn)
        }
        few = [n for n, k in count.items() if k == 0 or (k == 1 and n not in driven)]
        if few:
            raise ModelError(
                f"link(s) {', '.join(few)} have fewer than two joints (a link on one pin "
                "swings freely unless its angle is driven: drive(link), or a motor at the "
                "pin); check the point names shared with other links"
            )
        m = self.mobility()
        if not self._drivers:
            raise ModelError(f"mobility is {m} but no driver was named: call drive(...)")
        if m != len(self._drivers):
            raise ModelError(
                f"mobility (Kutzbach–Gruebler) is {m} but {len(self._drivers)} driver(s) were "
                f"named ({', '.join(self._drivers)}): name {m} driver(s)"
                + (" — the drawing is a structure" if m <= 0 else "")
            )
        for name in [*self._springs, *self._torsions]:
            self._element_links(name)  # ends on two different links
        self._compiled = _compile(self, edges)
        return self._compiled

    # ------------------------------------------------------------------ solving
    def loop_system(self) -> LoopSystem:
        """The compiled :class:`~machdyn.loops.LoopSystem` (loops, constraints, inputs).

        Examples
        --------
        >>> lk = Linkage({"O2": (0, 0), "O4": (8, 0), "A": (4, 0), "B": (7, 5)})
        >>> lk = lk.ground("O2", "O4").link("crank", "O2", "A").link("coupler", "A", "B")
        >>> lk = lk.link("rocker", "O4", "B").drive("crank")
        >>> print(lk.loop_system().check())  # doctest: +ELLIPSIS
        3 variables, 2 equations: DOF 1
        ...
        """
        return self._compile().system

    def solve(
        self,
        values: Any,
        velocity: Any = None,
        acceleration: Any = 0.0,
        *,
        continuation: bool | None = None,
    ) -> LinkageMotion:
        """Positions, velocities and accelerations of every link, point and centre of mass.

        Parameters
        ----------
        values : array_like or mapping of driver name to array_like
            Driver values: link angles in radians (absolute, as ``theta``),
            motor angles (``theta_b − theta_a``, radians),
            slider displacements or actuator lengths. A plain array when there
            is one driver.
        velocity, acceleration : array_like or mapping, optional
            Their first and second time derivatives (``acceleration`` defaults
            to 0). Without ``velocity`` only positions are computed.
        continuation : bool, optional
            Follow a 1-D sweep along one circuit (default for 1-D arrays).
            The circuit is the drawn one: the solver first marches from the
            drawn pose to the first value.

        Returns
        -------
        LinkageMotion

        Examples
        --------
        A four-bar drawn in one pose and swept through a full turn of the crank:

        >>> import numpy as np
        >>> lk = (Linkage({"O2": (0, 0), "O4": (8, 0), "A": (0, 2), "B": (5.0, 5.0)})
        ...       .ground("O2", "O4").link("crank", "O2", "A").link("coupler", "A", "B")
        ...       .link("rocker", "O4", "B").drive("crank"))
        >>> m = lk.solve(np.radians(np.arange(0, 360, 10.0)), velocity=2.0)
        >>> bool(m.ok.all()), m.omega["rocker"].shape
        (True, (36,))
        """
        c = self._compile()
        drivers = tuple(self._drivers)
        vals = self._per_driver("values", values, drivers, required=True)
        vel = None if velocity is None else self._per_driver("velocity", velocity, drivers, True)
        acc = self._per_driver("acceleration", acceleration, drivers, False)
        if vel is None and acceleration is not None and not _is_zero(acceleration):
            raise ModelError("acceleration needs the driver velocity too (velocity=...)")
        shape = np.broadcast_shapes(*(np.shape(v) for v in vals.values()))
        u = {
            var: np.broadcast_to(vals[d], shape) - off
            for d, var, off in zip(drivers, c.driver_vars, c.driver_offsets, strict=True)
        }
        unknowns = [n for n in c.drawn if n not in c.driver_vars]
        guess = {n: c.drawn[n] for n in unknowns}
        cont = (
            continuation if continuation is not None else (len(shape) <= 1 and np.prod(shape) > 1)
        )
        if cont or np.prod(shape) == 1:  # follow the drawn circuit to the first sample
            _check_drawn_pose(c)
            guess = _march(c, guess, {k: float(np.ravel(v)[0]) for k, v in u.items()})
        kw: dict[str, Any] = {"continuation": cont}
        if vel is not None:
            kw["velocity"] = {var: vel[d] for d, var in zip(drivers, c.driver_vars, strict=True)}
            kw["acceleration"] = {
                var: acc[d] for d, var in zip(drivers, c.driver_vars, strict=True)
            }
            kw["order"] = 2
        lm = c.system.solve(u, guess, **kw)
        return _motion(self, c, lm, vals)

    @staticmethod
    def _per_driver(field: str, value: Any, drivers: tuple[str, ...], required: bool):
        if isinstance(value, Mapping):
            extra = [k for k in value if k not in drivers]
            if extra:
                raise ModelError(
                    f"{field} given for {', '.join(extra)}, which are not drivers "
                    f"({', '.join(drivers)})"
                )
            missing = [d for d in drivers if d not in value]
            if missing and required:
                raise ModelError(f"{field}: no value for driver(s) {', '.join(missing)}")
            return {d: finite_array(f"{field}[{d}]", value.get(d, 0.0)) for d in drivers}
        if len(drivers) != 1 and not required and np.ndim(value) == 0:
            return {d: finite_array(f"{field}[{d}]", value) for d in drivers}
        if len(drivers) != 1:
            raise ModelError(
                f"{field}: give a mapping {{driver: values}} for the drivers {', '.join(drivers)}"
            )
        return {drivers[0]: finite_array(field, value)}

    # ------------------------------------------------------------------ forces
    def forces(
        self,
        motion: LinkageMotion,
        *,
        gravity: float = 0.0,
        external_forces: Iterable[tuple[str, Any, Any]] = (),
        external_torques: Mapping[str, Any] | Iterable[tuple[str, Any]] = (),
        viscous: Mapping[str, float] | None = None,
        coulomb: Mapping[str, float] | None = None,
    ) -> LinkageForces:
        """Newton–Euler joint forces and driver efforts for every sample of ``motion``.

        Three equations per moving link (Norton eq. 11.9; the notes' matrix
        method): ``ΣF = m a_G`` and ``ΣM_G = I_G α``. Unknowns: the force
        ``F_ap`` of every pin (force on link *p* from link *a*), the normal
        force and couple of every prismatic joint, the normal force of every
        slot, and the driver torque (angle driver: a motor between the ground
        and the link; :meth:`motor`: the torque on its link *b*, ``−T`` on
        *a*) or force (slider driver: along the slide; actuator driver:
        positive when it pushes its ends apart). Springs and dampers
        (:meth:`spring`, :meth:`torsion_spring`) are known loads from the
        motion, reported in ``elements``, ``element_length`` and ``element_rate``.

        Parameters
        ----------
        motion : LinkageMotion
            From :meth:`solve` with ``velocity`` given.
        gravity : float
            ``g ≥ 0`` along −y.
        external_forces : iterable of (link, point, force)
            ``point`` a point name or a complex position in the link frame
            (origin at its first point, x toward its second); ``force`` complex
            ``Fx + j Fy``, one value or one per sample.
        external_torques : mapping link → torque, or (link, torque) pairs
            CCW positive; scalars or per-sample arrays.
        viscous : mapping of slider name → β, optional
            Viscous friction at sliders, ``−β·v_slip`` along the slide on the block.
        coulomb : mapping of slider or slot name → μ, optional
            Coulomb friction ``−μ |N| sign(v_slip)`` along the slide (at rest the
            impending direction, the sign of the slide acceleration). The sign of
            ``N`` is found by re-solving until it agrees with the assumption;
            samples where it never does are flagged.

        Returns
        -------
        LinkageForces

        Examples
        --------
        A massless slider-crank at θ2 = 90° with a load F = −50 on the piston
        (along −x): by virtual work ``T12 ω2 + F ḋ = 0``, with ḋ = −a ω2 = −2:

        >>> import numpy as np
        >>> lk = (Linkage({"O2": (0, 0), "A": (2, 0), "B": (8, 0)}).ground("O2")
        ...       .link("crank", "O2", "A").link("rod", "A", "B").link("block", "B")
        ...       .slider("block", "ground", "B", 0.0, name="guide").drive("crank"))
        >>> m = lk.solve(np.radians(90.0), velocity=1.0)
        >>> f = lk.forces(m, external_forces=[("block", "B", -50.0)])
        >>> round(float(f.driver["crank"]), 9), round(float(m.length_rate["guide"]), 9)
        (-100.0, -2.0)
        """
        return _forces(
            self, motion, gravity, external_forces, external_torques, viscous or {}, coulomb or {}
        )


def _same_link(what: str, name: str, link: str) -> NoReturn:
    """Refuse a spring whose two ends are on one link: its load would be internal."""
    raise ModelError(
        f"{what} {name!r}: both ends are on link {link!r}, so its load is internal to that "
        "rigid link and does nothing (its length or angle never changes); attach it to two "
        "different links (or a link and the ground)"
    )


def _ground_motor(name: str, at: str, pair: tuple[str, str]) -> NoReturn:
    """Refuse a motor on a ground pin: it is an ordinary link driver."""
    other = pair[1] if pair[0] == GROUND else pair[0]
    raise ModelError(
        f"motor {name!r}: pin {at!r} joins the ground, so the motor turns {other!r} "
        f"by its absolute angle — that is an ordinary link driver: drive({other!r})"
    )


def _is_inf(value: Any) -> bool:
    try:
        return bool(np.isposinf(float(magnitude(value))))
    except (TypeError, ValueError):
        return False


def _is_zero(value: Any) -> bool:
    if isinstance(value, Mapping):
        return all(np.all(np.asarray(v) == 0) for v in value.values())
    return bool(np.all(np.asarray(value) == 0))


# ---------------------------------------------------------------------- compilation
def _ident(text: str) -> str:
    """A loop-variable name made of ``text`` (non-word characters become ``_``)."""
    return _IDENT.sub("_", text)


def _compile(lk: Linkage, edges: list[_Edge]) -> _Compiled:
    links = [GROUND, *lk._links]
    adj: dict[str, list[int]] = {n: [] for n in links}
    for i, e in enumerate(edges):
        adj[e.a].append(i)
        adj[e.b].append(i)
    # spanning tree by breadth-first search from the ground
    parent: dict[str, tuple[int, str] | None] = {GROUND: None}
    order = [GROUND]
    depth = {GROUND: 0}
    tree_edges: set[int] = set()
    tree: list[tuple[str, _Edge, bool]] = []
    for node in order:
        for i in adj[node]:
            e = edges[i]
            other = e.b if e.a == node else e.a
            if other not in parent:
                parent[other] = (i, node)
                depth[other] = depth[node] + 1
                order.append(other)
                tree_edges.add(i)
                tree.append((other, e, other == e.b))
    loose = [n for n in links if n not in parent]
    if loose:
        raise ModelError(
            f"link(s) {', '.join(loose)} are not connected to the ground by any joint chain"
        )
    # rotation classes: links joined by a prismatic joint turn together
    cls = {n: n for n in links}

    def find(n: str) -> str:
        while cls[n] != n:
            n = cls[n]
        return n

    for e in edges:
        if e.kind == "P":
            ra, rb = find(e.a), find(e.b)
            if ra != rb:
                if rb == GROUND:
                    ra, rb = rb, ra
                cls[rb] = ra

    def xy_on(link: str, e: _Edge) -> str:
        return e.pa if link == e.a else e.pb

    # fundamental cycles: one per chord
    cycles: list[list[tuple[int, str, str]]] = []  # (edge, from link, to link)
    on_loop: set[int] = set()
    for i, e in enumerate(edges):
        if i in tree_edges:
            continue
        a, b = e.a, e.b
        up_a: list[tuple[int, str, str]] = []
        up_b: list[tuple[int, str, str]] = []
        while depth[a] > depth[b]:
            j, p = parent[a]
            up_a.append((j, a, p))
            a = p
        while depth[b] > depth[a]:
            j, p = parent[b]
            up_b.append((j, b, p))
            b = p
        while a != b:
            j, p = parent[a]
            up_a.append((j, a, p))
            a = p
            j, p = parent[b]
            up_b.append((j, b, p))
            b = p
        # walk: e.a -> ... -> lca -> ... -> e.b, then cross e from e.b to e.a
        walk = up_a + [(j, t, f) for j, f, t in reversed(up_b)] + [(i, e.b, e.a)]
        cycles.append(walk)
        on_loop.update(j for j, _, _ in walk)
    # A pin on no loop (an open chain: a lid, an arm) leaves the links beyond it free to
    # turn: each such link gets an angle variable of its own below, which a driver (or a
    # motor) must then fix. Any other joint must be on a loop.
    hanging = {
        n for i, e in enumerate(edges) if i not in on_loop and e.kind == "R" for n in (e.a, e.b)
    } - {GROUND}
    bridges = [e.name for i, e in enumerate(edges) if i not in on_loop and e.kind != "R"]
    if bridges:
        raise ModelError(
            f"joint(s) {', '.join(bridges)} lie on no closed loop: only a pin may hang a "
            "link outside the loops (an open chain, its angle driven); add the missing joints"
        )

    system = LoopSystem()
    vec_of: dict[tuple[str, str, str], tuple[str, int]] = {}  # (link, p, q) -> (vector, sign)
    class_var: dict[str, tuple[str, float]] = {}  # class root -> (variable, drawn angle)
    drawn: dict[str, float] = {}
    used_names: set[str] = set()

    def fresh(base: str) -> str:
        name = _ident(base)
        k, out = 1, name
        while out in used_names:
            k += 1
            out = f"{name}_{k}"
        used_names.add(out)
        return out

    def angle_of(link: str, ang0: float, tag: str) -> str | float:
        """Angle variable (or constant) of a vector fixed in ``link`` drawn at ``ang0``."""
        root = find(link)
        if root == GROUND:
            return ang0
        if root not in class_var:
            var = fresh(f"theta_{root}")
            class_var[root] = (var, ang0)
            drawn[var] = ang0
            return var
        var0, a0 = class_var[root]
        var = fresh(f"theta_{link}_{tag}")
        system.constraint(f"{var} = {var0} + alpha", alpha=ang0 - a0)
        drawn[var] = ang0
        return var

    # every vector of a moving link starts at its hub (the joint where the spanning
    # tree enters it), so a link with k joints has at most k - 1 vectors and never
    # the redundant triangle of a ternary link
    hub = {child: (e.pb if child_is_b else e.pa) for child, e, child_is_b in tree}

    def link_path(link: str, p: str, q: str) -> list[tuple[str, int]]:
        """Vectors of ``link`` leading from its joint ``p`` to its joint ``q``."""
        if p == q:
            return []
        if link == GROUND or hub[link] in (p, q):
            v = link_vector(link, p, q)
            return [] if v is None else [v]
        out = []
        for x, sign in ((p, -1), (q, 1)):
            v = link_vector(link, hub[link], x)
            if v is not None:
                out.append((v[0], sign * v[1]))
        return out

    def link_vector(link: str, p: str, q: str) -> tuple[str, int] | None:
        if p == q:
            return None
        if (link, p, q) in vec_of:
            return vec_of[(link, p, q)]
        if (link, q, p) in vec_of:
            name, s = vec_of[(link, q, p)]
            return name, -s
        z = lk._xy(q) - lk._xy(p)
        if abs(z) == 0:
            return None
        name = fresh(f"R_{link}_{p}{q}")
        ang = angle_of(link, float(np.angle(z)), f"{p}{q}")
        system.vector(name, float(abs(z)), ang)
        vec_of[(link, p, q)] = (name, 1)
        return name, 1

    cross_vars: dict[str, tuple[str, str | None, float]] = {}
    cross_vec: dict[int, list[tuple[str, int]]] = {}
    roll_parts: dict[str, tuple[tuple[float, float | str, float | str], ...]] = {}

    def crossing(i: int) -> list[tuple[str, int]]:
        """Vectors (with signs) crossing joint ``i`` from its point on ``a`` to ``b``'s."""
        e = edges[i]
        if e.kind == "R":
            return []
        if i not in cross_vec:
            cross_vec[i] = roll_crossing(e) if e.kind == "roll" else [(new_crossing(e), 1)]
        return cross_vec[i]

    def roll_crossing(e: _Edge) -> list[tuple[str, int]]:
        z = lk._xy(e.pb) - lk._xy(e.pa)
        if np.isinf(e.radii[1]):  # centre_a -> contact line point: -(s û + r n̂), fixed in b
            n0 = e.direction
            svar = fresh(f"s_{e.name}")
            drawn[svar] = 0.0
            ang_u = angle_of(e.b, float(np.angle(1j * n0)), f"tan_{e.name}")
            ang_n = angle_of(e.b, float(np.angle(n0)), f"nor_{e.name}")
            ru, rn = fresh(f"R_{e.name}_s"), fresh(f"R_{e.name}_n")
            system.vector(ru, svar, ang_u)
            height: float | str = e.radii[0]
            if e.carried:  # the guide fixes the height already: a free length
                height = fresh(f"h_{e.name}")
                drawn[height] = e.radii[0]
            system.vector(rn, height, ang_n)
            roll_parts[e.name] = ((-1.0, svar, ang_u), (-1.0, height, ang_n))
            return [(ru, -1), (rn, -1)]
        name, pvar = fresh(f"R_{e.name}"), fresh(f"phi_{e.name}")
        drawn[pvar] = float(np.angle(z))
        if e.carried:  # the distance is fixed by the carrier: a free length, no redundancy
            length: float | str = fresh(f"L_{e.name}")
            drawn[length] = float(abs(z))
        else:
            length = float(abs(z))
        system.vector(name, length, pvar)
        roll_parts[e.name] = ((1.0, length, pvar),)
        return [(name, 1)]

    def new_crossing(e: _Edge) -> str:
        name = fresh(f"R_{e.name}")
        z = lk._xy(e.pb) - lk._xy(e.pa)
        if e.kind in ("P", "slot"):
            dvar = fresh(f"d_{e.name}")
            d0 = float((z * e.direction.conjugate()).real)
            drawn[dvar] = d0
            ang = angle_of(e.a, float(np.angle(e.direction)), f"dir_{e.name}")
            system.vector(name, dvar, ang)
            if isinstance(ang, str):
                cross_vars[e.name] = (dvar, ang, 0.0)
            else:
                cross_vars[e.name] = (dvar, None, ang)
        else:
            lvar, pvar = fresh(f"L_{e.name}"), fresh(f"phi_{e.name}")
            if abs(z) == 0:
                raise AssemblyError(f"actuator {e.name!r} has zero length in the drawing")
            drawn[lvar], drawn[pvar] = float(abs(z)), float(np.angle(z))
            system.vector(name, lvar, pvar)
            cross_vars[e.name] = (lvar, pvar, 0.0)
        return name

    for walk in cycles:
        terms: list[tuple[str, int]] = []
        for k, (j, f, t) in enumerate(walk):
            e = edges[j]
            terms += [(v, s if f == e.a else -s) for v, s in crossing(j)]
            nj = walk[(k + 1) % len(walk)][0]
            link = t
            terms += link_path(link, xy_on(link, e), xy_on(link, edges[nj]))
        merged: dict[str, int] = {}
        for n, s in terms:
            merged[n] = merged.get(n, 0) + s
        text = " ".join(f"{'+' if s > 0 else '-'} {n}" for n, s in merged.items() if s)
        if not text:
            continue
        text = text[2:] if text.startswith("+ ") else "-" + text[1:]
        system.loop(text)
    # a joint on no loop is a pin (others were refused): it has no crossing vector
    for e in edges:
        if e.kind == "act" and e.name not in cross_vars:
            raise ModelError(f"actuator {e.name!r} is on no loop")

    def give_angle(n: str) -> None:
        """Give link ``n``'s rotation class an angle variable if it has none yet.

        The variable is the angle of a reference vector (named as a point), so that
        the core counts it as a variable of the loop system.
        """
        if find(n) != GROUND and find(n) not in class_var:
            ref = fresh(f"R_{n}_ref")
            system.vector(ref, 1.0, angle_of(n, _ref_angle(lk, n), "ref"))
            system.point(fresh(f"P_{n}_ref"), ref)

    # rolling: every link in contact needs an angle variable (a wheel turning on a
    # pivot may be in no loop), then the no-slip condition is a linear constraint
    # among angles (and s or φ)
    for i, e in enumerate(edges):
        if e.kind != "roll":
            continue
        for n in (e.a, e.b):
            give_angle(n)
        crossing(i)
        text, consts = _no_slip(e, roll_parts[e.name], class_var, find, drawn)
        system.constraint(text, **consts)
    for n in links:
        if n in hanging:  # a link hanging on a pin outside the loops (an open chain)
            give_angle(n)
    # every moving rotation class must have an angle variable
    rot_var: dict[str, str | None] = {}
    rot_offset: dict[str, float] = {}
    undetermined = []
    for n in links:
        root = find(n)
        ref = _ref_angle(lk, n)
        if root == GROUND:
            rot_var[n], rot_offset[n] = None, 0.0
        elif root in class_var:
            var, a0 = class_var[root]
            rot_var[n], rot_offset[n] = var, ref - a0
        else:
            undetermined.append(n)
    if undetermined:
        raise ModelError(
            f"the orientation of link(s) {', '.join(undetermined)} is not fixed by any loop "
            "(all their joints at one point?)"
        )
    # motors: phi = theta_b - theta_a, a linear constraint; phi is the angle of a
    # reference vector (named as a point) so that the core counts it as a variable
    motor_vars = {}
    for mn in lk._motors:
        a, b = lk._motor_links(mn)
        if mn in lk._drivers:
            motor_vars[mn] = _motor_variable(system, fresh, lk, mn, a, b, rot_var, rot_offset)
            drawn[motor_vars[mn]] = _ref_angle(lk, b) - _ref_angle(lk, a)
    driver_vars, driver_offsets = [], []
    for d in lk._drivers:
        if d in motor_vars:
            driver_vars.append(motor_vars[d])
            driver_offsets.append(0.0)
        elif d in lk._links:
            var = rot_var[d]
            if var is None:
                raise ModelError(f"driver {d!r} cannot turn: it slides on the ground")
            driver_vars.append(var)
            driver_offsets.append(rot_offset[d])
        else:
            driver_vars.append(cross_vars[d][0])
            driver_offsets.append(0.0)
    if len(set(driver_vars)) != len(driver_vars):
        raise ModelError(f"drivers {', '.join(lk._drivers)} drive the same variable")
    system.inputs(*driver_vars)
    system.check()
    return _Compiled(
        system=system,
        driver_vars=tuple(driver_vars),
        driver_offsets=tuple(driver_offsets),
        drawn=drawn,
        rot_var=rot_var,
        rot_offset=rot_offset,
        tree=tuple(tree),
        cross_vars=cross_vars,
        roll_parts=roll_parts,
    )


def _typical_length(lk: Linkage) -> float:
    """The mean distance from each link's first point to its others (1 if there is none)."""
    sizes = [
        abs(lk._points[q] - lk._points[ln.points[0]])
        for ln in lk._links.values()
        for q in ln.points[1:]
    ]
    sizes = [d for d in sizes if d > 0]
    return float(np.mean(sizes)) if sizes else 1.0


def _motor_variable(
    system: LoopSystem,
    fresh: Callable[[str], str],
    lk: Linkage,
    name: str,
    a: str,
    b: str,
    rot_var: dict[str, str | None],
    rot_offset: dict[str, float],
) -> str:
    """Add motor ``name``'s relative angle ``phi = theta_b − theta_a`` to ``system``.

    With ``theta = var + offset`` for each link's rotation class the constraint
    is ``phi − var_b + var_a = offset_b − offset_a`` (a link that only slides on
    the ground has a constant angle: its term is a constant). ``phi`` is the
    angle of a reference vector reaching a point of its own, so that the core
    counts it as a variable of the loop system.
    """
    phi = fresh(f"phi_{name}")
    ref = fresh(f"R_{name}_ref")
    # its length, the mean link size, keeps the core's length scale (a mean) about as it was
    system.vector(ref, _typical_length(lk), phi)
    system.point(fresh(f"P_{name}_ref"), ref)
    terms, consts = [f"{phi}"], {"c_motor": 0.0}
    for link, sign in ((b, 1.0), (a, -1.0)):
        var = rot_var[link]
        theta0 = _ref_angle(lk, link) if var is None else rot_offset[link]
        consts["c_motor"] += sign * theta0
        if var is not None:
            terms.append(f"{'-' if sign > 0 else '+'} {var}")
    system.constraint(" ".join(terms) + " = c_motor", **consts)
    return phi


def _no_slip(
    e: _Edge,
    parts: tuple[tuple[float, float | str, float | str], ...],
    class_var: dict[str, tuple[str, float]],
    find: Callable[[str], str],
    drawn: dict[str, float],
) -> tuple[str, dict[str, float]]:
    """The no-slip condition of rolling joint ``e`` as a linear constraint.

    With the contact point ``C = A + ρa e^{jφ} = B + ρb e^{jφ}`` (A, B the centres,
    ``φ`` the angle of ``B − A``, ``ρa − ρb = d``), equal velocities of the two
    material points at C give ``ρa ωa − ρb ωb = d φ̇`` (the normal component holds
    by the constant distance); for a straight profile of b with its normal ``n̂``
    toward A and tangent ``û = j n̂``, ``ṡ = r (ωa − ωb)`` for the contact's
    abscissa ``s``. Integrated: ``Σ k·x = c`` with ``c`` from the drawing.
    """
    coefs: dict[str, float] = {}

    def add(link: str, k: float) -> None:
        root = find(link)
        if root != GROUND:
            var = class_var[root][0]
            coefs[var] = coefs.get(var, 0.0) + k

    rho_a, rho_b = e.radii
    if np.isinf(rho_b):
        svar = parts[0][1]
        coefs[svar] = 1.0
        add(e.a, -rho_a)
        add(e.b, rho_a)
    else:
        add(e.a, rho_a)
        add(e.b, -rho_b)
        phi = parts[0][2]
        coefs[phi] = coefs.get(phi, 0.0) - (rho_a - rho_b)
    terms = {v: k for v, k in coefs.items() if k != 0.0}
    consts = {f"k_roll_{i}": k for i, k in enumerate(terms.values())}
    consts["c_roll"] = sum(k * drawn[v] for v, k in terms.items())
    text = " + ".join(f"k_roll_{i}*{v}" for i, v in enumerate(terms)) + " = c_roll"
    return text, consts


def _ref_angle(lk: Linkage, link: str) -> float:
    if link == GROUND:
        return 0.0
    p = lk._links[link].points
    if len(p) < 2:
        return 0.0
    z = lk._points[p[1]] - lk._points[p[0]]
    return float(np.angle(z)) if abs(z) else 0.0


def _check_drawn_pose(c: _Compiled) -> None:
    """Refuse a drawing at a toggle: there the branches meet and it cannot pick one."""
    at = {k: np.array([v]) for k, v in c.drawn.items()}
    m = c.system.evaluate(at, velocity={v: 1.0 for v in c.driver_vars})
    if not bool(m.ok[0]):
        raise ModelError(
            "the drawing is at a toggle (two links in line), where the mechanism's "
            "branches meet, so it cannot say which one to follow: draw it in a pose "
            "away from the toggle"
        )


def _march(c: _Compiled, guess: dict[str, float], target: dict[str, float]) -> dict[str, float]:
    """Follow the drawn circuit from the drawn driver values to ``target``."""
    start = {v: c.drawn[v] for v in c.driver_vars}
    span = max(abs(target[v] - start[v]) for v in c.driver_vars)
    if span < 1e-12:
        return guess
    n = int(np.ceil(span / 0.05)) + 1
    path = {v: np.linspace(start[v], target[v], n) for v in c.driver_vars}
    m = c.system.solve(path, guess, continuation=True)
    if not bool(m.ok[-1]) and not np.isfinite(next(iter(m.positions.values()))[-1]):
        return guess
    last = {k: float(v[-1]) for k, v in m.positions.items() if k in guess}
    if not all(np.isfinite(x) for x in last.values()):
        return guess
    return last


# ---------------------------------------------------------------------- kinematics results
def _vector_motion(d, dd, ddd, phi, w, a) -> tuple[np.ndarray, Any, Any]:
    """``d e^{jφ}`` and its first two time derivatives (DESIGN.md's rules)."""
    e = np.exp(1j * phi)
    pos = d * e
    if dd is None:
        return pos, None, None
    vel = (dd + 1j * d * w) * e
    acc = (ddd - d * w * w + 1j * (d * a + 2.0 * dd * w)) * e
    return pos, vel, acc


@dataclass(frozen=True)
class LinkageMotion:
    """Kinematics of a :class:`Linkage` over a batch of driver values.

    Arrays have the broadcast shape of the driver values. Angles in radians,
    not wrapped; positions are complex ``x + jy``.

    Attributes
    ----------
    inputs : mapping of driver name to ndarray
        The driver values as given.
    theta, omega, alpha : mapping of link name to ndarray
        Angle of each moving link (its first→second point line), angular
        velocity and acceleration (None without ``velocity``).
    points, point_velocity, point_acceleration : mapping of point name to complex ndarray
        Every named point (joints and coupler points).
    cg, cg_velocity, cg_acceleration : mapping of link name to complex ndarray
        Centre of mass of each moving link (its first point for a massless link).
    lengths, length_rate, length_acceleration : mapping of joint name to ndarray
        Slider and slot displacements, actuator lengths, and their rates.
    ok : ndarray of bool
        True where assembled and away from toggles.
    reason : ndarray of str
        Why a sample is not ok ('' where it is).
    loop_motion : machdyn.loops.Motion
        The underlying vector-loop solution (every loop variable).
    angle_drivers : frozenset of str
        The drivers whose values are angles (links, motors), for labels.

    Examples
    --------
    >>> import numpy as np
    >>> lk = (Linkage({"O2": (0, 0), "O4": (8, 0), "A": (4, 0), "B": (7.625, 35.859375**0.5)})
    ...       .ground("O2", "O4").link("crank", "O2", "A").link("coupler", "A", "B")
    ...       .link("rocker", "O4", "B").drive("crank"))
    >>> m = lk.solve([0.0, 0.1], velocity=1.0)
    >>> sorted(m.theta), m.points["B"].shape
    (['coupler', 'crank', 'rocker'], (2,))
    """

    inputs: Mapping[str, np.ndarray]
    theta: Mapping[str, np.ndarray]
    omega: Mapping[str, np.ndarray] | None
    alpha: Mapping[str, np.ndarray] | None
    points: Mapping[str, np.ndarray]
    point_velocity: Mapping[str, np.ndarray] | None
    point_acceleration: Mapping[str, np.ndarray] | None
    cg: Mapping[str, np.ndarray]
    cg_velocity: Mapping[str, np.ndarray] | None
    cg_acceleration: Mapping[str, np.ndarray] | None
    lengths: Mapping[str, np.ndarray]
    length_rate: Mapping[str, np.ndarray] | None
    length_acceleration: Mapping[str, np.ndarray] | None
    ok: np.ndarray
    reason: np.ndarray
    loop_motion: Motion = field(repr=False)
    angle_drivers: frozenset[str] = frozenset()

    def angle(self, link: str) -> np.ndarray:
        """Angle ``theta`` of ``link`` (radians)."""
        return _lookup(self.theta, link, "link")

    def plot(self, links: Sequence[str] | None = None, ax: Any = None) -> Any:
        """Plot link angles (degrees) against the first driver (degrees if an angle).

        Parameters
        ----------
        links : sequence of str, optional
            Links to plot; default all but the driven ones.
        ax : matplotlib Axes, optional

        Returns
        -------
        matplotlib Axes
        """
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots()
        driver, x = next(iter(self.inputs.items()))
        is_angle = driver in self.angle_drivers
        xs = np.degrees(np.ravel(x)) if is_angle else np.ravel(x)
        names = [n for n in self.theta if n not in self.inputs] if links is None else links
        for name in names:
            ax.plot(xs, np.degrees(np.ravel(self.angle(name))), label=f"theta {name} [deg]")
        ax.set_xlabel(f"{driver} [deg]" if is_angle else driver)
        ax.legend()
        return ax

    def __len__(self) -> int:
        return int(self.ok.size)

    def to_pandas(self) -> Any:
        """One row per sample: drivers, link angles and rates, points, centres of mass.

        Columns ``theta_<link>``, ``omega_<link>``, ``alpha_<link>``, ``<P>_x``,
        ``<P>_y``, ``<P>_vx`` ..., ``G_<link>_x`` ..., ``ok``, ``reason``.
        """
        import pandas as pd

        cols: dict[str, np.ndarray] = {k: np.ravel(v) for k, v in self.inputs.items()}
        for tag, table in (("theta", self.theta), ("omega", self.omega), ("alpha", self.alpha)):
            for k, v in (table or {}).items():
                cols[f"{tag}_{k}"] = np.ravel(v)
        for k, v in self.lengths.items():
            cols[f"d_{k}"] = np.ravel(v)
        for prefix, groups in (
            ("", (self.points, self.point_velocity, self.point_acceleration)),
            ("G_", (self.cg, self.cg_velocity, self.cg_acceleration)),
        ):
            for tag, table in zip(("", "v", "a"), groups, strict=True):
                for k, v in (table or {}).items():
                    cols[f"{prefix}{k}_{tag}x"] = np.ravel(v).real
                    cols[f"{prefix}{k}_{tag}y"] = np.ravel(v).imag
        cols["ok"] = np.ravel(self.ok)
        cols["reason"] = np.ravel(self.reason)
        return pd.DataFrame(cols)


def _lookup(table: Mapping[str, np.ndarray] | None, key: str, what: str) -> np.ndarray:
    if table is None:
        raise ModelError("no rates were computed: solve with velocity=...")
    if key not in table:
        raise KeyError(f"unknown {what} {key!r}; known: {', '.join(table)}")
    return table[key]


def _motion(lk: Linkage, c: _Compiled, lm: Motion, vals: dict[str, np.ndarray]) -> LinkageMotion:
    rates = lm.velocity is not None
    shape = lm.ok.shape
    pos, vel, acc = lm.positions, lm.velocity, lm.acceleration
    zero = np.zeros(shape)

    def var(table, name):
        return zero if name is None else table[name]

    theta, omega, alpha, delta = {}, {}, {}, {}
    for n in [GROUND, *lk._links]:
        v = c.rot_var[n]
        ref0 = _ref_angle(lk, n)
        theta[n] = var(pos, v) + c.rot_offset[n] if v else np.full(shape, ref0)
        delta[n] = theta[n] - ref0
        if rates:
            omega[n], alpha[n] = var(vel, v) + 0.0, var(acc, v) + 0.0
    # anchors: one point per link, positioned along the spanning tree
    anchor: dict[str, tuple[complex, Any, Any, Any]] = {GROUND: (0j, zero + 0j, zero, zero)}

    def rigid(link: str, z: complex):
        z0, ap, av, aa = anchor[link]
        r = (z - z0) * np.exp(1j * delta[link])
        if not rates:
            return ap + r, None, None
        w, al = omega[link], alpha[link]
        return ap + r, av + 1j * w * r, aa + (1j * al - w * w) * r

    cross: dict[str, tuple[Any, Any, Any]] = {}
    for e_name, (lv, av_, fixed) in c.cross_vars.items():
        if av_ is None:  # direction fixed in the ground
            phi = np.full(shape, fixed)
            w = a = zero
        else:
            phi = pos[av_]
            w, a = (vel[av_], acc[av_]) if rates else (None, None)
        cross[e_name] = _vector_motion(
            pos[lv],
            vel[lv] if rates else None,
            acc[lv] if rates else None,
            phi,
            w,
            a,
        )
    for e_name, parts in c.roll_parts.items():
        total: list[Any] = [0j, 0j if rates else None, 0j if rates else None]
        for sign, length, ang in parts:
            lv = pos[length] if isinstance(length, str) else length
            ph = pos[ang] if isinstance(ang, str) else np.full(shape, ang)
            if rates:
                dl = vel[length] if isinstance(length, str) else zero
                ddl = acc[length] if isinstance(length, str) else zero
                w = vel[ang] if isinstance(ang, str) else zero
                a = acc[ang] if isinstance(ang, str) else zero
            else:
                dl = ddl = w = a = None
            part = _vector_motion(lv, dl, ddl, ph, w, a)
            total = [t if p is None else t + sign * p for t, p in zip(total, part, strict=True)]
        cross[e_name] = tuple(total)
    for child, e, child_is_b in c.tree:
        par = e.a if child_is_b else e.b
        p_key, c_key = (e.pa, e.pb) if child_is_b else (e.pb, e.pa)
        pp, pv, pa = rigid(par, lk._xy(p_key))
        if e.kind != "R":
            s = 1.0 if child_is_b else -1.0
            xp, xv, xa = cross[e.name]
            pp = pp + s * xp
            if rates:
                pv, pa = pv + s * xv, pa + s * xa
        anchor[child] = (lk._xy(c_key), pp, pv, pa)

    points, pvel, pacc = {}, {}, {}
    owners = [(GROUND, lk._ground)] + [(n, ln.points) for n, ln in lk._links.items()]
    for n, pts in owners:
        for p in pts:
            if p not in points:
                points[p], pvel[p], pacc[p] = rigid(n, lk._points[p])
    cg, cgv, cga = {}, {}, {}
    for n, ln in lk._links.items():
        cg[n], cgv[n], cga[n] = rigid(n, _cg_drawn(lk, ln))
    lengths, lrate, lacc = {}, {}, {}
    for e_name, (lv, _, _) in c.cross_vars.items():
        lengths[e_name] = pos[lv]
        if rates:
            lrate[e_name], lacc[e_name] = vel[lv], acc[lv]

    def fr(d, keep=lambda k: True):
        return _frozen({k: np.array(v, copy=True) for k, v in d.items() if keep(k)})

    moving = lambda k: k != GROUND  # noqa: E731
    return LinkageMotion(
        inputs=fr({k: np.broadcast_to(v, shape) for k, v in vals.items()}),
        theta=fr(theta, moving),
        omega=fr(omega, moving) if rates else None,
        alpha=fr(alpha, moving) if rates else None,
        points=fr(points),
        point_velocity=fr(pvel) if rates else None,
        point_acceleration=fr(pacc) if rates else None,
        cg=fr(cg),
        cg_velocity=fr(cgv) if rates else None,
        cg_acceleration=fr(cga) if rates else None,
        lengths=fr(lengths),
        length_rate=fr(lrate) if rates else None,
        length_acceleration=fr(lacc) if rates else None,
        ok=lm.ok,
        reason=lm.reason,
        loop_motion=lm,
        angle_drivers=frozenset(d for d in vals if d in lk._links or d in lk._motors),
    )


def _cg_drawn(lk: Linkage, ln: _Link) -> complex:
    p0 = lk._points[ln.points[0]]
    if ln.cg is None:
        return p0
    if isinstance(ln.cg, str):
        return lk._points[ln.cg]
    return p0 + ln.cg * np.exp(1j * _ref_angle(lk, ln.name))


# ---------------------------------------------------------------------- Newton–Euler
#: Samples are assembled and solved in blocks of this size (bounded memory).
_CHUNK = 1 << 15
#: A force block whose pivot ratio (after equilibration) is below this is singular.
_SINGULAR_RCOND = 1e-12

FORCE_REASONS = {
    "singular": "singular force system (toggle or dead point): the joint forces are not "
    "determined by Newton–Euler",
    "coulomb": "Coulomb friction: no consistent sign of the normal force (self-locking)",
    "spring": "a spring's two ends meet (zero length): the direction of its force is undefined",
}


@dataclass(frozen=True)
class LinkageForces:
    """Newton–Euler forces of a :class:`Linkage` for every sample of a motion.

    Forces are complex ``Fx + j Fy``, torques CCW positive; ``F_ap`` is the force
    on link *p* from link *a* (``F_pa = −F_ap``).

    Attributes
    ----------
    pins : mapping of (a, p) to complex ndarray
        Every pin force ``F_ap`` (one entry per pair of links joined by a pin);
        use :meth:`F` for either direction.
    sliders : mapping of joint name to complex ndarray
        Total force on the block (or pin, for a slot) from the guide: normal
        force, driving force and friction.
    normal : mapping of joint name to ndarray
        Normal force of sliders and slots along ``j·û`` (û the slide direction).
    couple : mapping of joint name to ndarray
        The couple a prismatic joint transmits to the block.
    driver : mapping of driver name to ndarray
        Driving torque (of the ground on the driven link, like ``T12``; of a
        motor's link *a* on its link *b*, ``−T`` on *a*) or force (along the
        slide; an actuator's push).
    rolling : mapping of rolling-joint name to complex ndarray
        Contact force on ``link_b`` from ``link_a`` at the contact point (on
        ``link_a`` it is the opposite); for a contact whose centres share a
        carrier only its tangential part (the preload is taken as 0).
    contact : mapping of rolling-joint name to complex ndarray
        Position of each rolling contact point.
    elements : mapping of spring name to ndarray
        The effort of every :meth:`Linkage.spring` — its tension ``T``
        (positive pulling the ends together, a force) — and of every
        :meth:`Linkage.torsion_spring` — its torque ``tau`` (positive winding
        ``phi`` back, ``−tau`` on link *b*).
    element_length, element_rate : mapping of spring name to ndarray
        A spring's length ``L`` and ``dL/dt``; a torsion spring's relative
        angle ``phi = theta_b − theta_a`` (radians, not wrapped) and ``dphi/dt``.
        The element's power on the mechanism is ``−effort × rate``.
    shaking_force : complex ndarray
        Sum of the forces the moving links exert on the ground.
    shaking_moment : ndarray
        Their moment about the drawing's origin, with the reaction torques.
    ok, reason : ndarray
        Per-sample flags (kinematic failures and singular force systems).
    motion : LinkageMotion

    Examples
    --------
    >>> import numpy as np
    >>> lk = (Linkage({"O2": (0, 0), "O4": (8, 0), "A": (4, 0), "B": (7.625, 35.859375**0.5)})
    ...       .ground("O2", "O4").link("crank", "O2", "A", mass=1.0, inertia=0.1, cg=2.0)
    ...       .link("coupler", "A", "B").link("rocker", "O4", "B").drive("crank"))
    >>> f = lk.forces(lk.solve([0.0, 0.1], velocity=10.0))
    >>> sorted(f.pins)  # doctest: +NORMALIZE_WHITESPACE
    [('coupler', 'rocker'), ('crank', 'coupler'), ('ground', 'crank'), ('ground', 'rocker')]
    >>> bool(np.allclose(f.F("rocker", "coupler"), -f.F("coupler", "rocker")))
    True
    """

    pins: Mapping[tuple[str, str], np.ndarray]
    sliders: Mapping[str, np.ndarray]
    normal: Mapping[str, np.ndarray]
    couple: Mapping[str, np.ndarray]
    driver: Mapping[str, np.ndarray]
    shaking_force: np.ndarray
    shaking_moment: np.ndarray
    ok: np.ndarray
    reason: np.ndarray
    motion: LinkageMotion = field(repr=False)
    rolling: Mapping[str, np.ndarray] = field(default_factory=dict)
    contact: Mapping[str, np.ndarray] = field(default_factory=dict)
    elements: Mapping[str, np.ndarray] = field(default_factory=dict)
    element_length: Mapping[str, np.ndarray] = field(default_factory=dict)
    element_rate: Mapping[str, np.ndarray] = field(default_factory=dict)

    def F(self, a: str, p: str) -> np.ndarray:
        """The pin force on link ``p`` from link ``a`` (``F_ap``)."""
        if (a, p) in self.pins:
            return self.pins[(a, p)]
        if (p, a) in self.pins:
            return -self.pins[(p, a)]
        raise KeyError(f"no pin joins {a!r} and {p!r}; pins: {', '.join(map(str, self.pins))}")

    def __len__(self) -> int:
        return int(self.ok.size)

    def plot(self, ax: Any = None) -> Any:
        """Plot the driver efforts against the first driver (degrees if an angle).

        Returns
        -------
        matplotlib Axes
        """
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots()
        driver, x = next(iter(self.motion.inputs.items()))
        is_angle = driver in self.motion.angle_drivers
        xs = np.degrees(np.ravel(x)) if is_angle else np.ravel(x)
        for name, effort in self.driver.items():
            kind = "torque" if name in self.motion.angle_drivers else "force"
            ax.plot(xs, np.ravel(effort), label=f"driver {name} ({kind})")
        ax.set_xlabel(f"{driver} [deg]" if is_angle else driver)
        ax.legend()
        return ax

    def to_pandas(self) -> Any:
        """One row per sample: pin, slider and contact forces, drivers, springs, shaking, flags.

        A spring or torsion spring ``k`` gives columns ``T_k`` (tension or torque),
        ``L_k`` (length or relative angle) and ``Ldot_k`` (its rate).
        """
        import pandas as pd

        cols: dict[str, np.ndarray] = {}
        for (a, p), v in self.pins.items():
            cols[f"F_{a}_{p}_x"], cols[f"F_{a}_{p}_y"] = np.ravel(v).real, np.ravel(v).imag
        for k, v in self.sliders.items():
            cols[f"F_{k}_x"], cols[f"F_{k}_y"] = np.ravel(v).real, np.ravel(v).imag
        for k, v in self.normal.items():
            cols[f"N_{k}"] = np.ravel(v)
        for k, v in self.couple.items():
            cols[f"M_{k}"] = np.ravel(v)
        for k, v in self.rolling.items():
            cols[f"F_{k}_x"], cols[f"F_{k}_y"] = np.ravel(v).real, np.ravel(v).imag
        for k, v in self.driver.items():
            cols[f"driver_{k}"] = np.ravel(v)
        for k, v in self.elements.items():
            cols[f"T_{k}"] = np.ravel(v)
            cols[f"L_{k}"] = np.ravel(self.element_length[k])
            cols[f"Ldot_{k}"] = np.ravel(self.element_rate[k])
        cols["shaking_force_x"] = np.ravel(self.shaking_force).real
        cols["shaking_force_y"] = np.ravel(self.shaking_force).imag
        cols["shaking_moment"] = np.ravel(self.shaking_moment)
        cols["ok"], cols["reason"] = np.ravel(self.ok), np.ravel(self.reason)
        return pd.DataFrame(cols)


def _cross(u, v):
    return u.real * v.imag - u.imag * v.real


def _block_triangular(pattern: np.ndarray, labels: list, moving: list[str]) -> list:
    """Split the force system into blocks solved one after another (Assur groups).

    A perfect matching of equations to unknowns puts a structural non-zero on
    the diagonal; the strongly connected components of the matched graph are the
    irreducible diagonal blocks, ordered so that every block uses only unknowns
    of blocks solved before it (block lower-triangular form). For a Watt
    six-bar this gives the outer dyad (6 × 6), the inner dyad (6 × 6) and the
    crank (3 × 3) instead of one 15 × 15 system.

    Returns a list of ``(rows, cols)``: each block's equations and unknowns.
    """
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import connected_components, maximum_bipartite_matching

    n = pattern.shape[0]
    match = maximum_bipartite_matching(csr_matrix(pattern.astype(np.int8)), perm_type="column")
    if (match < 0).any():
        lost = [moving[r // 3] for r in np.flatnonzero(match < 0)]
        raise ModelError(
            "the force system is structurally singular: the equations of link(s) "
            f"{', '.join(dict.fromkeys(lost))} cannot be satisfied by the joint forces"
        )
    uses = pattern[:, match]  # row i uses the unknown matched to row r
    n_comp, comp = connected_components(csr_matrix(uses), directed=True, connection="strong")
    dep = np.zeros((n_comp, n_comp), bool)
    ri, rr = np.nonzero(uses)
    dep[comp[ri], comp[rr]] = True
    np.fill_diagonal(dep, False)
    order: list[int] = []
    done = np.zeros(n_comp, bool)
    while len(order) < n_comp:
        ready = [c for c in range(n_comp) if not done[c] and not (dep[c] & ~done).any()]
        for c in ready:
            done[c] = True
            order.append(c)
    del labels, n
    return [(np.flatnonzero(comp == c), match[comp == c]) for c in order]


def _forces(
    lk, motion, gravity, external_forces, external_torques, viscous, coulomb
) -> LinkageForces:
    if not isinstance(motion, LinkageMotion):
        raise InputError("motion", f"must be a LinkageMotion from Linkage.solve, got {motion!r}")
    if motion.omega is None:
        raise ModelError("forces need accelerations: solve with velocity=... first")
    lk._compile()
    g = nonnegative("gravity", gravity)
    shape = motion.ok.shape
    n_s = int(np.prod(shape))
    moving = list(lk._links)
    row = {n: 3 * i for i, n in enumerate(moving)}
    n_eq = 3 * len(moving)

    def flat(x) -> np.ndarray:
        return np.broadcast_to(np.asarray(x), shape).reshape(n_s)

    G = {n: flat(np.nan_to_num(motion.cg[n])) for n in moving}
    P = {k: flat(np.nan_to_num(v)) for k, v in motion.points.items()}
    delta = {n: flat(np.nan_to_num(motion.theta[n])) - _ref_angle(lk, n) for n in moving}
    delta[GROUND] = np.zeros(n_s)

    drivers = set(lk._drivers)
    one = np.ones(n_s)
    edges = lk._edges()
    slide_u = {
        e.name: e.direction * np.exp(1j * delta[e.a]) for e in edges if e.kind in ("P", "slot")
    }
    contact: dict[str, tuple[np.ndarray, np.ndarray]] = {}  # roll -> (point, tangent)
    for e in edges:
        if e.kind != "roll":
            continue
        rho_a, rho_b = e.radii
        if np.isinf(rho_b):  # the normal of b's straight profile, toward centre_a
            n = e.direction * np.exp(1j * delta[e.b])
            C = P[e.pa] - rho_a * n
        else:
            z = P[e.pb] - P[e.pa]
            n = z / np.where(np.abs(z) > 0, np.abs(z), 1.0)
            C = P[e.pa] + rho_a * n
        contact[e.name] = (C, 1j * n)
    columns: list[list[tuple[int, Any]]] = []
    ground_parts: list[tuple[int, Any, Any]] = []  # (col, force unit (complex), moment coef)
    labels: list[tuple[str, str]] = []

    def force_col(entries: list[tuple[str, Any, Any, float]], label: tuple[str, str]) -> None:
        """A unit force ``u`` at ``X`` on each listed link with a sign (+ on the first)."""
        col: list[tuple[int, Any]] = []
        k = len(columns)
        for link, X, u, sgn in entries:
            if link == GROUND:
                ground_parts.append((k, sgn * u, sgn * _cross(X, u)))
                continue
            r = row[link]
            col += [(r, sgn * u.real), (r + 1, sgn * u.imag), (r + 2, sgn * _cross(X - G[link], u))]
        columns.append(col)
        labels.append(label)

    def couple_col(entries: list[tuple[str, float]], label: tuple[str, str]) -> None:
        k = len(columns)
        col = []
        for link, sgn in entries:
            if link == GROUND:
                ground_parts.append((k, 0j, sgn))
            else:
                col.append((row[link] + 2, sgn))
        columns.append(col)
        labels.append(label)

    def build(kappa: Mapping[str, Any]) -> None:
        """Columns of the unknowns; ``kappa[slider]`` adds Coulomb friction κ·N·û."""
        columns.clear()
        ground_parts.clear()
        labels.clear()
        for e in edges:
            build_edge(e, kappa)
        for d in lk._drivers:
            if d in lk._links:
                couple_col([(d, 1.0), (GROUND, -1.0)], ("driver", d))
            elif d in lk._motors:  # torque T on link b, its reaction -T on link a
                a, b_ = lk._motor_links(d)
                couple_col([(b_, 1.0), (a, -1.0)], ("driver", d))

    def build_edge(e: _Edge, kappa: Mapping[str, Any]) -> None:
        if e.kind == "R":
            X = P[e.pa]
            for comp, u in (("x", one + 0j), ("y", 1j * one)):
                force_col([(e.b, X, u, 1.0), (e.a, X, u, -1.0)], ("pin", f"{e.a}|{e.b}|{comp}"))
        elif e.kind in ("P", "slot"):
            X = P[e.pb]
            uhat = slide_u[e.name]
            un = 1j * uhat + kappa.get(e.name, 0.0) * uhat
            force_col([(e.b, X, un, 1.0), (e.a, X, un, -1.0)], ("normal", e.name))
            if e.kind == "P":
                couple_col([(e.b, 1.0), (e.a, -1.0)], ("couple", e.name))
            if e.name in drivers:
                force_col([(e.b, X, uhat, 1.0), (e.a, X, uhat, -1.0)], ("driver", e.name))
        elif e.kind == "roll":  # a force at the contact point, like a pin there
            C, t = contact[e.name]
            if e.carried:  # only the tangential force (the preload is indeterminate)
                force_col([(e.b, C, t, 1.0), (e.a, C, t, -1.0)], ("roll", f"{e.name}|t"))
            else:
                for comp, u in (("x", one + 0j), ("y", 1j * one)):
                    force_col([(e.b, C, u, 1.0), (e.a, C, u, -1.0)], ("roll", f"{e.name}|{comp}"))
        elif e.name in drivers:  # actuator
            Xa, Xb = P[e.pa], P[e.pb]
            d = Xb - Xa
            uhat = d / np.where(np.abs(d) > 0, np.abs(d), 1.0)
            force_col([(e.b, Xb, uhat, 1.0), (e.a, Xa, uhat, -1.0)], ("driver", e.name))

    build({})
    if len(columns) != n_eq:
        raise ModelError(
            f"{len(columns)} force unknowns for {n_eq} equations of {len(moving)} moving links; "
            "the force system is not square (check the drivers)"
        )

    # right-hand side: m aG + m g j − external forces; I α − external moments about G
    b = np.zeros((n_s, n_eq))
    aG = {n: flat(np.nan_to_num(motion.cg_acceleration[n])) for n in moving}
    alpha = {n: flat(np.nan_to_num(motion.alpha[n])) for n in moving}
    for n in moving:
        ln, r = lk._links[n], row[n]
        b[:, r] = ln.mass * aG[n].real
        b[:, r + 1] = ln.mass * (aG[n].imag + g)
        b[:, r + 2] = ln.inertia * alpha[n]
    ext_force_ground = np.zeros(n_s, complex)
    ext_moment_ground = np.zeros(n_s)

    def apply(link: str, X, F) -> None:
        nonlocal ext_force_ground, ext_moment_ground
        if link == GROUND:
            ext_force_ground = ext_force_ground + F
            ext_moment_ground = ext_moment_ground + _cross(X, F)
            return
        r = row[link]
        b[:, r] -= F.real
        b[:, r + 1] -= F.imag
        b[:, r + 2] -= _cross(X - G[link], F)

    for item in external_forces:
        try:
            link, point, force = item
        except (TypeError, ValueError):
            raise InputError(
                "external_forces", f"each is (link, point, force), got {item!r}"
            ) from None
        if link not in lk._links:
            raise ModelError(f"external force on unknown link {link!r}; links: {lk._names()}")
        if isinstance(point, str):
            if point not in lk._links[link].points:
                raise ModelError(f"external force: point {point!r} is not on link {link!r}")
            X = P[point]
        else:
            ln = lk._links[link]
            z = lk._points[ln.points[0]] + _complex_point("external force point", point) * np.exp(
                1j * _ref_angle(lk, link)
            )
            p0 = P[ln.points[0]]
            X = p0 + (z - lk._points[ln.points[0]]) * np.exp(1j * delta[link])
        F = np.asarray(force, dtype=complex)
        if not np.all(np.isfinite(F)):
            raise InputError(f"external force on {link}", "must be finite (Fx + j Fy)")
        try:
            F = flat(F)
        except ValueError:
            raise InputError(
                f"external force on {link}", f"shape {F.shape} does not match the motion {shape}"
            ) from None
        apply(link, X, F)
    torques = (
        external_torques.items() if isinstance(external_torques, Mapping) else external_torques
    )
    for link, T in torques:
        if link not in lk._links:
            raise ModelError(f"external torque on unknown link {link!r}; links: {lk._names()}")
        b[:, row[link] + 2] -= flat(finite_array(f"external torque on {link}", T))
    friction: dict[str, np.ndarray] = {}
    for name, beta in viscous.items():
        edge = next((e for e in lk._edges() if e.name == name and e.kind == "P"), None)
        if edge is None:
            raise ModelError(
                f"viscous friction at {name!r}: no such slider; sliders: "
                f"{', '.join(lk._sliders) or '(none)'}"
            )
        beta = nonnegative(f"viscous[{name}]", beta)
        v_slip = flat(np.nan_to_num(motion.length_rate[name]))
        f = -beta * v_slip * slide_u[name]
        friction[name] = f
        X = P[edge.pb]
        apply(edge.b, X, f)
        apply(edge.a, X, -f)

    # springs and dampers: known loads on the links they join (no unknowns)
    effort, extent, rate = {}, {}, {}
    V = {k: flat(np.nan_to_num(v)) for k, v in motion.point_velocity.items()}
    zero_length = np.zeros(n_s, bool)
    for name, s in lk._springs.items():
        a, b_ = lk._element_links(name)
        d = P[s.end] - P[s.start]
        ell = np.abs(d)  # the spring's length L
        short = ell <= 1e-12 * max(s.free_length, 1.0)
        zero_length |= short
        u = d / np.where(short, 1.0, ell)
        ell_dot = ((V[s.end] - V[s.start]) * u.conjugate()).real
        T = s.stiffness * (ell - s.free_length) + s.damping * ell_dot + s.preload
        apply(a, P[s.start], T * u)  # the tension pulls start toward end ...
        apply(b_, P[s.end], -T * u)  # ... and end toward start
        effort[name], extent[name], rate[name] = T, ell, ell_dot

    def angle_of(link: str) -> tuple[np.ndarray, np.ndarray]:
        if link == GROUND:
            return np.zeros(n_s), np.zeros(n_s)
        return flat(np.nan_to_num(motion.theta[link])), flat(np.nan_to_num(motion.omega[link]))

    for name, t in lk._torsions.items():
        a, b_ = lk._element_links(name)
        (th_a, w_a), (th_b, w_b) = angle_of(a), angle_of(b_)
        phi, phi_dot = th_b - th_a, w_b - w_a
        tau = t.stiffness * (phi - t.free_angle) + t.damping * phi_dot + t.preload
        for link, sgn in ((a, 1.0), (b_, -1.0)):
            if link == GROUND:
                ext_moment_ground = ext_moment_ground + sgn * tau
            else:
                b[:, row[link] + 2] -= sgn * tau
        effort[name], extent[name], rate[name] = tau, phi, phi_dot

    # assemble and solve in chunks, block by block (Assur groups, found from the pattern)
    bad = ~np.ravel(motion.ok) | zero_length

    # static scaling (moment rows by 1/L, couple columns by L, L a typical link
    # size) makes every block O(1) for the LU and its singularity test
    length = _typical_length(lk)

    def solve_system() -> tuple[np.ndarray, np.ndarray]:
        x = np.full((n_s, n_eq), np.nan)
        singular = np.zeros(n_s, bool)
        entries = [(r, k, coef) for k, col in enumerate(columns) for r, coef in col]
        pattern = np.zeros((n_eq, n_eq), bool)
        for r, k, _ in entries:
            pattern[r, k] = True
        row_scale = np.tile([1.0, 1.0, 1.0 / length], len(moving))
        col_scale = np.array(
            [
                length if kind == "couple" or name in lk._links or name in lk._motors else 1.0
                for kind, name in labels
            ]
        )
        blocks = []
        for rows, cols in _block_triangular(pattern, labels, moving):
            ri = {r: i for i, r in enumerate(rows)}
            cj = {k: j for j, k in enumerate(cols)}
            inner = [(ri[r], cj[k], c) for r, k, c in entries if r in ri and k in cj]
            coupling = [(ri[r], k, c) for r, k, c in entries if r in ri and k not in cj]
            blocks.append((rows, cols, inner, coupling))
        for lo in range(0, n_s, _CHUNK):
            sl = slice(lo, min(lo + _CHUNK, n_s))
            size = sl.stop - sl.start
            skip = bad[sl]
            for rows, cols, inner, coupling in blocks:
                nb = len(rows)
                A = np.zeros((nb, nb, size))  # layout of machdyn.loops.lu_factor
                for i, j, coef in inner:
                    A[i, j] += coef[sl] if np.ndim(coef) else coef
                rhs = b[sl, rows].T
                for i, k, coef in coupling:
                    rhs[i] -= (coef[sl] if np.ndim(coef) else coef) * x[sl, k]
                if skip.any():
                    A[:, :, skip] = np.eye(nb)[:, :, None]
                    rhs[:, skip] = 0.0
                fac = lu_factor(A, row_scale[rows], col_scale[cols])
                singular[sl] |= ~(fac.rcond > _SINGULAR_RCOND)
                x[sl, cols] = lu_solve(fac, rhs).T
        x[bad | singular] = np.nan
        return x, singular

    x, singular = solve_system()
    kappa: dict[str, Any] = {}
    slipping = {}
    for name, mu in coulomb.items():
        edge = next((e for e in edges if e.name == name and e.kind in ("P", "slot")), None)
        if edge is None:
            raise ModelError(
                f"Coulomb friction at {name!r}: no such slider or slot; joints: "
                f"{', '.join([*lk._sliders, *lk._slots]) or '(none)'}"
            )
        mu = nonnegative(f"coulomb[{name}]", mu)
        v = flat(np.nan_to_num(motion.length_rate[name]))
        a = flat(np.nan_to_num(motion.length_acceleration[name]))
        slipping[name] = (mu, np.where(v != 0, np.sign(v), np.sign(a)))  # at rest: impending
    friction_bad = np.zeros(n_s, bool)
    if slipping:
        # the sign of N is unknown beforehand: start from the smooth solution and
        # re-solve with the signs found until they agree (the notes' ±μN)
        sign_n = {n: np.where(x[:, labels.index(("normal", n))] < 0, -1.0, 1.0) for n in slipping}
        for _ in range(8):
            kappa = {n: -mu * sign_n[n] * sv for n, (mu, sv) in slipping.items()}
            build(kappa)
            x, singular = solve_system()
            friction_bad[:] = False
            for n in slipping:
                N = x[:, labels.index(("normal", n))]
                new = np.where(N < 0, -1.0, 1.0)
                wrong = (new != sign_n[n]) & np.isfinite(N) & (np.abs(N) > 0)
                friction_bad |= wrong
                sign_n[n] = new
            if not friction_bad.any():
                break
        x[friction_bad] = np.nan
    bad_all = bad | singular | friction_bad

    def col_of(kind: str, name: str) -> np.ndarray:
        return x[:, labels.index((kind, name))]

    pins = {}
    for e in lk._edges():
        if e.kind == "R":
            pins[(e.a, e.b)] = (
                col_of("pin", f"{e.a}|{e.b}|x") + 1j * col_of("pin", f"{e.a}|{e.b}|y")
            ).reshape(shape)
    normal, couple, sliders, driver = {}, {}, {}, {}
    for e in lk._edges():
        if e.kind in ("P", "slot"):
            N = col_of("normal", e.name)
            F = N * (1j + kappa.get(e.name, 0.0)) * slide_u[e.name]
            normal[e.name] = N.reshape(shape)
            if e.kind == "P":
                couple[e.name] = col_of("couple", e.name).reshape(shape)
            if e.name in drivers:
                F = F + col_of("driver", e.name) * slide_u[e.name]
            if e.name in friction:
                F = F + np.where(bad_all, np.nan, friction[e.name])
            sliders[e.name] = F.reshape(shape)
    for d in lk._drivers:
        driver[d] = col_of("driver", d).reshape(shape)
    rolling = {}
    for e in edges:
        if e.kind == "roll":
            if e.carried:
                F = col_of("roll", f"{e.name}|t") * contact[e.name][1]
            else:
                F = col_of("roll", f"{e.name}|x") + 1j * col_of("roll", f"{e.name}|y")
            rolling[e.name] = F.reshape(shape)
    # shaking: forces and moments the moving links exert on the ground (reactions)
    Fs = np.zeros(n_s, complex)
    Ms = np.zeros(n_s)
    for k, u, mom in ground_parts:
        Fs += x[:, k] * u
        Ms += x[:, k] * mom
    # ... and the known loads on the ground: friction of a ground guide, springs
    Fs += ext_force_ground
    Ms += ext_moment_ground
    reasons = np.array(motion.reason, dtype=object).reshape(n_s).copy()

    def per_sample(table: dict[str, np.ndarray]) -> Mapping[str, np.ndarray]:
        return _frozen({k: np.where(bad_all, np.nan, v).reshape(shape) for k, v in table.items()})

    reasons[zero_length & np.ravel(motion.ok)] = FORCE_REASONS["spring"]
    reasons[singular & ~bad] = FORCE_REASONS["singular"]
    reasons[friction_bad & ~bad & ~singular] = FORCE_REASONS["coulomb"]
    return LinkageForces(
        pins=_frozen(pins),
        sliders=_frozen(sliders),
        normal=_frozen(normal),
        couple=_frozen(couple),
        driver=_frozen(driver),
        shaking_force=np.where(bad_all, np.nan, Fs).reshape(shape),
        shaking_moment=np.where(bad_all, np.nan, Ms).reshape(shape),
        ok=(~bad_all).reshape(shape),
        reason=reasons.reshape(shape),
        motion=motion,
        rolling=_frozen(rolling),
        contact=_frozen(
            {k: np.where(bad_all, np.nan, v[0]).reshape(shape) for k, v in contact.items()}
        ),
        elements=per_sample(effort),
        element_length=per_sample(extent),
        element_rate=per_sample(rate),
    )
