"""Assur-group decomposition of a drawn linkage, in solving order.

Starting from the ground, the links are peeled off in groups whose joints fix
exactly their freedoms once the bodies they join are known (Norton,
*Design of Machinery*, §2.15; the notes' Assur groups):

* a **driver**: a link pinned to a known body with its angle driven (a
  crank), turned by a motor against a known body, or sliding on a known body
  with its displacement driven;
* a **dyad** of two links (or one link and a virtual one: a driven
  actuator's bar, the block of a pin-in-slot) joined to each other and to
  known bodies by revolute (R) or prismatic (P) pairs — RRR, RRP, PRR, RPR,
  RPP, PPR, PRP — solved in closed form (:mod:`machdyn.linkage.dyads`), its
  assembly sign taken from the drawing and kept;
* any other group (a triad, a rolling contact, a motor between moving links,
  …) is **general**: solved by the vector-loop core.

Equations are counted per joint: a pin or a slider 2, a slot, a driven
actuator, a carried rolling contact, a driven motor and every driver 1, other
rolling contacts 2; a group of ``k`` links has ``3k`` equations.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import InputError, ModelError
from ._common import GROUND, _ref_angle, check_motion
from .program import RPP, RPR, Crank, Dyad, General, Motor, PArm, Program, RArm, Slide
from .topology import _Edge

if TYPE_CHECKING:
    from .builder import Linkage

__all__ = ["Group"]

#: Largest group searched link set by link set (larger general groups are taken whole).
_SEARCH = 6


@dataclass(frozen=True)
class Group:
    """One Assur group (or driver) of a linkage, as solved.

    Attributes
    ----------
    kind : str
        ``"driver"``; a dyad ``"RRR"``, ``"RRP"``, ``"PRR"``, ``"RPR"``,
        ``"RPP"``, ``"PPR"``, ``"PRP"`` (its joints in order from the first
        link's known side to the second's; a virtual link — an actuator's bar,
        a slot's block — counts as a link); or ``"general"`` (solved by the
        vector-loop core).
    links : tuple of str
        The links it places (virtual links are not listed).
    joints : tuple of str
        The joints and drivers it closes (``"pin A"``, slider and actuator names, ...).
    sign : int
        The assembly sign from the drawing, kept at every sample: +1 or −1
        for RRR (+1: the pin on the left of the line from the first link's
        pivot to the second's), RRP/PRR (+1: the pin ahead of the pivot along
        the slide) and RPR (+1: the second pivot ahead of the first's foot
        along the slide); 0 where there is one solution.
    attached : tuple of str
        The links (solved before it, or the ground) it is joined to.

    Examples
    --------
    >>> import numpy as np
    >>> from machdyn.linkage import Linkage
    >>> lk = (Linkage({"O2": (0, 0), "O4": (8, 0), "A": (4, 0),
    ...                "B": (7.625, np.sqrt(49 - 3.625**2))})
    ...       .ground("O2", "O4").link("crank", "O2", "A").link("coupler", "A", "B")
    ...       .link("rocker", "O4", "B").drive("crank"))
    >>> [(g.kind, g.links, g.sign) for g in lk.groups]
    [('driver', ('crank',), 0), ('RRR', ('coupler', 'rocker'), 1)]
    >>> lk.groups[1].name
    'RRR dyad (coupler, rocker)'
    """

    kind: str
    links: tuple[str, ...]
    joints: tuple[str, ...]
    sign: int
    attached: tuple[str, ...]

    @property
    def name(self) -> str:
        """How reasons and messages name the group."""
        links = ", ".join(self.links)
        if self.kind == "driver":
            return f"driver {self.joints[-1]} ({links})"
        if self.kind == "general":
            return f"group ({links})"
        return f"{self.kind} dyad ({links})"


@dataclass(frozen=True)
class _Con:
    """One constraint between two links: a joint or a driver, with its equation count."""

    kind: str  # R P slot act roll motor angle disp
    name: str
    a: str
    b: str
    eqs: int
    edge: _Edge | None = None


def _constraints(lk: Linkage, edges: list[_Edge]) -> list[_Con]:
    drivers = set(lk._drivers)
    cons = []
    for e in edges:
        if e.kind in ("R", "P"):
            cons.append(_Con(e.kind, e.name, e.a, e.b, 2, e))
        elif e.kind == "slot":
            cons.append(_Con("slot", e.name, e.a, e.b, 1, e))
        elif e.kind == "act":
            if e.name in drivers:
                cons.append(_Con("act", e.name, e.a, e.b, 1, e))
        elif e.kind == "roll":
            cons.append(_Con("roll", e.name, e.a, e.b, 1 if e.carried else 2, e))
        elif e.kind in ("arc", "arcP"):  # curved slot (half) / slider (full): loop core
            cons.append(_Con(e.kind, e.name, e.a, e.b, 1 if e.kind == "arc" else 2, e))
        if e.kind in ("P", "slot") and e.name in drivers:
            cons.append(_Con("disp", e.name, e.a, e.b, 1, e))
    for name in lk._motors:
        if name in drivers:
            a, b = lk._motor_links(name)
            cons.append(_Con("motor", name, a, b, 1))
    for d in lk._drivers:
        if d in lk._links:
            cons.append(_Con("angle", d, GROUND, d, 1))
    return cons


class _Geometry:
    """Drawn offsets and link indices for building the steps."""

    def __init__(self, lk: Linkage) -> None:
        self.lk = lk
        self.index = {GROUND: 0, **{n: i + 1 for i, n in enumerate(lk._links)}}
        self.origin = {GROUND: 0j, **{n: lk._points[ln.points[0]] for n, ln in lk._links.items()}}
        self.driver = {d: i for i, d in enumerate(lk._drivers)}

    def xy(self, key: str) -> complex:
        return self.lk._xy(key)

    def ref(self, link: str, key: str) -> tuple[int, complex]:
        return self.index[link], self.xy(key) - self.origin[link]

    def at(self, link: str, z: complex) -> tuple[int, complex]:
        return self.index[link], z - self.origin[link]

    def r_arm(self, link: str, known: str, pivot: str, pin: str) -> RArm | None:
        u0 = self.xy(pin) - self.xy(pivot)
        if abs(u0) == 0:
            return None
        return RArm(
            self.ref(known, pivot), self.index[link], self.xy(pin) - self.origin[link], u0, abs(u0)
        )

    def p_arm(self, link: str | None, known: str, e: _Edge, pin: str) -> PArm:
        B0 = self.xy(pin)
        r = 0j if link is None else B0 - self.origin[link]
        return PArm(
            self.index[known],
            self.at(known, B0),
            e.direction,
            -1 if link is None else self.index[link],
            r,
        )


def _sign(x: float) -> int:
    return 1 if x > 0 else -1 if x < 0 else 0


class _Decomposer:
    """Peel a linkage into drivers and Assur groups; build the program of closed-form steps."""

    def __init__(self, lk: Linkage, edges: list[_Edge]) -> None:
        self.lk = lk
        self.edges = edges
        self.geo = _Geometry(lk)
        self.cons = _constraints(lk, edges)
        self.touching: dict[str, list[_Con]] = {n: [] for n in [GROUND, *lk._links]}
        for c in self.cons:
            self.touching[c.a].append(c)
            if c.b != c.a:
                self.touching[c.b].append(c)
        self.known = {GROUND}
        self.groups: list[Group] = []
        self.steps: list[Any] = []  # None for a general group
        self.exact = {GROUND: True}
        self.group_of_link: dict[str, int] = {}

    # ------------------------------------------------------------------ search
    def relevant(self, S: set[str]) -> list[_Con]:
        seen, out = set(), []
        for n in sorted(S, key=self.geo.index.__getitem__):  # the links' order, not the set's
            for c in self.touching[n]:
                if id(c) not in seen and c.a in S | self.known and c.b in S | self.known:
                    seen.add(id(c))
                    out.append(c)
        return out

    def run(self) -> None:
        unknown = list(self.lk._links)
        while unknown:
            S, rel = self.next_group(unknown)
            self.add(S, rel)
            unknown = [n for n in unknown if n not in S]

    def next_group(self, unknown: list[str]) -> tuple[list[str], list[_Con]]:
        for size in range(1, min(len(unknown), _SEARCH) + 1):
            for S in combinations(unknown, size):
                rel = self.relevant(set(S))
                count = sum(c.eqs for c in rel)
                if count > 3 * size:
                    self.over(list(S), rel)
                if count == 3 * size and self.connected(set(S), rel):
                    return list(S), rel
        rel = self.relevant(set(unknown))
        count = sum(c.eqs for c in rel)
        if count == 3 * len(unknown):
            return unknown, rel
        if count > 3 * len(unknown):
            self.over(unknown, rel)
        raise ModelError(
            f"link(s) {', '.join(unknown)} are not determined by their joints and drivers "
            f"({count} equations for their {3 * len(unknown)} freedoms): a floating link, "
            "or fewer drivers than freedoms there"
        )

    def connected(self, S: set[str], rel: list[_Con]) -> bool:
        if len(S) == 1:
            return True
        seen = {next(iter(S))}
        grew = True
        while grew:
            grew = False
            for c in rel:
                if (c.a in seen) != (c.b in seen) and c.a in S and c.b in S:
                    seen |= {c.a, c.b}
                    grew = True
        return seen == S

    def over(self, S: list[str], rel: list[_Con]) -> None:
        raise ModelError(
            f"link(s) {', '.join(S)} are over-constrained: {', '.join(c.name for c in rel)} "
            f"fix {sum(c.eqs for c in rel)} equations for their {3 * len(S)} freedoms "
            "(a structure, or more drivers than freedoms)"
        )

    # ------------------------------------------------------------------ groups
    def add(self, S: list[str], rel: list[_Con]) -> None:
        made = self.closed_form(S, rel)
        if made is None:
            kind, step, sign = "general", self.general(S, rel), 0
            for n in S:
                self.exact[n] = True  # continuous: the loop core follows the sweep
        else:
            kind, step, sign = made
        attached = sorted({n for c in rel for n in (c.a, c.b) if n not in S})
        joints = tuple(dict.fromkeys(c.name for c in rel))
        g = len(self.groups)
        self.groups.append(Group(kind, tuple(S), joints, sign, tuple(attached)))
        self.steps.append(step)
        for n in S:
            self.group_of_link[n] = g
        self.known |= set(S)

    def general(self, S: list[str], rel: list[_Con]) -> General:
        """The step of a group solved by the vector-loop core (the known links as inputs)."""
        from .loopcompile import compile_loops

        mine = {c.name for c in rel if c.kind in ("angle", "motor", "disp", "act")}
        drivers = tuple(d for d in self.lk._drivers if d in mine)
        compiled = compile_loops(self.lk, self.edges, S, drivers, set(self.known))
        return General(self.lk, compiled, tuple(S), tuple(self.geo.driver[d] for d in drivers))

    def closed_form(self, S: list[str], rel: list[_Con]) -> tuple[str, Any, int] | None:
        if len(S) == 1:
            return self.single(S[0], rel)
        if len(S) == 2 and len(rel) == 3 and all(c.kind in ("R", "P") for c in rel):
            return self.dyad(S[0], S[1], rel)
        return None

    def single(self, L: str, rel: list[_Con]) -> tuple[str, Any, int] | None:
        by = {c.kind: c for c in rel}
        kinds = sorted(by)
        if len(rel) != 2:
            return None
        geo, i = self.geo, self.geo.index[L]
        if kinds == ["R", "angle"]:
            pin = by["R"]
            K, p = self.other(pin, L), pin.edge.pa
            self.exact[L] = True
            step = Crank(
                i, geo.ref(K, p), geo.xy(p) - geo.origin[L], geo.driver[L], _ref_angle(self.lk, L)
            )
            return "driver", step, 0
        if kinds == ["R", "motor"]:
            pin, motor = by["R"], by["motor"]
            K, p = self.other(pin, L), pin.edge.pa
            source = self.other(motor, L)
            sign = 1.0 if motor.b == L else -1.0
            phi0 = _ref_angle(self.lk, motor.b) - _ref_angle(self.lk, motor.a)
            self.exact[L] = self.exact[source]
            step = Motor(
                i,
                geo.ref(K, p),
                geo.xy(p) - geo.origin[L],
                geo.index[source],
                sign,
                geo.driver[motor.name],
                phi0,
            )
            return "driver", step, 0
        if kinds == ["P", "disp"] and by["P"].name == by["disp"].name:
            e = by["P"].edge
            K = self.other(by["P"], L)
            block = e.b == L
            self.exact[L] = self.exact[K]
            step = Slide(
                i,
                geo.index[K],
                geo.ref(e.a, e.pa),
                geo.ref(e.b, e.pb),
                e.direction,
                geo.driver[e.name],
                block,
            )
            return "driver", step, 0
        if kinds == ["R", "act"]:
            return self.with_actuator(L, by["R"], by["act"])
        if kinds == ["P", "act"]:
            return self.with_actuator(L, by["P"], by["act"])
        if kinds == ["R", "slot"] or kinds == ["P", "slot"]:
            return self.with_slot(L, by.get("R") or by["P"], by["slot"])
        return None

    def other(self, c: _Con, L: str) -> str:
        return c.b if c.a == L else c.a

    def arm(self, L: str, c: _Con, pin: str) -> RArm | PArm | None:
        """The arm of link ``L`` from its joint ``c`` with a known body to the dyad's pin."""
        K = self.other(c, L)
        if c.kind == "R":
            return self.geo.r_arm(L, K, c.edge.pa, pin)
        return self.geo.p_arm(L, K, c.edge, pin)

    def with_actuator(self, L: str, c: _Con, act: _Con) -> tuple[str, Any, int] | None:
        geo, e = self.geo, act.edge
        near, far = (e.pb, e.pa) if act.b == L else (e.pa, e.pb)  # on L / on the known body
        K = self.other(act, L)
        u0 = geo.xy(near) - geo.xy(far)
        if abs(u0) == 0:
            return None
        bar = RArm(geo.ref(K, far), -1, 0j, u0, abs(u0), geo.driver[act.name])
        own = self.arm(L, c, near)
        if own is None:
            return None
        sign = self.sign2(own, bar, geo.xy(near))
        kind = ("R" if c.kind == "R" else "P") + "RR"
        self.set_exact(own, L)
        return kind, Dyad(own, bar, sign), int(sign)

    def with_slot(self, L: str, c: _Con, slot: _Con) -> tuple[str, Any, int] | None:
        geo, e = self.geo, slot.edge
        if e.b == L:  # the pin is L's, the slot a known body's: a virtual block slides there
            own = self.arm(L, c, e.pb)
            if own is None:
                return None
            block = geo.p_arm(None, e.a, e, e.pb)
            sign = self.sign2(own, block, geo.xy(e.pb))
            self.set_exact(own, L)
            return ("R" if c.kind == "R" else "P") + "RP", Dyad(own, block, sign), int(sign)
        # the slot is L's; a known body's pin slides in it
        S_ref = geo.ref(e.b, e.pb)
        if c.kind == "R":
            return self.rpr(L, c, S_ref, geo.xy(e.pb), -1, e.direction)
        return self.rpp(None, S_ref, geo.xy(e.pb), e.direction, L, c)

    def set_exact(self, arm: RArm | PArm, L: str) -> None:
        if isinstance(arm, RArm):
            self.exact[L] = False
        else:
            self.exact[L] = self.exact[self.name_of(arm.known)]

    def name_of(self, index: int) -> str:
        return GROUND if index == 0 else list(self.lk._links)[index - 1]

    def sign2(self, arm1: RArm | PArm, arm2: RArm | PArm, B0: complex) -> float:
        """The drawn assembly sign of two arms meeting at ``B0`` (0 for two sliders)."""
        if isinstance(arm1, RArm) and isinstance(arm2, RArm):
            A1, A2 = self.drawn(arm1.centre), self.drawn(arm2.centre)
            return float(_sign(((A2 - A1).conjugate() * (B0 - A1)).imag))
        if isinstance(arm1, RArm) or isinstance(arm2, RArm):
            r, p = (arm1, arm2) if isinstance(arm1, RArm) else (arm2, arm1)
            return float(_sign(((B0 - self.drawn(r.centre)) * p.u0.conjugate()).real))
        return 0.0

    def drawn(self, ref: tuple[int, complex]) -> complex:
        i, r = ref
        return self.geo.origin[self.name_of(i)] + r

    def dyad(self, L1: str, L2: str, rel: list[_Con]) -> tuple[str, Any, int] | None:
        inner = [c for c in rel if {c.a, c.b} == {L1, L2}]
        if len(inner) != 1:
            return None
        mid = inner[0]
        j1 = [c for c in rel if c is not mid and L1 in (c.a, c.b)]
        j3 = [c for c in rel if c is not mid and L2 in (c.a, c.b)]
        if len(j1) != 1 or len(j3) != 1:
            return None
        j1, j3 = j1[0], j3[0]
        kind = j1.kind + mid.kind + j3.kind
        geo = self.geo
        if mid.kind == "R":
            pin = mid.edge.pa
            arm1, arm2 = self.arm(L1, j1, pin), self.arm(L2, j3, pin)
            if arm1 is None or arm2 is None:
                return None
            sign = self.sign2(arm1, arm2, geo.xy(pin))
            self.set_exact(arm1, L1)
            self.set_exact(arm2, L2)
            return kind, Dyad(arm1, arm2, sign), int(sign)
        if j1.kind == "R" and j3.kind == "R":
            C = j3.edge.pa
            return self.rpr(
                L1,
                j1,
                geo.ref(self.other(j3, L2), C),
                geo.xy(C),
                geo.index[L2],
                mid.edge.direction,
                kind,
            )
        if j1.kind == "R" and j3.kind == "P":
            return self.rpp(
                L1,
                geo.ref(self.other(j1, L1), j1.edge.pa),
                geo.xy(j1.edge.pa),
                mid.edge.direction,
                L2,
                j3,
                kind,
            )
        if j1.kind == "P" and j3.kind == "R":
            return self.rpp(
                L2,
                geo.ref(self.other(j3, L2), j3.edge.pa),
                geo.xy(j3.edge.pa),
                mid.edge.direction,
                L1,
                j1,
                kind,
            )
        return None

    def rpr(
        self, L1: str, pin: _Con, C_ref, C0: complex, link2: int, u0: complex, kind: str = "RPR"
    ) -> tuple[str, Any, int] | None:
        geo = self.geo
        A = pin.edge.pa
        A0 = geo.xy(A)
        w = (C0 - A0) * u0.conjugate()
        if w.real == 0:
            return None
        r2 = 0j if link2 < 0 else C0 - geo.origin[self.name_of(link2)]
        step = RPR(
            geo.index[L1],
            geo.ref(self.other(pin, L1), A),
            A0 - geo.origin[L1],
            C_ref,
            link2,
            r2,
            w.imag,
            u0,
            float(_sign(w.real)),
        )
        self.exact[L1] = False
        if link2 >= 0:
            self.exact[self.name_of(link2)] = False
        return kind, step, _sign(w.real)

    def rpp(
        self,
        L1: str | None,
        A_ref,
        A0: complex,
        u1: complex,
        L2: str,
        slide: _Con,
        kind: str = "PPR",
    ) -> tuple[str, Any, int] | None:
        geo = self.geo
        K = self.other(slide, L2)
        u2 = slide.edge.direction
        if (u1.conjugate() * u2).imag == 0:
            return None
        step = RPP(
            -1 if L1 is None else geo.index[L1],
            A_ref,
            0j if L1 is None else A0 - geo.origin[L1],
            geo.index[K],
            geo.at(K, A0),
            u1,
            u2,
            geo.index[L2],
            A0 - geo.origin[L2],
        )
        for n in (L1, L2):
            if n is not None:
                self.exact[n] = self.exact[K]
        return kind, step, 0

    # ------------------------------------------------------------------ result
    def program(self) -> Program:
        """The program of the steps, one per group."""
        deps = []
        for grp in self.groups:
            deps.append(tuple(sorted({self.group_of_link[n] for n in grp.attached if n != GROUND})))
        unwrap = frozenset(
            self.geo.index[n] for n in self.lk._links if not self.exact.get(n, False)
        )
        links = [tuple(self.geo.index[n] for n in grp.links) for grp in self.groups]
        steps, order = list(self.steps), list(range(len(self.steps)))
        return Program(len(self.geo.index), steps, order, deps, links, unwrap)


