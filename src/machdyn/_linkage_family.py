"""Many linkages of one topology at once: the closed-form family solver.

A drawn :class:`~machdyn.linkage.Linkage` fixes a topology (its links, pins,
driver and Assur groups, :attr:`Linkage.groups`); a *family* is many
linkages of that topology, each with its own dimensions, solved over the
same sweep of the driver: samples × poses in one set of NumPy array
operations (a sample's geometry is a column ``(N, 1)``, the sweep a row).

Each link's shape is the drawn offsets of its points from its first point
``F`` (the ground's are absolute). The dimensions, named as the builder names
points and links:

* ``"P.x"``, ``"P.y"``: the drawn coordinates of point ``P``, as in
  :func:`machdyn.sensitivity`: every link carrying ``P`` sees it move (a
  ground pivot moved also lengthens or shortens the links pinned there; the
  frame alone is toleranced by the ground's own ``"O2-O4"``, ``"O6.p"``, ...);
* ``"F-S"``: the distance between a link's first two points (its length;
  ``S`` moves along ``F → S``, the link's other points keep their offsets
  from ``F``), written ``"link:F-S"`` where two links share those points;
* ``"Q.p"``, ``"Q.delta"``: the polar coordinates of a link's further point
  ``Q`` (third and on) from ``F``, the angle from the line ``F → S`` — the
  notes' coupler-point parameters (``"link:Q.p"`` where ambiguous).

Each sample keeps the nominal drawing's assembly of every dyad (the sign of
``Im(conj(A₂ − A₁)(B − A₁))``), so no sample is read on another circuit;
where a dyad does not close the sample is flagged with the group's name.

* ``"guide.angle"``, ``"guide.offset"``: a straight ground slider's guide line
  (named as its joint, :meth:`Linkage.slider` ``name=``), turned about the
  drawn sliding point and shifted across itself (to the left of its
  direction); the line's point is the sliding point's ``"B.x"``, ``"B.y"``.

Groups solved: a crank (a link pinned to a known body, its angle driven), RRR
dyads and RRP dyads (a pin-pin link ending in a block on a straight ground
guide; the block turns with its guide) — the closed forms of
:mod:`machdyn.linkage.program` written over samples × poses, with the slide
displacement ``"length.<joint>"`` as an output. Other groups (slots, sliders
on moving links, actuators) are refused with an
:class:`~machdyn.errors.InputError` naming them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ._dual import Dual, expj
from .errors import InputError

__all__: list[str] = []

GROUND = "ground"


def _cross(a: Any, b: Any) -> Any:
    """``Im(conj(a) b)``."""
    return a.real * b.imag - a.imag * b.real


# The solver's arithmetic runs on arrays (samples × poses) or on duals (one linkage,
# derivatives along its drawn coordinates: machdyn.sensitivity's closed-form path).
def _expj(x: Any) -> Any:
    return expj(x) if isinstance(x, Dual) else np.exp(1j * x)


def _value(x: Any) -> Any:
    return x.v if isinstance(x, Dual) else x


def _sqrt0(x: Any) -> Any:
    """``√max(x, 0)``."""
    if isinstance(x, Dual):
        r = np.sqrt(np.maximum(x.v, 0.0))
        with np.errstate(divide="ignore", invalid="ignore"):
            return Dual(r, x.d / (2.0 * r[..., None]))
    return np.sqrt(np.maximum(x, 0.0))


def _abs(z: Any) -> Any:
    """``|z|`` (``d|z| = Re(conj(z) dz)/|z|``)."""
    if isinstance(z, Dual):
        r = np.abs(z.v)
        return Dual(r, (np.conj(z.v)[..., None] * z.d).real / r[..., None])
    return np.abs(z)


def _arg(z: Any) -> Any:
    """The angle of ``z`` (``d arg z = Im(dz / z)``)."""
    if isinstance(z, Dual):
        return Dual(np.angle(z.v), (z.d / z.v[..., None]).imag)
    return np.angle(z)


@dataclass(frozen=True)
class Dimension:
    """One dimension of a linkage family: a coordinate, a length or a polar parameter."""

    name: str
    kind: str  # "x" | "y" | "length" | "p" | "delta" | "angle" | "offset"
    link: str | None  # the link whose shape it changes (None: a drawn coordinate)
    point: str  # the point that moves


@dataclass
class Geometry:
    """The shapes of ``n`` linkages: per link, its points' offsets ``(n, 1)`` and drawn angle."""

    q: dict[str, dict[str, np.ndarray]]
    psi: dict[str, np.ndarray]
    bad: np.ndarray  # (n,) a length ≤ 0
    guides: dict[str, tuple[Any, Any]]  # per slider: a point of its line and its unit û


