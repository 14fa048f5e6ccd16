"""The link graph of a drawn linkage and its compilation into vector loops.

Links are the nodes and joints the edges (:class:`_Edge`); a spanning tree grown
from the ground gives one independent loop per remaining joint, and
:func:`compile_loops` writes those loops, the constant-angle constraints,
rolling and motor constraints into a :class:`~machdyn.loops.LoopSystem`.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from ..errors import AssemblyError, ModelError
from ..loops import LoopSystem
from ._common import GROUND, _ref_angle, _typical_length

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


class _Model:
    """A validated linkage: its joints, Assur groups, closed-form program, and loops on demand."""

    def __init__(self, lk: Linkage, edges: list[_Edge], groups: tuple, program) -> None:
        self.lk = lk
        self.edges = edges
        self.groups = groups
        self.program = program  # None when a group needs the vector-loop core
        self._loops: _Compiled | None = None
        self.cache: dict[str, object] = {}

    def loops(self) -> _Compiled:
        """The whole linkage compiled into vector loops (built at the first call)."""
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


def _ident(text: str) -> str:
    """A loop-variable name made of ``text`` (non-word characters become ``_``)."""
    return _IDENT.sub("_", text)


def compile_loops(lk: Linkage, edges: list[_Edge]) -> _Compiled:
    """Compile ``lk`` (its joints ``edges``) into vector loops, the way the notes teach."""
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
            if e.kind == "roll":
                cross_vec[i] = roll_crossing(e)
            elif e.kind in ("arc", "arcP"):
                cross_vec[i] = arc_crossing(e)
            else:
                cross_vec[i] = [(new_crossing(e), 1)]
        return cross_vec[i]

    def arc_crossing(e: _Edge) -> list[tuple[str, int]]:
        """Centre of curvature → pin: ``R e^{jψ}``, the effective link of a curved joint.

        In a curved slot ψ is free (the pin turns in the slot); a curved slider's
        block turns with the radius, so ψ is an angle of the block.
        """
        z = lk._xy(e.pb) - lk._xy(e.pa)
        name = fresh(f"R_{e.name}")
        if e.kind == "arcP":
            ang: float | str = angle_of(e.b, float(np.angle(z)), f"arc_{e.name}")
        else:
            ang = fresh(f"psi_{e.name}")
            drawn[ang] = float(np.angle(z))
        system.vector(name, e.radii[0], ang)
        roll_parts[e.name] = ((1.0, e.radii[0], ang),)
        return [(name, 1)]

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