def decompose(lk: Linkage, edges: list[_Edge]) -> tuple[tuple[Group, ...], Program]:
    """The groups of ``lk`` in solving order and the program of their steps."""
    d = _Decomposer(lk, edges)
    d.run()
    return tuple(d.groups), d.program()


# ---------------------------------------------------------------------- analyses on groups
def transmission_angles(lk: Linkage, motion: Any) -> dict[str, np.ndarray]:
    """The transmission angle μ of every dyad with two assemblies, per sample (radians).

    RRR: the acute angle between its two links at the middle pin (``FourBar.mu``'s
    convention: 90° best, 0 at a toggle); RRP/PRR: the acute angle between the
    rod and the normal to the slide (90° when the rod pushes along the slide).
    NaN where the motion is not ok.
    """
    from .kinematics import LinkageMotion

    if not isinstance(motion, LinkageMotion):
        raise InputError("motion", f"must be a LinkageMotion from Linkage.solve, got {motion!r}")
    check_motion(lk, motion)
    program = lk._compile().program
    names = {i + 1: n for i, n in enumerate(lk._links)}
    theta0 = {n: _ref_angle(lk, n) for n in lk._links}

    def rotation(i: int) -> Any:
        if i == 0:
            return 1.0
        name = names[i]
        return np.exp(1j * (np.asarray(motion.theta[name]) - theta0[name]))

    def at(i: int, r: complex) -> Any:
        if i == 0:
            return r
        first = lk._links[names[i]].points[0]
        return np.asarray(motion.points[first]) + r * rotation(i)

    out: dict[str, np.ndarray] = {}
    bad = ~np.asarray(motion.ok)
    for grp, step in zip(lk._compile().groups, program.steps, strict=True):
        if not isinstance(step, Dyad) or step.sign == 0:
            continue
        arms = (step.arm1, step.arm2)
        real = next(a for a in arms if a.link >= 0)
        B = at(real.link, real.r)
        vec = []
        for a in arms:
            if isinstance(a, RArm):
                vec.append(at(*a.centre) - B)
            else:
                vec.append(1j * a.u0 * rotation(a.known))  # the slide's normal
        c = np.abs((vec[0] * np.conj(vec[1])).real) / (np.abs(vec[0]) * np.abs(vec[1]))
        mu = np.arccos(np.clip(c, 0.0, 1.0))
        out[grp.name] = np.where(bad, np.nan, mu)
    return out