class State:
    """Poses (and rates) of every link of ``n`` linkages over ``m`` poses."""

    def __init__(self, geo: Geometry, order: int) -> None:
        self.geo, self.order = geo, order
        self.O: dict[str, Any] = {}
        self.E: dict[str, Any] = {}
        self.V: dict[str, Any] = {}
        self.w: dict[str, Any] = {}
        self.A: dict[str, Any] = {}
        self.al: dict[str, Any] = {}

    def pos(self, link: str, x: str) -> Any:
        """Position of point ``x`` of ``link``."""
        q = self.geo.q[link][x]
        return q if link == GROUND else self.O[link] + q * self.E[link]

    def vel(self, link: str, x: str) -> Any:
        """Velocity of point ``x`` of ``link``."""
        if link == GROUND:
            return 0.0
        return self.V[link] + 1j * self.w[link] * (self.geo.q[link][x] * self.E[link])

    def acc(self, link: str, x: str) -> Any:
        """Acceleration of point ``x`` of ``link``."""
        if link == GROUND:
            return 0.0
        w = self.w[link]
        return self.A[link] + (1j * self.al[link] - w * w) * (self.geo.q[link][x] * self.E[link])

    def place(self, link: str, x: str, P: list[Any], E: Any, w: Any, al: Any) -> None:
        """Set ``link`` from its point ``x`` at ``P`` (with rates), turned by ``E``."""
        qE = self.geo.q[link][x] * E
        self.E[link] = E
        self.O[link] = P[0] - qE
        if self.order >= 1:
            self.w[link] = w
            self.V[link] = P[1] - 1j * w * qE
        if self.order >= 2:
            self.al[link] = al
            self.A[link] = P[2] - (1j * al - w * w) * qE

    def direction(self, link: str) -> Any:
        """``e^{jθ}`` of the link's angle (of its first → second line)."""
        return _expj(self.geo.psi[link]) * self.E[link]


