"""The :class:`Linkage` builder: points, links, ground, drivers, and their validation."""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable, Mapping, Sequence
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

import numpy as np

from .._validate import TINY, finite_scalar
from ..errors import InputError, ModelError
from ..loops import LoopSystem
from ..massprops import MassProperties
from ..mobility import mobility_of
from . import kinematics as _kinematics
from ._common import GROUND, _complex_point, _name, _ref_angle
from .elements import _ElementMethods, _Spring, _Torsion
from .forces import LinkageForces, _forces
from .groups import Group, decompose
from .joints import _JointMethods
from .kinematics import LinkageMotion
from .topology import _Edge, _Model, edges_of
from .view import Joint, Link, Spring, TorsionSpring, elements_of, joints_of

if TYPE_CHECKING:
    from ..centres import InstantCentres


class Linkage(_JointMethods, _ElementMethods):
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

    #: The units the linkage computes in and labels its results with (a
    #: :class:`machdyn.units.UnitSystem`, set by :func:`machdyn.load`); None: unit-free.
    units: Any = None

    def __init__(self, points: Mapping[str, Any] | None = None) -> None:
        self._points: dict[str, complex] = {}
        self._links: dict[str, Link] = {}
        self._ground: tuple[str, ...] = ()
        self._sliders: dict[str, tuple[str, str, str, complex, str | None]] = {}
        self._slots: dict[str, tuple[str, str, str, complex, str | None]] = {}
        # curved slots and sliders: name -> (kind "slot"/"slider", moving, on, at, centre, R)
        self._curved: dict[str, tuple[str, str, str, str, str, float]] = {}
        self._actuators: dict[str, tuple[str, str, str, str]] = {}
        self._rolls: dict[str, tuple[str, str, float, str, str, float, bool]] = {}
        self._motors: dict[str, tuple[str, tuple[str, str] | None]] = {}  # name -> (pin, links)
        self._springs: dict[str, _Spring] = {}
        self._torsions: dict[str, _Torsion] = {}
        self._drivers: list[str] = []
        self._compiled: _Model | None = None
        self._points_extra: dict[str, complex] = {}
        if points is not None and not isinstance(points, Mapping):
            raise InputError("points", f"must map point names to (x, y), got {points!r}")
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
        if _name("name", name) not in self._points:
            raise ModelError(f"unknown point {name!r}; known points: {', '.join(self._points)}")
        return self._points[name]

    def _need_points(self, owner: str, names: Iterable[str]) -> None:
        missing = [p for p in names if _name(owner, p) not in self._points]
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
        points = tuple(dict.fromkeys(_name(f"link {name!r}", p) for p in points))
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
        self._links[name] = Link(name, points, m, i_g, c)
        return self._changed()

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
            if n in self._curved:
                raise ModelError(
                    f"driver {n!r}: a curved slider or slot cannot be driven yet (its arc length "
                    "is not a joint variable); drive a link, a straight slider or a motor"
                )
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
            self._curved,
            self._actuators,
            self._rolls,
            self._motors,
            self._springs,
            self._torsions,
        )
        return any(name in t for t in tables)

    def _names(self) -> str:
        return ", ".join(self._links) or "(none)"

    # ------------------------------------------------------------------ read-only view
    @property
    def points(self) -> Mapping[str, complex]:
        """Drawn coordinates of every named point, ``x + yj`` (read-only).

        Examples
        --------
        >>> Linkage({"O2": (0, 0), "A": (2, 1)}).points["A"]
        (2+1j)
        """
        return MappingProxyType(dict(self._points))

    @property
    def ground_points(self) -> tuple[str, ...]:
        """The points fixed to the ground, in the order :meth:`ground` was given them."""
        return self._ground

    @property
    def links(self) -> Mapping[str, Link]:
        """The moving links (:class:`~machdyn.linkage.view.Link`) by name, in definition order."""
        return MappingProxyType(dict(self._links))

    @property
    def joints(self) -> tuple[Joint, ...]:
        """Every joint (:class:`~machdyn.linkage.view.Joint`): pins, sliders, slots, ...

        Pins come first, one per point shared by links (in point order), then
        sliders, slots, actuators, rolling contacts and motors, each in the
        order they were added.
        """
        return joints_of(self)

    def __repr__(self) -> str:
        from .._summary import linkage_repr

        return linkage_repr(self)

    def _repr_html_(self) -> str:
        from .._summary import linkage_html

        return linkage_html(self)

    def to_spec(self, name: str = "linkage") -> dict[str, Any]:
        """The linkage as a machine-file dict (``docs/spec.md``; :func:`machdyn.from_spec`)."""
        from ..spec import model_spec

        return model_spec(self, "linkage", name)

    @property
    def drivers(self) -> tuple[str, ...]:
        """The driver names given to :meth:`drive`, in order."""
        return tuple(self._drivers)

    @property
    def elements(self) -> tuple[Spring | TorsionSpring, ...]:
        """The springs and torsion springs (known loads), in the order they were added."""
        return elements_of(self)

    @property
    def drawn_inputs(self) -> Mapping[str, float]:
        """Every driver's value in the drawn pose (radians for angles, lengths otherwise).

        A link's angle ``theta`` (its first → second point), a motor's
        ``theta_b − theta_a``, a slider's or slot's displacement along its line
        from the foot of the guide's first point (or of ``through``), an
        actuator's length: the values :meth:`solve` reproduces the drawing at.

        Examples
        --------
        >>> lk = (Linkage({"O2": (0, 0), "A": (0, 2), "B": (6, 0)}).ground("O2")
        ...       .link("crank", "O2", "A").link("rod", "A", "B").link("block", "B")
        ...       .slider("block", "ground", "B", 0.0, name="guide").drive("crank", "guide"))
        >>> {k: round(v, 6) for k, v in lk.drawn_inputs.items()}
        {'crank': 1.570796, 'guide': 6.0}
        """
        out = {}
        for d in self._drivers:
            if d in self._links:
                out[d] = _ref_angle(self, d)
            elif d in self._motors:
                a, b = self._motor_links(d)
                out[d] = _ref_angle(self, b) - _ref_angle(self, a)
            elif d in self._actuators:
                start, end = self._actuators[d][:2]
                out[d] = float(abs(self._points[end] - self._points[start]))
            else:
                _, on, at, u, through = {**self._sliders, **self._slots}[d]
                ref = self._points[through] if through else self._first_point(on)
                out[d] = float(((self._points[at] - ref) * u.conjugate()).real)
        return MappingProxyType(out)

    # ------------------------------------------------------------------ pictures
    def draw(self, frame: int | None = None, ax: Any = None, **options: Any) -> Any:
        """Draw the linkage in one pose (:func:`machdyn.draw.draw`)."""
        from ..draw import draw

        return draw(self, frame, ax, **options)

    def animate(self, path: Any = None, **options: Any) -> Any:
        """Animate the linkage (:func:`machdyn.draw.animate`)."""
        from ..draw import animate

        return animate(self, path, **options)

    def to_html(self, path: Any = None, **options: Any) -> str:
        """A self-contained HTML page of the motion (:func:`machdyn.draw.to_html`)."""
        from ..draw import to_html

        return to_html(self, path, **options)

    def instant_centres(self, values: Any, velocity: Any = None) -> InstantCentres:
        """All instant centres at driver ``values``: :func:`machdyn.centres.instant_centres_of`.

        Examples
        --------
        >>> lk = (Linkage({"O2": (0, 0), "O4": (8, 0), "A": (0, 2), "B": (5.0, 5.0)})
        ...       .ground("O2", "O4").link("crank", "O2", "A").link("coupler", "A", "B")
        ...       .link("rocker", "O4", "B").drive("crank"))
        >>> lk.instant_centres(1.0).method("ground", "coupler")
        'kennedy'
        """
        from ..centres import instant_centres_of

        return instant_centres_of(self, values, velocity)

    def report(self, path: Any = None, **options: Any) -> Any:
        """A design report of the linkage (:func:`machdyn.report.report`)."""
        from ..report import report

        return report(self, path, **options)

    def transmission_angles(self, motion: LinkageMotion) -> Mapping[str, np.ndarray]:
        """Transmission angle μ (radians) of every dyad with two assemblies, per sample.

        RRR: the acute angle between its two links at the middle pin (as
        ``FourBar.mu``: 90° best, 0 at a toggle); RRP/PRR: the acute angle
        between the rod and the normal to the slide. Keyed by group name; NaN
        where ``motion`` is not ok.

        Examples
        --------
        >>> import numpy as np
        >>> lk = (Linkage({"O2": (0, 0), "O4": (8, 0), "A": (4, 0),
        ...                "B": (7.625, np.sqrt(49 - 3.625**2))})
        ...       .ground("O2", "O4").link("crank", "O2", "A").link("coupler", "A", "B")
        ...       .link("rocker", "O4", "B").drive("crank"))
        >>> mu = lk.transmission_angles(lk.solve([0.0, 1.0]))["RRR dyad (coupler, rocker)"]
        >>> from machdyn.fourbar import FourBar  # the closed form's μ, the same linkage
        >>> bool(np.allclose(mu, FourBar(8, 4, 7, 6).solve([0.0, 1.0]).mu))
        True
        """
        from .groups import transmission_angles

        return MappingProxyType(transmission_angles(self, motion))

    def flipped(self, group: str) -> Linkage:
        """The linkage drawn on the other assembly of dyad ``group`` (a group's name).

        The group's links, and those of every group depending on it, are
        re-placed at the drawn driver values; the drawing is the new linkage's.

        Examples
        --------
        >>> import numpy as np
        >>> lk = (Linkage({"O2": (0, 0), "O4": (8, 0), "A": (4, 0),
        ...                "B": (7.625, np.sqrt(49 - 3.625**2))})
        ...       .ground("O2", "O4").link("crank", "O2", "A").link("coupler", "A", "B")
        ...       .link("rocker", "O4", "B").drive("crank"))
        >>> other = lk.flipped("RRR dyad (coupler, rocker)")
        >>> complex(other.points["B"]).conjugate() == complex(lk.points["B"])  # mirrored in AO4
        True
        >>> other.groups[1].sign
        -1
        """
        from .groups import flipped

        return flipped(self, group)

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
        return edges_of(self)

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
            elif e.kind in ("slot", "arc"):  # arc: a pin in a curved slot
                joints.append(("pin-in-slot", (e.a, e.b)))
            elif e.kind == "arcP":  # a block on a curved guide
                joints.append(("P", (e.a, e.b)))
            elif e.kind == "roll":  # a carried contact only adds the no-slip condition
                joints.append(("half" if e.carried else "rolling", (e.a, e.b)))
            else:
                barrel, rod = f"{e.name}#barrel", f"{e.name}#rod"
                joints += [("R", (e.a, barrel)), ("P", (barrel, rod)), ("R", (rod, e.b))]
        n_links = 1 + len(self._links) + 2 * len(self._actuators)
        if not joints:
            return 3 * (n_links - 1)
        return mobility_of(joints, links=n_links)

    def _compile(self) -> _Model:
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
        self._refuse_zero_length(edges)
        m = self.mobility()
        if not self._drivers:
            raise ModelError(f"mobility is {m} but no driver was named: call drive(...)")
        if m != len(self._drivers):
            where = ""
            try:  # the Assur decomposition names the links and joints at fault
                decompose(self, edges)
            except ModelError as exc:
                where = f"; {exc}"
            raise ModelError(
                f"mobility (Kutzbach–Gruebler) is {m} but {len(self._drivers)} driver(s) were "
                f"named ({', '.join(self._drivers)}): name {m} driver(s)"
                + (" — the drawing is a structure" if m <= 0 else "")
                + where
            )
        for name in [*self._springs, *self._torsions]:
            self._element_links(name)  # ends on two different links
        groups, program = decompose(self, edges)
        self._compiled = _Model(self, edges, groups, program)
        return self._compiled

    def _refuse_zero_length(self, edges: list[_Edge]) -> None:
        """A moving link whose pins are all drawn at one place moves nothing: refuse it.

        (A crank drawn with A on O2 would otherwise turn on the spot while the rest
        of the linkage stands still, a structure passed off as a mechanism.) A
        drawing less than 1e-50 across is refused too: the squares of its lengths
        underflow, and its dyads would seem not to close.
        """
        spots = list(self._points.values())
        across = max((abs(z - spots[0]) for z in spots), default=0.0)
        if 0.0 < across < TINY:
            raise InputError(
                "points",
                f"the drawing is {across:g} across, below {TINY:g}, the range machdyn computes "
                "in; draw it in smaller units",
            )
        size = max((abs(z) for z in self._points.values()), default=0.0) or 1.0
        pins: dict[str, list[str]] = {n: [] for n in self._links}
        for e in edges:
            if e.kind == "R":
                for n in (e.a, e.b):
                    if n in pins and e.pa not in pins[n]:
                        pins[n].append(e.pa)
        for name, names in pins.items():
            spots = [self._points[p] for p in names]
            if len(spots) >= 2 and max(abs(z - spots[0]) for z in spots) <= 1e-12 * size:
                raise ModelError(
                    f"link {name!r} has its pins {', '.join(names)} drawn at one place (a "
                    "link of zero length moves nothing): draw them apart, or join the links "
                    "at one named point"
                )

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
        return self._compile().loops().system

    @property
    def groups(self) -> tuple[Group, ...]:
        """The drivers and Assur groups in solving order (:class:`~machdyn.linkage.groups.Group`).

        Each group's kind (``"driver"``, a dyad ``"RRR"``, ``"RRP"``, ... or
        ``"general"``), links, joints and the assembly sign from the drawing,
        which every sample keeps.

        Examples
        --------
        >>> import numpy as np
        >>> lk = (Linkage({"O2": (0, 0), "A": (2, 0), "B": (8, 0)}).ground("O2")
        ...       .link("crank", "O2", "A").link("rod", "A", "B").link("block", "B")
        ...       .slider("block", "ground", "B", 0.0, name="guide").drive("crank"))
        >>> [(g.kind, g.links, g.sign) for g in lk.groups]
        [('driver', ('crank',), 0), ('RRP', ('rod', 'block'), 1)]
        """
        return self._compile().groups

    def solve(
        self,
        values: Any,
        velocity: Any = None,
        acceleration: Any = 0.0,
        jerk: Any = None,
        *,
        continuation: bool | None = None,
    ) -> LinkageMotion:
        """Positions, velocities, accelerations (and jerks) of every link, point and centre of mass.

        The linkage is solved group by group (:attr:`groups`): drivers and
        dyads in closed form, each dyad on the assembly sign of the drawing at
        every sample; a group the closed forms do not cover by the vector-loop
        core. A sample where a group cannot be assembled, or sits at a toggle,
        is flagged (``ok``, ``reason``) naming the group; the links of the
        groups that depend on it are NaN there, never taken from another branch.

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
        jerk : array_like or mapping, optional
            The drivers' third derivatives; given (0 for a steady speed), the
            jerks are computed too (``LinkageMotion.jerk``, ``point_jerk``, ...).
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
        motion = _kinematics.solve(self, values, velocity, acceleration, jerk, continuation)
        return motion if self.units is None else dataclasses.replace(motion, units=self.units)

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
            self,
            motion,
            gravity,
            external_forces,
            external_torques,
            {} if viscous is None else viscous,
            {} if coulomb is None else coulomb,
        )
