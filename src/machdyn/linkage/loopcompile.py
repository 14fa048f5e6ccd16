"""Compiling a linkage — or one of its Assur groups — into vector loops (:mod:`machdyn.loops`).

The notes' method (review lecture 3; Norton, *Design of Machinery*, §4.5 and
§4.13): links are the nodes and joints the edges of the link graph; a spanning
tree grown from the base gives one independent loop per remaining joint; in
each loop every link contributes the vector from the joint where the loop
enters it to the joint where it leaves (from its *hub*, so a link with k joints
has at most k − 1 vectors); links joined by a prismatic joint share one angle
variable, other vectors of one link are tied by constant-angle constraints.

The base is the ground for the whole linkage. For a group solved after others
(:mod:`machdyn.linkage.groups`), the base is every link already known: a
vector fixed in a known link has the link's angle (an **input** of the loop
system) plus a constant, and a vector between points of two different known
bodies has an input length and angle — their values come from the known poses.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import AssemblyError, ModelError
from ..loops import LoopSystem
from ._common import GROUND, _ref_angle, _typical_length
from .topology import _Edge

if TYPE_CHECKING:
    from .builder import Linkage

_IDENT = re.compile(r"\W")

Side = tuple[str, str]  # (link, point key)


@dataclass(frozen=True)
class _Compiled:
    system: LoopSystem
    driver_vars: tuple[str, ...]  # loop variable of each driver (of the group)
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
    drivers: tuple[str, ...] = ()  # the drivers of the group, in the order of driver_vars
    # inputs from known links: angle variable -> (link, drawn angle), and
    # (length variable, angle variable) -> the two sides it joins
    rot_inputs: dict[str, tuple[str, float]] = field(default_factory=dict)
    vec_inputs: dict[tuple[str, str], tuple[Side, Side]] = field(default_factory=dict)


def _ident(text: str) -> str:
    """A loop-variable name made of ``text`` (non-word characters become ``_``)."""
    return _IDENT.sub("_", text)


class _LoopCompiler:
    """One compilation: the loops of ``group`` (all links) against the known ``base``."""

    def __init__(
        self,
        lk: Linkage,
        edges: list[_Edge],
        group: list[str] | None = None,
        drivers: tuple[str, ...] | None = None,
        known: set[str] | None = None,
    ) -> None:
        self.lk = lk
        self.group = list(lk._links) if group is None else list(group)
        inside = set(self.group)
        self.base = {GROUND} | (known or set())
        both = inside | self.base
        self.edges = [e for e in edges if (e.a in inside or e.b in inside) and {e.a, e.b} <= both]
        self.drivers = tuple(lk._drivers) if drivers is None else drivers
        self.system = LoopSystem()
        self.drawn: dict[str, float] = {}
        self.used: set[str] = set()
        self.class_var: dict[str, tuple[str, float]] = {}
        self.vec_of: dict[tuple[str, str, str], tuple[str, int]] = {}
        self.cross_vars: dict[str, tuple[str, str | None, float]] = {}
        self.cross_vec: dict[int, list[tuple[str, int]]] = {}
        self.roll_parts: dict[str, tuple[tuple[float, float | str, float | str], ...]] = {}
        self.rot_inputs: dict[str, tuple[str, float]] = {}
        self.vec_inputs: dict[tuple[str, str], tuple[Side, Side]] = {}
        self.bridges: dict[tuple[Side, Side], str] = {}
        self.cls = {n: n for n in [*self.base, *self.group]}
        for e in self.edges:
            if e.kind == "P":
                self.union(e.a, e.b)

    # ------------------------------------------------------------------ helpers
    def node(self, link: str) -> str:
        """The graph node of a link: the base (named ground) for every known link."""
        return GROUND if link in self.base else link

    def find(self, n: str) -> str:
        while self.cls[n] != n:
            n = self.cls[n]
        return n

    def union(self, a: str, b: str) -> None:
        ra, rb = self.find(a), self.find(b)
        if ra == rb:
            return
        if rb == GROUND or (rb in self.base and ra != GROUND):
            ra, rb = rb, ra  # the root of a class is the ground, else a known link
        self.cls[rb] = ra

    def fresh(self, base: str) -> str:
        name = _ident(base)
        k, out = 1, name
        while out in self.used:
            k += 1
            out = f"{name}_{k}"
        self.used.add(out)
        return out

    def side(self, e: _Edge, node: str) -> Side:
        """The link and point key of joint ``e`` at graph node ``node``."""
        if self.node(e.a) == node:
            return e.a, e.pa
        return e.b, e.pb

    def angle_of(self, link: str, ang0: float, tag: str) -> str | float:
        """Angle variable (or constant) of a vector fixed in ``link`` drawn at ``ang0``."""
        root = self.find(link)
        if root == GROUND:
            return ang0
        if root not in self.class_var:
            var = self.fresh(f"theta_{root}")
            self.class_var[root] = (var, ang0)
            self.drawn[var] = ang0
            if root in self.base:
                self.rot_inputs[var] = (root, ang0)
            return var
        var0, a0 = self.class_var[root]
        var = self.fresh(f"theta_{link}_{tag}")
        self.system.constraint(f"{var} = {var0} + alpha", alpha=ang0 - a0)
        self.drawn[var] = ang0
        return var

    def link_vector(self, link: str, p: str, q: str) -> tuple[str, int] | None:
        if p == q:
            return None
        if (link, p, q) in self.vec_of:
            return self.vec_of[(link, p, q)]
        if (link, q, p) in self.vec_of:
            name, s = self.vec_of[(link, q, p)]
            return name, -s
        z = self.lk._xy(q) - self.lk._xy(p)
        if abs(z) == 0:
            return None
        name = self.fresh(f"R_{link}_{p}{q}")
        ang = self.angle_of(link, float(np.angle(z)), f"{p}{q}")
        self.system.vector(name, float(abs(z)), ang)
        self.vec_of[(link, p, q)] = (name, 1)
        return name, 1

    def base_vector(self, a: Side, b: Side) -> list[tuple[str, int]]:
        """From a point of one known body to a point of another (or of the same one)."""
        (ka, p), (kb, q) = a, b
        if p == q:
            return []
        if ka == kb:
            v = self.link_vector(ka, p, q)
            return [] if v is None else [v]
        if (a, b) in self.bridges:
            return [(self.bridges[(a, b)], 1)]
        if (b, a) in self.bridges:
            return [(self.bridges[(b, a)], -1)]
        z = self.lk._xy(q) - self.lk._xy(p)
        name = self.fresh(f"R_{ka}_{p}_{kb}_{q}")
        lv, av = self.fresh(f"L_{name}"), self.fresh(f"phi_{name}")
        self.drawn[lv], self.drawn[av] = float(abs(z)), float(np.angle(z))
        self.system.vector(name, lv, av)
        self.vec_inputs[(lv, av)] = (a, b)
        self.bridges[(a, b)] = name
        return [(name, 1)]

    # ------------------------------------------------------------------ graph
    def spanning_tree(self) -> None:
        adj: dict[str, list[int]] = {GROUND: [], **{n: [] for n in self.group}}
        for i, e in enumerate(self.edges):
            adj[self.node(e.a)].append(i)
            adj[self.node(e.b)].append(i)
        self.parent: dict[str, tuple[int, str] | None] = {GROUND: None}
        self.depth = {GROUND: 0}
        self.tree_edges: set[int] = set()
        self.tree: list[tuple[str, _Edge, bool]] = []
        order = [GROUND]
        for node in order:
            for i in adj[node]:
                e = self.edges[i]
                other = self.node(e.b) if self.node(e.a) == node else self.node(e.a)
                if other not in self.parent:
                    self.parent[other] = (i, node)
                    self.depth[other] = self.depth[node] + 1
                    order.append(other)
                    self.tree_edges.add(i)
                    self.tree.append((other, e, other == e.b))
        loose = [n for n in self.group if n not in self.parent]
        if loose:
            raise ModelError(
                f"link(s) {', '.join(loose)} are not connected to the ground by any joint chain"
            )
        self.hub = {child: (e.pb if child_is_b else e.pa) for child, e, child_is_b in self.tree}

    def cycles(self) -> list[list[tuple[int, str, str]]]:
        """Fundamental cycles, one per chord: (edge, from node, to node) steps."""
        out = []
        parent, depth = self.parent, self.depth
        for i, e in enumerate(self.edges):
            if i in self.tree_edges:
                continue
            a, b = self.node(e.a), self.node(e.b)
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
            na, nb = self.node(e.a), self.node(e.b)
            out.append(up_a + [(j, t, f) for j, f, t in reversed(up_b)] + [(i, nb, na)])
        return out

    def through(self, node: str, e_in: _Edge, e_out: _Edge) -> list[tuple[str, int]]:
        """Vectors across graph node ``node`` from joint ``e_in`` to joint ``e_out``."""
        a, b = self.side(e_in, node), self.side(e_out, node)
        if node == GROUND:
            return self.base_vector(a, b)
        link, p, q = node, a[1], b[1]
        if p == q:
            return []
        if self.hub[link] in (p, q):
            v = self.link_vector(link, p, q)
            return [] if v is None else [v]
        out = []
        for x, sign in ((p, -1), (q, 1)):
            v = self.link_vector(link, self.hub[link], x)
            if v is not None:
                out.append((v[0], sign * v[1]))
        return out

    # ------------------------------------------------------------------ joints
    def crossing(self, i: int) -> list[tuple[str, int]]:
        """Vectors (with signs) crossing joint ``i`` from its point on ``a`` to ``b``'s."""
        e = self.edges[i]
        if e.kind == "R":
            return []
        if i not in self.cross_vec:
            if e.kind == "roll":
                made = self.roll_crossing(e)
            elif e.kind in ("arc", "arcP"):
                made = self.arc_crossing(e)
            else:
                made = [(self.new_crossing(e), 1)]
            self.cross_vec[i] = made
        return self.cross_vec[i]

    def arc_crossing(self, e: _Edge) -> list[tuple[str, int]]:
        """Centre of curvature → pin: ``R e^{jψ}``, the effective link of a curved joint.

        In a curved slot ψ is free (the pin turns in the slot); a curved slider's
        block turns with the radius, so ψ is an angle of the block.
        """
        z = self.lk._xy(e.pb) - self.lk._xy(e.pa)
        name = self.fresh(f"R_{e.name}")
        if e.kind == "arcP":
            ang: float | str = self.angle_of(e.b, float(np.angle(z)), f"arc_{e.name}")
        else:
            ang = self.fresh(f"psi_{e.name}")
            self.drawn[ang] = float(np.angle(z))
        self.system.vector(name, e.radii[0], ang)
        self.roll_parts[e.name] = ((1.0, e.radii[0], ang),)
        return [(name, 1)]

    def roll_crossing(self, e: _Edge) -> list[tuple[str, int]]:
        z = self.lk._xy(e.pb) - self.lk._xy(e.pa)
        fresh, drawn, system = self.fresh, self.drawn, self.system
        if np.isinf(e.radii[1]):  # centre_a -> contact line point: -(s û + r n̂), fixed in b
            n0 = e.direction
            svar = fresh(f"s_{e.name}")
            drawn[svar] = 0.0
            ang_u = self.angle_of(e.b, float(np.angle(1j * n0)), f"tan_{e.name}")
            ang_n = self.angle_of(e.b, float(np.angle(n0)), f"nor_{e.name}")
            ru, rn = fresh(f"R_{e.name}_s"), fresh(f"R_{e.name}_n")
            system.vector(ru, svar, ang_u)
            height: float | str = e.radii[0]
            if e.carried:  # the guide fixes the height already: a free length
                height = fresh(f"h_{e.name}")
                drawn[height] = e.radii[0]
            system.vector(rn, height, ang_n)
            self.roll_parts[e.name] = ((-1.0, svar, ang_u), (-1.0, height, ang_n))
            return [(ru, -1), (rn, -1)]
        name, pvar = fresh(f"R_{e.name}"), fresh(f"phi_{e.name}")
        drawn[pvar] = float(np.angle(z))
        if e.carried:  # the distance is fixed by the carrier: a free length, no redundancy
            length: float | str = fresh(f"L_{e.name}")
            drawn[length] = float(abs(z))
        else:
            length = float(abs(z))
        system.vector(name, length, pvar)
        self.roll_parts[e.name] = ((1.0, length, pvar),)
        return [(name, 1)]

    def new_crossing(self, e: _Edge) -> str:
        name = self.fresh(f"R_{e.name}")
        z = self.lk._xy(e.pb) - self.lk._xy(e.pa)
        if e.kind in ("P", "slot"):
            dvar = self.fresh(f"d_{e.name}")
            self.drawn[dvar] = float((z * e.direction.conjugate()).real)
            ang = self.angle_of(e.a, float(np.angle(e.direction)), f"dir_{e.name}")
            self.system.vector(name, dvar, ang)
            self.cross_vars[e.name] = (
                (dvar, ang, 0.0) if isinstance(ang, str) else (dvar, None, ang)
            )
        else:
            lvar, pvar = self.fresh(f"L_{e.name}"), self.fresh(f"phi_{e.name}")
            if abs(z) == 0:
                raise AssemblyError(f"actuator {e.name!r} has zero length in the drawing")
            self.drawn[lvar], self.drawn[pvar] = float(abs(z)), float(np.angle(z))
            self.system.vector(name, lvar, pvar)
            self.cross_vars[e.name] = (lvar, pvar, 0.0)
        return name

    def give_angle(self, n: str) -> None:
        """Give link ``n``'s rotation class an angle variable if it has none yet.

        The variable is the angle of a reference vector (named as a point), so that
        the core counts it as a variable of the loop system.
        """
        if self.find(n) != GROUND and self.find(n) not in self.class_var:
            ref = self.fresh(f"R_{n}_ref")
            self.system.vector(ref, 1.0, self.angle_of(n, _ref_angle(self.lk, n), "ref"))
            self.system.point(self.fresh(f"P_{n}_ref"), ref)

    # ------------------------------------------------------------------ the whole
    def compile(self) -> _Compiled:
        self.spanning_tree()
        on_loop: set[int] = set()
        for walk in self.cycles():
            on_loop.update(j for j, _, _ in walk)
            self.add_loop(walk)
        # A pin on no loop (an open chain: a lid, an arm) leaves the links beyond it free to
        # turn: each such link gets an angle variable of its own below, which a driver (or a
        # motor) must then fix. Any other joint must be on a loop.
        edges = self.edges
        hanging = {
            n for i, e in enumerate(edges) if i not in on_loop and e.kind == "R" for n in (e.a, e.b)
        } - self.base
        # a joint on no loop that is no pin (a wheel on the ground, a driven slider hanging
        # a block): its crossing vector places the link beyond it; its variables are fixed
        # by its own constraint (no slip) or a driver, which the core's count checks
        for i, e in enumerate(edges):
            if i not in on_loop and e.kind != "R":
                chain = " ".join(f"{'+' if s > 0 else '-'} {v}" for v, s in self.crossing(i))
                self.system.point(self.fresh(f"P_{e.name}"), chain.lstrip("+ "))
        for e in edges:
            if e.kind == "act" and e.name not in self.cross_vars:
                raise ModelError(f"actuator {e.name!r} is on no loop")
        # rolling: every link in contact needs an angle variable (a wheel turning on a
        # pivot may be in no loop), then the no-slip condition is a linear constraint
        for i, e in enumerate(edges):
            if e.kind != "roll":
                continue
            for n in (e.a, e.b):
                self.give_angle(n)
            self.crossing(i)
            text, consts = _no_slip(
                e, self.roll_parts[e.name], self.class_var, self.find, self.drawn
            )
            self.system.constraint(text, **consts)
        for n in self.group:
            if n in hanging:  # a link hanging on a pin outside the loops (an open chain)
                self.give_angle(n)
        motors = [m for m in self.lk._motors if m in self.drivers]
        for m in motors:
            for n in self.lk._motor_links(m):
                self.give_angle(n)
        rot_var, rot_offset = self.rotations()
        return self.finish(rot_var, rot_offset, motors)

    def add_loop(self, walk: list[tuple[int, str, str]]) -> None:
        terms: list[tuple[str, int]] = []
        for k, (j, f, t) in enumerate(walk):
            e = self.edges[j]
            terms += [(v, s if f == self.node(e.a) else -s) for v, s in self.crossing(j)]
            nj = walk[(k + 1) % len(walk)][0]
            terms += self.through(t, e, self.edges[nj])
        merged: dict[str, int] = {}
        for n, s in terms:
            merged[n] = merged.get(n, 0) + s
        text = " ".join(f"{'+' if s > 0 else '-'} {n}" for n, s in merged.items() if s)
        if text:
            self.system.loop(text[2:] if text.startswith("+ ") else "-" + text[1:])

    def rotations(self) -> tuple[dict[str, str | None], dict[str, float]]:
        """Each link's angle variable and offset (``theta = var + offset``)."""
        rot_var: dict[str, str | None] = {}
        rot_offset: dict[str, float] = {}
        undetermined = []
        for n in [GROUND, *(sorted(self.base - {GROUND})), *self.group]:
            root = self.find(n)
            ref = _ref_angle(self.lk, n)
            if root == GROUND:
                rot_var[n], rot_offset[n] = None, 0.0
            elif root in self.class_var:
                var, a0 = self.class_var[root]
                rot_var[n], rot_offset[n] = var, ref - a0
            elif n in self.group:
                undetermined.append(n)
        if undetermined:
            raise ModelError(
                f"the orientation of link(s) {', '.join(undetermined)} is not fixed by any loop "
                "(all their joints at one point?)"
            )
        return rot_var, rot_offset

    def finish(self, rot_var, rot_offset, motors: list[str]) -> _Compiled:
        lk = self.lk
        motor_vars = {}
        for mn in motors:
            a, b = lk._motor_links(mn)
            motor_vars[mn] = _motor_variable(self, mn, a, b, rot_var, rot_offset)
            self.drawn[motor_vars[mn]] = _ref_angle(lk, b) - _ref_angle(lk, a)
        driver_vars, driver_offsets = [], []
        for d in self.drivers:
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
                driver_vars.append(self.cross_vars[d][0])
                driver_offsets.append(0.0)
        if len(set(driver_vars)) != len(driver_vars):
            raise ModelError(f"drivers {', '.join(self.drivers)} drive the same variable")
        inputs = [*driver_vars, *self.rot_inputs, *(v for pair in self.vec_inputs for v in pair)]
        self.system.inputs(*inputs)
        self.system.check()
        return _Compiled(
            system=self.system,
            driver_vars=tuple(driver_vars),
            driver_offsets=tuple(driver_offsets),
            drawn=self.drawn,
            rot_var=rot_var,
            rot_offset=rot_offset,
            tree=tuple(self.tree),
            cross_vars=self.cross_vars,
            roll_parts=self.roll_parts,
            drivers=self.drivers,
            rot_inputs=self.rot_inputs,
            vec_inputs=self.vec_inputs,
        )