class Family:
    """A linkage's topology compiled for samples × poses (see the module's notes).

    Parameters
    ----------
    lk : Linkage
        The nominal linkage: one driver, groups of the kinds solved here.
    """

    def __init__(self, lk: Any) -> None:
        self.lk = lk
        if len(lk.drivers) != 1:
            raise InputError(
                "model", f"tolerance takes a linkage with one driver; this one has {lk.drivers}"
            )
        self.driver = lk.drivers[0]
        self.points = dict(lk.points)
        self.carriers = {GROUND: tuple(lk.ground_points)}
        self.carriers |= {n: tuple(ln.points) for n, ln in lk.links.items()}
        self.links = tuple(lk.links)
        self.mass = {n: (ln.mass, ln.inertia, ln.cg) for n, ln in lk.links.items()}
        self.sliders: dict[str, tuple[str, str, complex, str | None]] = {}
        self.steps, self.group_names = self._steps()
        self.dims = self._dimensions()
        self.names = tuple(d.name for d in self.dims)
        self.nominal = np.array([self._nominal(d) for d in self.dims])

    # ------------------------------------------------------------------ topology
    def _pin(self, joints: dict[str, Any], names: tuple[str, ...], link: str, known: set[str]):
        """The pin of ``link`` with a known body among the group's joints: (body, point)."""
        for name in names:
            j = joints.get(name)
            if j is None or j.kind != "pin" or link not in j.links:
                continue
            for other in j.links:
                if other != link and other in known:
                    return other, j.points[0]
        return None

    def _steps(self) -> tuple[list[tuple], list[str]]:
        joints = {j.name: j for j in self.lk.joints}
        known, steps, names = {GROUND}, [], []
        for g in self.lk.groups:
            step = None
            if g.kind == "driver":
                L = g.links[0]
                pin = self._pin(joints, g.joints, L, known)
                drive = g.joints[-1]
                if pin is not None and drive == L:
                    step = ("crank", L, *pin)
            elif g.kind == "RRR":
                L1, L2 = g.links
                p1 = self._pin(joints, g.joints, L1, known)
                p2 = self._pin(joints, g.joints, L2, known)
                mid = self._pin(joints, g.joints, L1, {L2})
                if p1 and p2 and mid:
                    A1, A2, B = (self.points[p] for p in (p1[1], p2[1], mid[1]))
                    sign = float(np.sign(_cross(A2 - A1, B - A1))) or float(g.sign)
                    if sign:
                        step = ("rrr", L1, *p1, L2, *p2, mid[1], sign)
            elif g.kind == "RRP":
                step = self._rrp_step(joints, g, known)
            if step is None:
                raise InputError(
                    "model",
                    f"tolerance of a Linkage: {g.name} is not solved in closed form by the "
                    "family solver (cranks, RRR dyads and RRP dyads on a ground guide are); "
                    "slots, sliders on moving links and actuators are not toleranced yet",
                )
            steps.append(step)
            names.append(g.name)
            known |= set(g.links)
        return steps, names

    def _rrp_step(self, joints: dict[str, Any], g: Any, known: set[str]) -> tuple | None:
        """An RRP dyad: a pin-pin link ``L1`` and a block ``L2`` on a straight ground guide."""
        slider = next((joints[n] for n in g.joints if joints[n].kind == "slider"), None)
        if slider is None or slider.links[1] != GROUND or slider.radius is not None:
            return None
        L2 = slider.links[0]
        L1 = next((x for x in g.links if x != L2), None)
        p1 = self._pin(joints, g.joints, L1, known) if L1 else None
        mid = self._pin(joints, g.joints, L1, {L2}) if L1 else None
        if not (p1 and mid):
            return None
        at, A, B = slider.points[0], self.points[p1[1]], self.points[mid[1]]
        u = complex(slider.direction)
        sign = float(np.sign(((B - A) * u.conjugate()).real)) or float(g.sign)
        if not sign:
            return None
        self.sliders[slider.name] = (L2, at, u, slider.through)
        return ("rrp", L1, *p1, L2, mid[1], slider.name, sign)

    def _dimensions(self) -> list[Dimension]:
        dims = [Dimension(f"{p}.{a}", a, None, p) for p in self.points for a in ("x", "y")]
        shape: list[Dimension] = []
        for link, pts in self.carriers.items():
            if len(pts) >= 2:
                shape.append(Dimension(f"{pts[0]}-{pts[1]}", "length", link, pts[1]))
            for q in pts[2:]:
                shape += [Dimension(f"{q}.{k}", k, link, q) for k in ("p", "delta")]
        for name, (_, at, _, _) in self.sliders.items():
            shape += [Dimension(f"{name}.{k}", k, None, at) for k in ("angle", "offset")]
        count: dict[str, int] = {}
        for d in shape:
            count[d.name] = count.get(d.name, 0) + 1
        for d in shape:
            name = d.name if count[d.name] == 1 else f"{d.link}:{d.name}"
            dims.append(Dimension(name, d.kind, d.link, d.point))
        return dims

    def _nominal(self, d: Dimension) -> float:
        z = self.points[d.point]
        if d.kind == "x":
            return z.real
        if d.kind == "y":
            return z.imag
        if d.kind == "angle":
            return float(np.angle(self.sliders[d.name.rsplit(".", 1)[0]][2]))
        if d.kind == "offset":
            return 0.0
        pts = self.carriers[d.link]
        off = z - self.points[pts[0]]
        if d.kind in ("length", "p"):
            return abs(off)
        return math.remainder(np.angle(off) - np.angle(self.points[pts[1]] - self.points[pts[0]]),
                              2 * math.pi)  # fmt: skip

    # ------------------------------------------------------------------ geometry
    def geometry(self, dims: np.ndarray) -> Geometry:
        """The shapes of the linkages whose dimensions are the rows of ``dims`` (n, D)."""
        dims = np.asarray(dims, dtype=float)
        dev = dims - self.nominal
        moved = np.flatnonzero(np.any(dev != 0.0, axis=0))
        return self._shapes(dims.shape[0], {int(i): dev[:, i : i + 1] for i in moved})

    def seeded(self, index: Any = None) -> Geometry:
        """The nominal shapes as duals along the dimensions ``index`` (default: ``P.x``, ``P.y``).

        Solving them gives every output's exact first derivatives with respect
        to those dimensions (forward differentiation through the closed forms).
        """
        index = range(2 * len(self.points)) if index is None else index
        index = [int(i) for i in index]
        cols = {}
        for k, i in enumerate(index):
            d = np.zeros((1, 1, len(index)))
            d[..., k] = 1.0
            cols[i] = Dual(np.zeros((1, 1)), d)
        return self._shapes(1, cols)

    def _shapes(self, n: int, cols: dict[int, Any]) -> Geometry:
        """Each link's offsets with the deviations ``cols`` (dimension → (n, 1) column or dual)."""
        P: dict[str, Any] = {p: np.full((n, 1), z) for p, z in self.points.items()}
        shape: dict[str, list[tuple[Dimension, Any]]] = {}
        line: dict[str, dict[str, Any]] = {}
        for i, col in cols.items():
            d = self.dims[i]
            if d.kind in ("angle", "offset"):
                line.setdefault(d.name.rsplit(".", 1)[0], {})[d.kind] = col
            elif d.kind == "x":
                P[d.point] = P[d.point] + col
            elif d.kind == "y":
                P[d.point] = P[d.point] + 1j * col
            else:
                shape.setdefault(d.link, []).append((d, col))
        bad = np.zeros(n, dtype=bool)
        q: dict[str, dict[str, Any]] = {}
        psi: dict[str, Any] = {}
        for link, pts in self.carriers.items():
            F = P[pts[0]] if pts else 0j
            off = {x: P[x] - F for x in pts}
            for d, col in shape.get(link, ()):
                z = off[d.point]
                if d.kind == "delta":
                    off[d.point] = z * _expj(col)
                else:
                    size = _abs(z)
                    new = size + col
                    bad |= _value(new)[:, 0] <= 0.0
                    with np.errstate(invalid="ignore", divide="ignore"):
                        off[d.point] = z * (new / size)
            if link == GROUND:
                q[link] = {x: F + v for x, v in off.items()}
                psi[link] = np.zeros((n, 1))
            else:
                q[link] = off
                psi[link] = _arg(off[pts[1]]) if len(pts) > 1 else np.zeros((n, 1))
        guides = {}
        for name, (_, at, u0, _) in self.sliders.items():
            dev = line.get(name, {})
            u = u0 * _expj(dev["angle"]) if "angle" in dev else np.full((n, 1), u0)
            Q = P[at] + 1j * u * dev["offset"] if "offset" in dev else P[at]
            guides[name] = (Q, u)
        return Geometry(q, psi, bad, guides)

    # ------------------------------------------------------------------ solving
    def solve(self, geo: Geometry, u: list[Any], order: int = 0) -> tuple[State, np.ndarray]:
        """Every link's pose over the sweep ``u = [values, rates, ...]`` (each (m,) or scalar).

        Returns the state and, per group, which linkages close at every pose
        ((groups, n) bool).
        """
        st = State(geo, order)
        n = geo.bad.size
        closes = np.ones((len(self.steps), n), dtype=bool)
        for g, step in enumerate(self.steps):
            kind = step[0]
            if kind == "crank":
                _, L, K, p = step
                E = np.exp(1j * np.asarray(u[0])) * _expj(-geo.psi[L])
                self._crank(st, L, K, p, E, u)
            elif kind == "rrp":
                closes[g] = self._rrp(st, step)
            else:
                closes[g] = self._rrr(st, step)
        return st, closes

    def _crank(self, st: State, L: str, K: str, p: str, E: Any, u: list[Any]) -> None:
        P = [st.pos(K, p)]
        if st.order >= 1:
            P.append(st.vel(K, p))
        if st.order >= 2:
            P.append(st.acc(K, p))
        st.place(L, p, P, E, u[1] if st.order >= 1 else None, u[2] if st.order >= 2 else None)

    def _rrr(self, st: State, step: tuple) -> np.ndarray:
        _, L1, K1, p1, L2, K2, p2, B, sign = step
        q1, q2 = st.geo.q[L1], st.geo.q[L2]
        A1, A2 = st.pos(K1, p1), st.pos(K2, p2)
        arm1, arm2 = q1[B] - q1[p1], q2[B] - q2[p2]
        a2, b2 = (arm1 * arm1.conj()).real, (arm2 * arm2.conj()).real
        d = A2 - A1
        d2 = d.real * d.real + d.imag * d.imag
        with np.errstate(invalid="ignore", divide="ignore"):
            x = (a2 - b2 + d2) / (2.0 * d2)  # along d, in units of |d|
            y2 = a2 / d2 - x * x
            closes = np.all(_value(y2) >= 0.0, axis=1) & np.all(_value(d2) > 0.0, axis=1)
            Bz = A1 + d * (x + 1j * sign * _sqrt0(y2))
            r1, r2 = Bz - A1, Bz - A2
            E1, E2 = r1 / arm1, r2 / arm2
            PB = [Bz]
            w1 = w2 = al1 = al2 = None
            if st.order >= 1:
                c1, c2 = 1j * r1, -1j * r2
                det = _cross(c2, c1)
                k = st.vel(K2, p2) - st.vel(K1, p1)
                w1, w2 = _cross(c2, k) / det, -_cross(c1, k) / det
                PB.append(st.vel(K1, p1) + 1j * w1 * r1)
            if st.order >= 2:
                k = st.acc(K2, p2) - st.acc(K1, p1) + w1 * w1 * r1 - w2 * w2 * r2
                al1, al2 = _cross(c2, k) / det, -_cross(c1, k) / det
                PB.append(st.acc(K1, p1) + (1j * al1 - w1 * w1) * r1)
        st.place(L1, B, PB, E1, w1, al1)
        st.place(L2, B, PB, E2, w2, al2)
        return closes

    def _rrp(self, st: State, step: tuple) -> np.ndarray:
        """Circle (``L1`` about ``A``) meets the guide's line ``Q + s û``; the block rides on it."""
        _, L1, K1, p1, L2, B, guide, sign = step
        Q, u = st.geo.guides[guide]
        q1 = st.geo.q[L1]
        A = st.pos(K1, p1)
        arm1 = q1[B] - q1[p1]
        a2 = (arm1 * arm1.conj()).real
        d = Q - A
        t0, c = (d * u.conj()).real, _cross(u, d)  # along and across the line
        h2 = a2 - c * c
        with np.errstate(invalid="ignore", divide="ignore"):
            closes = np.all(_value(h2) >= 0.0, axis=1)
            r1 = (c * 1j + sign * _sqrt0(h2)) * u  # B − A
            Bz = A + r1
            E1 = r1 / arm1
            E2 = u / self.sliders[guide][2]  # the block turns with its (toleranced) guide
            PB, w1, al1 = [Bz], None, None
            zero = 0.0 * _value(t0)
            if st.order >= 1:
                c2 = -1j * r1  # v_B = ṡ û = v_A + j ω1 r1
                det = _cross(u, c2)
                k = st.vel(K1, p1)
                w1 = _cross(u, k) / det
                PB.append(k + 1j * w1 * r1)
            if st.order >= 2:
                k = st.acc(K1, p1) - w1 * w1 * r1
                al1 = _cross(u, k) / det
                PB.append(st.acc(K1, p1) + (1j * al1 - w1 * w1) * r1)
        st.place(L1, B, PB, E1, w1, al1)
        st.place(L2, B, PB, E2, zero, zero)
        return closes

    # ------------------------------------------------------------------ outputs
    def output_names(self) -> tuple[str, ...]:
        """Every output: link angles, moving points, and the driver's torque."""
        moving = [p for p in self.points if p not in self.carriers[GROUND]]
        return (
            tuple(f"theta.{n}" for n in self.links)
            + tuple(f"point.{p}" for p in moving)
            + tuple(f"length.{s}" for s in self.sliders)
            + (f"torque.{self.driver}",)
        )

    def owner(self, point: str) -> str:
        """A moving link carrying ``point``."""
        return next(n for n in self.links if point in self.carriers[n])

    def value(self, st: State, name: str, gravity: float = 0.0, speed: Any = 1.0) -> Any:
        """An output's value: ``e^{jθ}`` of a link angle, a point, or the driver's torque."""
        kind, what = name.split(".", 1)
        if kind == "theta":
            return st.direction(what)
        if kind == "point":
            return st.pos(self.owner(what), what)
        if kind == "length":
            return self.slide(st, what)
        return self.torque(st, gravity, speed)

    def slide(self, st: State, name: str) -> Any:
        """The slider's displacement along its guide from the foot of its reference point."""
        block, at, _, through = self.sliders[name]
        u = st.geo.guides[name][1]
        ref = through if through is not None else self.carriers[GROUND][0]
        return ((st.pos(block, at) - st.pos(GROUND, ref)) * u.conj()).real

    def torque(self, st: State, gravity: float, speed: Any) -> Any:
        """The driver's torque by the power balance ``T u̇ = Σ m (a_G + j g)·v_G + I α ω``."""
        power = 0.0
        for link, (m, inertia, cg) in self.mass.items():
            q = st.geo.q[link]
            if cg is None:
                g = q[self.carriers[link][0]]
            elif isinstance(cg, str):
                g = q[cg]
            else:
                g = complex(cg) * _expj(st.geo.psi[link])
            w, E = st.w[link], st.E[link]
            if m:
                gE = g * E
                vG = st.V[link] + 1j * w * gE
                aG = st.A[link] + (1j * st.al[link] - w * w) * gE + 1j * gravity
                power = power + m * (aG.real * vG.real + aG.imag * vG.imag)
            if inertia:
                power = power + inertia * st.al[link] * w
        return power / speed