def flipped(lk: Linkage, group: str) -> Linkage:
    """``lk`` drawn on the other assembly of dyad ``group`` (its name), at the drawn inputs."""
    from dataclasses import replace

    from .program import OK, RPR
    from .view import rebuilt

    model = lk._compile()
    program = model.program
    names = [g.name for g in model.groups]
    if not isinstance(group, str):
        raise InputError("group", f"name a group by its name (text), got {group!r}")
    if group not in names:
        raise ModelError(f"no group named {group!r}; groups: {', '.join(names)}")
    g = names.index(group)
    step = program.steps[g]
    if not isinstance(step, Dyad | RPR) or step.sign == 0:
        raise ModelError(f"{group} has one assembly only: there is nothing to flip")
    steps = list(program.steps)
    steps[g] = replace(step, sign=-step.sign)
    other = Program(program.n_links, steps, program.group_of_step, program.deps, program.links,
                    program.unwrap)  # fmt: skip
    start = list(lk.drawn_inputs.values())
    st, codes = other.run([[np.array([v]), 0.0, 0.0, 0.0] for v in start], 1, 0, False)
    for h, code in enumerate(codes[:, 0]):
        if code != OK:
            raise ModelError(
                f"{group} cannot be drawn on its other assembly at the drawn driver values: "
                f"{names[h]} does not close there"
            )
    index = {GROUND: 0, **{n: i + 1 for i, n in enumerate(lk._links)}}
    origin = {GROUND: 0j, **{n: lk._points[ln.points[0]] for n, ln in lk._links.items()}}
    points = dict(lk._points)
    for owner, pts in [(GROUND, lk._ground)] + [(n, ln.points) for n, ln in lk._links.items()]:
        for p in pts:
            if owner != GROUND:
                points[p] = complex(st.pos((index[owner], lk._points[p] - origin[owner]))[0])
    turn = {n: complex(st.E[index[n]][0]) for n in lk._links} | {GROUND: 1 + 0j}
    return rebuilt(lk, points, turn)