def compile_loops(
    lk: Linkage,
    edges: list[_Edge],
    group: list[str] | None = None,
    drivers: tuple[str, ...] | None = None,
    known: set[str] | None = None,
) -> _Compiled:
    """Compile ``lk`` — or the links ``group`` against the ``known`` ones — into vector loops."""
    return _LoopCompiler(lk, edges, group, drivers, known).compile()


def _motor_variable(
    c: _LoopCompiler,
    name: str,
    a: str,
    b: str,
    rot_var: dict[str, str | None],
    rot_offset: dict[str, float],
) -> str:
    """Add motor ``name``'s relative angle ``phi = theta_b − theta_a`` to the system.

    With ``theta = var + offset`` for each link's rotation class the constraint
    is ``phi − var_b + var_a = offset_b − offset_a`` (a link that only slides on
    the ground has a constant angle: its term is a constant). ``phi`` is the
    angle of a reference vector reaching a point of its own, so that the core
    counts it as a variable of the loop system.
    """
    lk = c.lk
    phi = c.fresh(f"phi_{name}")
    ref = c.fresh(f"R_{name}_ref")
    # its length, the mean link size, keeps the core's length scale (a mean) about as it was
    c.system.vector(ref, _typical_length(lk), phi)
    c.system.point(c.fresh(f"P_{name}_ref"), ref)
    terms, consts = [f"{phi}"], {"c_motor": 0.0}
    for link, sign in ((b, 1.0), (a, -1.0)):
        var = rot_var[link]
        theta0 = _ref_angle(lk, link) if var is None else rot_offset[link]
        consts["c_motor"] += sign * theta0
        if var is not None:
            terms.append(f"{'-' if sign > 0 else '+'} {var}")
    c.system.constraint(" ".join(terms) + " = c_motor", **consts)
    return phi


def _no_slip(
    e: _Edge,
    parts: tuple[tuple[float, float | str, float | str], ...],
    class_var: dict[str, tuple[str, float]],
    find: Any,
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
