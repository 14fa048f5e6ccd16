"""Joints of a drawn linkage: sliders, slots, actuators, rolling contacts, motors.

:class:`_JointMethods` holds the :class:`~machdyn.linkage.Linkage` builder
methods that add a joint (pins need none: a point shared by two links is one).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, NoReturn

import numpy as np

from .._validate import boolean, finite_scalar
from ..errors import AssemblyError, InputError, ModelError
from ._common import GROUND, _complex_point, _is_inf, _link_pair, _name

if TYPE_CHECKING:
    from .builder import Linkage


class _JointMethods:
    """The joint builders of :class:`~machdyn.linkage.Linkage` (a mixin)."""

    def _line(self, field: str, direction: Any, at: complex, through: str | None) -> complex:
        if isinstance(direction, str):
            self._need_points(field, [direction])
            u = self._points[direction] - at
            if abs(u) == 0:
                raise AssemblyError(f"{field}: direction point {direction!r} coincides with it")
        elif not isinstance(direction, complex | list | tuple | np.ndarray):
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
        centre: str | None = None,
        radius: float | None = None,
    ) -> Linkage:
        """Add a prismatic joint: link ``block`` slides on link ``on`` (or ``"ground"``).

        The slide line is fixed in ``on``, passes through the drawn position of
        point ``at`` (a point of ``block``), with ``direction`` an angle in
        radians, a vector ``(dx, dy)``, or a point name of ``on`` on the line.
        ``through`` optionally names a point of ``on`` that must lie on the line
        (the drawing is checked). The slider displacement ``d`` is measured
        along the line from the foot of ``on``'s first point (or ``through``).
        The block turns with ``on`` (same angular velocity).

        A *curved* slide: give ``centre``, a point of ``on`` at the centre of
        curvature of a circular guide through ``at`` (and optionally its
        ``radius``, checked against the drawing). The block then slides along
        the arc and turns with the radius ``centre → at`` (Norton's effective
        link: a binary link pinned at the centre of curvature); ``direction``
        and ``through`` are not used.

        Examples
        --------
        A slider-crank (crank 2, rod 6, no offset) drawn at θ2 = 0; the block is
        a one-point link (its pin B) sliding on the ground along +x:

        >>> from machdyn.linkage import Linkage
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
        name = f"{block}/{on}" if name is None else _name("name", name)
        _names_given(name, block=block, on=on, at=at, through=through, centre=centre)
        if centre is not None or radius is not None:
            return self._curved_joint("slider", block, on, at, centre, radius, name)
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
        centre: str | None = None,
        radius: float | None = None,
    ) -> Linkage:
        """Add a pin-in-slot half joint: point ``pin`` of ``link`` in a slot of ``on``.

        The slot is fixed in ``on`` along ``direction`` through the drawn pin
        (as in :meth:`slider`); the pin may turn in it (two freedoms: a half
        joint in the Kutzbach count).

        A *curved* slot: give ``centre``, a point of ``on`` at the centre of the
        circular arc through the drawn pin (and optionally its ``radius``,
        checked against the drawing); the pin then runs on that arc (Norton's
        effective link from the centre of curvature to the pin), with the slip
        acceleration ``v²/ρ`` toward the centre and the Coriolis term when
        ``on`` turns.

        Examples
        --------
        A Scotch yoke: the crank pin A runs in a vertical slot of a yoke that
        slides horizontally, so the yoke moves ``x = r cos θ2``:

        >>> from machdyn.linkage import Linkage
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
        name = f"{pin}@{on}" if name is None else _name("name", name)
        _names_given(name, pin=pin, link=link, on=on, through=through, centre=centre)
        if link == GROUND:  # a fixed pin in a slot of a moving link: a block on the pin
            raise ModelError(
                f"slot {name!r}: the pin must ride on a moving link, not the ground; for a "
                f"fixed pin {pin!r} in a slot of {on!r}, add a one-point link on the pin "
                f"(link('block', {pin!r})) and slide it: slider('block', {on!r}, {pin!r}, ...)"
            )
        if centre is not None or radius is not None:
            return self._curved_joint("slot", link, on, pin, centre, radius, name)
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

    def _curved_joint(
        self,
        kind: str,
        moving: str,
        on: str,
        at: str,
        centre: str | None,
        radius: float | None,
        name: str,
    ) -> Linkage:
        """A slider or slot on a circular arc of ``on`` about its point ``centre``."""
        what = f"{kind} {name!r}"
        if moving not in self._links:
            raise ModelError(f"{what}: unknown link {moving!r}; links: {self._names()}")
        if on != GROUND and on not in self._links:
            raise ModelError(f"{what}: unknown link {on!r}; links: {self._names()}")
        if at not in self._links[moving].points:
            raise ModelError(f"{what}: point {at!r} is not on link {moving!r}")
        if centre is None:
            raise InputError(
                f"{name}.centre",
                "a curved slot or slider needs its centre of curvature: a point of the "
                f"link {on!r} it runs on",
            )
        self._need_points(what, [centre])
        on_points = self._ground if on == GROUND else self._links[on].points
        if centre not in on_points:
            raise ModelError(f"{what}: the centre {centre!r} is not a point of {on!r}")
        drawn = abs(self._points[at] - self._points[centre])
        if radius is not None:
            r = finite_scalar(f"{name}.radius", radius)
            if r <= 0.0:
                raise InputError(
                    f"{name}.radius", f"must be a positive radius of curvature, got {r:g}"
                )
            if abs(r - drawn) > 1e-9 * max(r, drawn):
                raise AssemblyError(
                    f"{what}: the point {at!r} is {drawn:.10g} from the centre {centre!r}, "
                    f"not on the arc of radius {r:.10g}"
                )
        if drawn == 0.0:
            raise InputError(
                f"{name}.radius", f"must be positive: {at!r} sits on the centre {centre!r}"
            )
        if self._joint_named(name):
            raise ModelError(f"joint name {name!r} is used twice")
        self._curved[name] = (kind, moving, on, at, centre, float(drawn))
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
        >>> from machdyn.linkage import Linkage
        >>> lk = Linkage({"C": (0, 0), "D": (3, 4)}).ground("C")
        >>> lk = lk.link("arm", "D", "C").actuator("cyl", "C", "D", links=("ground", "arm"))
        """
        if not isinstance(name, str) or not name:
            raise InputError("actuator", f"a name is a non-empty string, got {name!r}")
        if self._joint_named(name):
            raise ModelError(f"joint name {name!r} is used twice")
        self._need_points(f"actuator {name!r}", (start, end))
        ends = _link_pair(f"{name}.links", links)
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

        >>> from machdyn.linkage import Linkage
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
        _names_given("roll", link_a=link_a, centre_a=centre_a, link_b=link_b, centre_b=centre_b)
        name = f"{link_a}~{link_b}" if name is None else _name("roll", name)
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
        internal = boolean(f"{name}.internal", internal)
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

        >>> from machdyn.linkage import Linkage
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
            given = _link_pair(f"{name}.links", links)
            if len(given) != 2:
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


def _ground_motor(name: str, at: str, pair: tuple[str, str]) -> NoReturn:
    """Refuse a motor on a ground pin: it is an ordinary link driver."""
    other = pair[1] if pair[0] == GROUND else pair[0]
    raise ModelError(
        f"motor {name!r}: pin {at!r} joins the ground, so the motor turns {other!r} "
        f"by its absolute angle — that is an ordinary link driver: drive({other!r})"
    )


def _names_given(joint: str, **given: Any) -> None:
    """Refuse a point or link name that is not text (None: not given)."""
    for field, value in given.items():
        if value is not None:
            _name(f"{joint}.{field}", value)
