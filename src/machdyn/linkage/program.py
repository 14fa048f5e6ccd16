"""The solving program of a linkage: one step per Assur group, run over every sample at once.

:func:`machdyn.linkage.groups.decompose` turns a drawn linkage into a list of
steps in solving order — a driver (crank, motor, driven slider), a closed-form
dyad — each of which finds the pose of its links from bodies already known.
This module runs them (NumPy, every sample at once); the compiled kernel in
:mod:`machdyn._linkage_kernels` runs the same steps over blocks of samples.

The pose of link ``i`` is its frame origin ``O`` (the drawn position of its
first point, moved) and its rotation ``E = e^{jΔ}`` since the drawing; a point
drawn at ``P⁰`` on it is ``O + (P⁰ − O⁰) E``. Rates: ``V, ω`` (order 1),
``a, α`` (order 2), ``jerk, ζ`` (order 3); a point at ``q = (P⁰ − O⁰) E`` from
``O`` moves with ``V + jω q``, ``a + (jα − ω²) q``, ``jerk + (jζ − 3ωα − jω³) q``
(DESIGN.md's rules for ``d e^{jθ}`` with constant ``d``). Every derivative order
of a dyad is the 2 × 2 linear system of its position Jacobian
(:func:`~machdyn.linkage.dyads.solve_pair`) with a known right-hand side.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..loops.result import blank
from .dyads import _line_line, _pair, _rpr, _rrp, _rrr, cross

#: Status codes of a group at a sample.
OK, NO_ASSEMBLY, SINGULAR, DEPENDS = 0, 1, 2, 3
#: A general group solved alone (no continuation) that Newton put on another branch.
OFF_BRANCH = (
    "cannot assemble on the drawn branch: solved alone from the drawn pose, the loop core "
    "found a pose with the other sign of a group's determinant"
)
#: A dyad whose Jacobian columns make a sine below this is at a toggle (as the
#: loop solver's rcond threshold, machdyn.loops.solve.SINGULAR_RCOND).
SINGULAR_SINE = 1e-4

Ref = tuple[int, complex]  # a material point: (link index, drawn offset from the link origin)


class State:
    """Poses and rates of every link over ``n`` samples (index 0 is the ground)."""

    def __init__(self, n_links: int, n: int, order: int) -> None:
        self.n, self.order = n, order
        zero_c = np.zeros(n, complex)
        self.O: list[Any] = [zero_c] * n_links
        self.E: list[Any] = [np.ones(n, complex)] * n_links
        self.ang: list[Any] = [np.zeros(n)] * n_links
        self.lin: list[list[Any]] = [[zero_c] * n_links for _ in range(order + 1)]
        self.rot: list[list[Any]] = [[np.zeros(n)] * n_links for _ in range(order + 1)]
        self.follow = False
        self.reasons: dict[int, np.ndarray] = {}
        # per general group (its step's id): where its core starts at each sample
        # (its unknowns; None: the drawn pose) and where it ended (NaN: not solved)
        self.guess: dict[int, dict[str, np.ndarray]] = {}
        self.solved: dict[int, dict[str, np.ndarray]] = {}

    def pos(self, ref: Ref) -> Any:
        """Position of a material point."""
        i, r = ref
        return r + 0j if i == 0 else self.O[i] + r * self.E[i]

    def rates(self, ref: Ref) -> list[Any]:
        """``[P, P', P'', P''']`` of a material point, up to the state's order."""
        i, r = ref
        if i == 0:
            return [r + 0j] + [0j] * self.order
        q = r * self.E[i]
        return [
            self.O[i] + q,
            *self.transfer(i, q, [self.lin[k][i] for k in range(1, self.order + 1)]),
        ]

    def transfer(self, i: int, q: Any, base: list[Any]) -> list[Any]:
        """Rates of the point ``q`` away from a point of link ``i`` whose rates are ``base``."""
        out = []
        rot = self.rot
        if self.order >= 1:
            w = rot[1][i]
            out.append(base[0] + 1j * w * q)
        if self.order >= 2:
            al = rot[2][i]
            out.append(base[1] + (1j * al - w * w) * q)
        if self.order >= 3:
            z = rot[3][i]
            out.append(base[2] + (1j * z - 3.0 * w * al - 1j * w * w * w) * q)
        return out

    def place(self, i: int, P: list[Any], r: complex, E: Any, ang: Any, rot: list[Any]) -> None:
        """Set link ``i`` from one of its points: at ``P`` (with rates), drawn ``r`` from ``O``."""
        self.E[i], self.ang[i] = E, ang
        for k in range(1, self.order + 1):
            self.rot[k][i] = rot[k - 1]
        q = -r * E
        self.O[i] = P[0] + q
        for k, v in enumerate(self.transfer(i, q, P[1:]), start=1):
            self.lin[k][i] = v


def _p_term(k: int, s: list[Any], u: Any, w: list[Any]) -> Any:
    """Order-``k`` rate of ``s û`` without its ``s⁽ᵏ⁾ û`` part (``û`` turning with ``w``).

    ``s`` holds ``s`` and its rates so far, ``w`` the rates ``ω, α, ζ`` of ``û``.
    """
    if k == 1:
        return 1j * s[0] * w[0] * u
    om, al = w[0], w[1]
    if k == 2:
        return (2j * s[1] * om + s[0] * (1j * al - om * om)) * u
    return (
        3j * s[2] * om
        + 3.0 * s[1] * (1j * al - om * om)
        + s[0] * (1j * w[2] - 3.0 * om * al - 1j * om * om * om)
    ) * u


def _r_term(k: int, L: list[Any], e: Any, w: list[Any]) -> Any:
    """Order-``k`` rate of ``L ê`` without its ``j L φ⁽ᵏ⁾ ê`` part (``ê`` turning with ``w``).

    ``L`` holds the length and its three rates, ``w`` the angle's rates so far.
    """
    if k == 1:
        return L[1] * e
    om = w[0]
    if k == 2:
        return (L[2] - L[0] * om * om + 2j * L[1] * om) * e
    al = w[1]
    return (
        L[3]
        - 3.0 * L[1] * om * om
        - 3.0 * L[0] * om * al
        + 1j * (3.0 * L[2] * om + 3.0 * L[1] * al - L[0] * om * om * om)
    ) * e


def _sine(c1: Any, c2: Any) -> Any:
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.abs(cross(c1, c2)) / (np.abs(c1) * np.abs(c2))


def _status(ok: Any, sine: Any) -> Any:
    code = np.where(ok, OK, NO_ASSEMBLY).astype(np.int8)
    return np.where(ok & ~(sine >= SINGULAR_SINE), SINGULAR, code).astype(np.int8)


# ---------------------------------------------------------------------- drivers
@dataclass(frozen=True)
class Crank:
    """Link ``link`` pinned at ``pin`` (a point of a known link), its angle driven."""

    link: int
    pin: Ref
    r: complex  # the pin's drawn offset on ``link``
    driver: int
    theta0: float  # drawn angle of the link (the driver's value at the drawing)

    def run(self, st: State, u: list[Any]) -> Any:
        """Place the step's links at every sample; the status codes (None: always OK)."""
        d = u[self.driver][0] - self.theta0
        E = np.exp(1j * d)
        st.place(self.link, st.rates(self.pin), self.r, E, d, u[self.driver][1:])
        return None


@dataclass(frozen=True)
class Motor:
    """Link ``link`` pinned at ``pin``; its angle is a known link's plus a driven motor angle."""

    link: int
    pin: Ref
    r: complex
    source: int  # the known link the motor turns it against
    sign: float  # +1: link is the motor's link b (theta_b = theta_a + phi)
    driver: int
    phi0: float

    def run(self, st: State, u: list[Any]) -> Any:
        """Place the step's links at every sample; the status codes (None: always OK)."""
        d = self.sign * (u[self.driver][0] - self.phi0)
        E = st.E[self.source] * np.exp(1j * d)
        rot = [
            st.rot[k][self.source] + self.sign * u[self.driver][k] for k in range(1, st.order + 1)
        ]
        st.place(self.link, st.rates(self.pin), self.r, E, st.ang[self.source] + d, rot)
        return None


@dataclass(frozen=True)
class Slide:
    """Link ``link`` on a prismatic joint with a known link, its displacement driven.

    The line runs through ``foot`` (on the guide) along ``u0``; the block
    carries ``at = foot + d û``. ``link`` is the block (``moving_block``) or the guide.
    """

    link: int
    known: int
    foot: Ref  # on the guide
    at: Ref  # on the block
    u0: complex
    driver: int
    moving_block: bool

    def run(self, st: State, u: list[Any]) -> Any:
        """Place the step's links at every sample; the status codes (None: always OK)."""
        K = self.known
        E, ang = st.E[K], st.ang[K]
        uhat = self.u0 * E
        w = [st.rot[k][K] for k in range(1, st.order + 1)]
        d = u[self.driver]
        sign = 1.0 if self.moving_block else -1.0
        base = st.rates(self.foot if self.moving_block else self.at)
        P = [base[0] + sign * d[0] * uhat]
        for k in range(1, st.order + 1):
            P.append(base[k] + sign * (_p_term(k, d, uhat, w) + d[k] * uhat))
        r = self.at[1] if self.moving_block else self.foot[1]
        st.place(self.link, P, r, E, ang, w)
        return None


# ---------------------------------------------------------------------- dyads
@dataclass(frozen=True)
class RArm:
    """A link turning about a known pivot ``centre`` to the dyad's pin ``B``.

    ``link`` is -1 for a virtual link (an actuator's bar, of driven length).
    """

    centre: Ref
    link: int
    r: complex  # B's drawn offset on ``link``
    u0: complex  # drawn B - centre
    length: float
    driver: int = -1  # the length is this driver's value (an actuator)


@dataclass(frozen=True)
class PArm:
    """A link sliding along a line fixed in the known link ``known`` (through ``G``, along ``u0``).

    ``G`` is the known link's material point at the drawn ``B`` (so ``s = 0`` there);
    ``link`` is -1 for a virtual block (the pin of a slot).
    """

    known: int
    G: Ref
    u0: complex
    link: int
    r: complex


def _arm_length(arm: RArm, u: list[Any], n: int) -> list[Any]:
    if arm.driver < 0:
        return [arm.length, 0.0, 0.0, 0.0]
    return u[arm.driver]


@dataclass(frozen=True)
class Dyad:
    """Two arms (RR, RP, PR, PP) meeting at the pin ``B``: RRR, RRP, PRR, PRP."""

    arm1: RArm | PArm
    arm2: RArm | PArm
    sign: float

    def run(self, st: State, u: list[Any]) -> Any:
        """Place the step's links at every sample; the status codes (None: always OK)."""
        arms = (self.arm1, self.arm2)
        base = [st.rates(a.centre if isinstance(a, RArm) else a.G) for a in arms]
        L = [_arm_length(a, u, st.n) if isinstance(a, RArm) else None for a in arms]
        uhat = [None if isinstance(a, RArm) else a.u0 * st.E[a.known] for a in arms]
        r1, r2 = isinstance(arms[0], RArm), isinstance(arms[1], RArm)
        if r1 and r2:
            B, _, ok = _rrr(base[0][0], base[1][0], L[0][0], L[1][0], self.sign)
        elif r1:
            B, _, ok = _rrp(base[0][0], L[0][0], base[1][0], uhat[1], self.sign)
        elif r2:
            B, _, ok = _rrp(base[1][0], L[1][0], base[0][0], uhat[0], self.sign)
        else:
            B, _, _, ok = _line_line(base[0][0], uhat[0], base[1][0], uhat[1])
        # per arm: its unknown's coefficient and the values of the unknown and its rates
        coef, x, e = [], [], []
        for a, b0, uh in zip(arms, base, uhat, strict=True):
            if isinstance(a, RArm):
                vec = B - b0[0]
                coef.append(1j * vec)
                with np.errstate(invalid="ignore"):  # NaN where the dyad does not close
                    e.append(vec / np.abs(vec) if a.driver >= 0 else vec / a.length)
                x.append([])
            else:
                coef.append(uh)
                e.append(None)
                x.append([((B - b0[0]) * np.conj(uh)).real])
        status = _status(ok, _sine(coef[0], coef[1]))
        Bk = [B]
        for k in range(1, st.order + 1):
            known = []
            for i, a in enumerate(arms):
                if isinstance(a, RArm):
                    known.append(base[i][k] + _r_term(k, L[i], e[i], x[i]))
                else:
                    w = [st.rot[j][a.known] for j in range(1, st.order + 1)]
                    known.append(base[i][k] + _p_term(k, x[i], uhat[i], w))
            x1, x2, _ = _pair(coef[0], -coef[1], known[1] - known[0])
            x[0].append(x1)
            x[1].append(x2)
            Bk.append(known[0] + coef[0] * x1)
        for i, a in enumerate(arms):
            if a.link < 0:
                continue
            if isinstance(a, RArm):
                E = (B - base[i][0]) / a.u0
                st.place(a.link, Bk, a.r, E, np.angle(E), x[i])
            else:
                K = a.known
                rot = [st.rot[j][K] for j in range(1, st.order + 1)]
                st.place(a.link, Bk, a.r, st.E[K], st.ang[K], rot)
        return status


@dataclass(frozen=True)
class RPR:
    """Two links pivoted at known ``A`` and ``C``, sliding on each other (a line through ``C``).

    The line, fixed in ``link1``, passes at the signed offset ``e`` from ``A``
    along ``u0`` in the drawing; ``link2`` (or a virtual block, -1) carries ``C``.
    """

    link1: int
    A: Ref
    r1: complex  # A's drawn offset on link1
    C: Ref
    link2: int
    r2: complex  # C's drawn offset on link2
    e: float
    u0: complex
    sign: float

    def run(self, st: State, u: list[Any]) -> Any:
        """Place the step's links at every sample; the status codes (None: always OK)."""
        A, C = st.rates(self.A), st.rates(self.C)
        uh, t, ok = _rpr(A[0], C[0], self.e, self.sign)
        w = C[0] - A[0]
        c1, c2 = 1j * w, uh
        status = _status(ok, _sine(c1, c2))
        om: list[Any] = []
        tt = [t]
        for k in range(1, st.order + 1):
            rhs = C[k] - A[k]
            if k == 2:
                rhs = rhs - 2j * tt[1] * om[0] * uh + om[0] * om[0] * w
            elif k == 3:
                o, a = om
                rhs = (
                    rhs
                    - (3j * tt[2] * o + 3j * tt[1] * a - 3.0 * tt[1] * o * o) * uh
                    + (3.0 * o * a + 1j * o * o * o) * w
                )
            x1, x2, _ = _pair(c1, c2, rhs)
            om.append(x1)
            tt.append(x2)
        E = uh / self.u0
        ang = np.angle(E)
        st.place(self.link1, A, self.r1, E, ang, om)
        if self.link2 >= 0:
            st.place(self.link2, C, self.r2, E, ang, om)
        return status


@dataclass(frozen=True)
class RPP:
    """Link ``link1`` pivoted at known ``A`` slides on ``link2``, which slides on ``known``.

    Both turn with ``known``: ``A = G + s2 û2 + s1 û1`` with ``G`` the known
    link's material point at the drawn ``A`` (PPR is the same read backwards;
    ``link1`` is -1 for a virtual block: a point of a known link in a slot).
    """

    link1: int
    A: Ref
    r1: complex
    known: int
    G: Ref
    u1: complex  # link1 on link2
    u2: complex  # link2 on known
    link2: int
    r2: complex  # the drawn A's offset on link2

    def run(self, st: State, u: list[Any]) -> Any:
        """Place the step's links at every sample; the status codes (None: always OK)."""
        K = self.known
        E, ang = st.E[K], st.ang[K]
        w = [st.rot[k][K] for k in range(1, st.order + 1)]
        A, G = st.rates(self.A), st.rates(self.G)
        u1, u2 = self.u1 * E, self.u2 * E
        s1, s2, ok = _pair(u1, u2, A[0] - G[0])
        status = _status(ok, _sine(u1, u2))
        s1, s2 = [s1], [s2]
        X = [G[0] + s2[0] * u2]
        for k in range(1, st.order + 1):
            p2 = _p_term(k, s2, u2, w)
            rhs = A[k] - G[k] - _p_term(k, s1, u1, w) - p2
            x1, x2, _ = _pair(u1, u2, rhs)
            s1.append(x1)
            s2.append(x2)
            X.append(G[k] + p2 + x2 * u2)
        rot = w[: st.order]
        st.place(self.link2, X, self.r2, E, ang, rot)
        if self.link1 >= 0:
            st.place(self.link1, A, self.r1, E, ang, rot)
        return status


# ---------------------------------------------------------------------- general groups
def _vector_rates(d: list[Any], phi: list[Any], order: int) -> list[Any]:
    """``d e^{jφ}`` and its rates to ``order`` (DESIGN.md's rules, and the jerk)."""
    e = np.exp(1j * phi[0])
    out = [d[0] * e]
    if order >= 1:
        w1 = phi[1]
        out.append((d[1] + 1j * d[0] * w1) * e)
    if order >= 2:
        w2 = phi[2]
        out.append((d[2] - d[0] * w1 * w1 + 1j * (d[0] * w2 + 2.0 * d[1] * w1)) * e)
    if order >= 3:
        w3 = phi[3]
        re = d[3] - 3.0 * d[1] * w1 * w1 - 3.0 * d[0] * w1 * w2
        im = 3.0 * d[2] * w1 + 3.0 * d[1] * w2 + d[0] * w3 - d[0] * w1 * w1 * w1
        out.append((re + 1j * im) * e)
    return out


def _vector_of_points(P: list[Any], Q: list[Any], order: int) -> tuple[list[Any], list[Any]]:
    """Length and angle of ``Q − P`` and their rates (the angle within π of the drawn one)."""
    r = [Q[k] - P[k] for k in range(order + 1)]
    L = np.abs(r[0])
    with np.errstate(invalid="ignore"):  # NaN where an earlier group did not close
        e = r[0] / L
    lr, ar = [L], [np.angle(r[0])]
    c = [r[k] * np.conj(e) for k in range(order + 1)]
    if order >= 1:
        lr.append(c[1].real)
        ar.append(c[1].imag / L)
    if order >= 2:
        lr.append(c[2].real + L * ar[1] ** 2)
        ar.append((c[2].imag - 2.0 * lr[1] * ar[1]) / L)
    if order >= 3:
        w1, w2 = ar[1], ar[2]
        lr.append(c[3].real + 3.0 * lr[1] * w1 * w1 + 3.0 * L * w1 * w2)
        ar.append((c[3].imag - 3.0 * lr[2] * w1 - 3.0 * lr[1] * w2 + L * w1**3) / L)
    return lr, ar


def unwrap(a: np.ndarray) -> np.ndarray:
    """Continuous angles along a path: every step wrapped to (−π, π], gaps skipped."""
    ok = np.isfinite(a)
    if ok.all():
        d = np.diff(a)
        if a.size < 2 or np.abs(d).max() <= np.pi:  # no step wraps: nothing to do
            return a
        return np.concatenate((a[:1], a[0] + np.cumsum((d + np.pi) % (2 * np.pi) - np.pi)))
    out = np.full_like(a, np.nan)
    idx = np.flatnonzero(ok)
    if idx.size:
        v = a[idx]
        d = (np.diff(v) + np.pi) % (2 * np.pi) - np.pi
        out[idx] = np.concatenate((v[:1], v[0] + np.cumsum(d)))
    return out


class General:
    """A group the closed forms do not cover, solved by the vector-loop core.

    Its loop system (:func:`~machdyn.linkage.loopcompile.compile_loops` of the
    group) takes the poses of the links already known as inputs; the drawn
    pose is the guess, and a sweep is followed by continuation.
    """

    def __init__(self, lk: Any, compiled: Any, group: tuple[str, ...], drivers: tuple[int, ...]):
        self.c = compiled
        self.drivers = drivers
        self.index = {"ground": 0, **{n: i + 1 for i, n in enumerate(lk._links)}}
        self.origin = {"ground": 0j, **{n: lk._points[ln.points[0]] for n, ln in lk._links.items()}}
        self.xy = lk._xy
        self.group = group
        from ._common import _ref_angle

        self.theta0 = {n: _ref_angle(lk, n) for n in group}
        inputs = set(compiled.system._inputs)
        self.unknowns = [v for v in compiled.drawn if v not in inputs]

    def ref(self, link: str, key: str) -> Ref:
        """The material point ``key`` of ``link``."""
        return self.index[link], self.xy(key) - self.origin[link]

    def inputs(self, st: State, u: list[Any]) -> list[dict[str, Any]]:
        """Values and rates of every input of the group's loop system."""
        c, order = self.c, st.order
        table: list[dict[str, Any]] = [{} for _ in range(order + 1)]
        for var, off, d in zip(c.driver_vars, c.driver_offsets, self.drivers, strict=True):
            table[0][var] = u[d][0] - off
            for k in range(1, order + 1):
                table[k][var] = u[d][k]
        for var, (link, a0) in c.rot_inputs.items():
            i = self.index[link]
            table[0][var] = a0 + st.ang[i]
            for k in range(1, order + 1):
                table[k][var] = st.rot[k][i]
        for (lv, av), (a, b) in c.vec_inputs.items():
            lr, ar = _vector_of_points(st.rates(self.ref(*a)), st.rates(self.ref(*b)), order)
            phi0 = c.drawn[av]
            ar[0] = phi0 + (ar[0] - phi0 + np.pi) % (2 * np.pi) - np.pi
            if st.follow:
                ar[0] = unwrap(ar[0])
            for k in range(order + 1):
                table[k][lv], table[k][av] = lr[k], ar[k]
        return table

    def run(self, st: State, u: list[Any]) -> Any:
        """Solve the group's loops at every sample; place its links."""
        from ..loops.solve import REASONS
        from ..loops.solve import SINGULAR as LOOP_SINGULAR

        c, n, order = self.c, st.n, st.order
        table = self.inputs(st, u)
        good = np.ones(n, bool)
        for v in table[0].values():
            good &= np.isfinite(np.broadcast_to(v, (n,)))
        for t in table[1:]:
            for v in t.values():
                good &= np.isfinite(np.broadcast_to(v, (n,)))
        sub = np.flatnonzero(good)
        values: dict[str, np.ndarray] = {}
        code = np.full(n, NO_ASSEMBLY, np.int8)
        reason = blank(n)
        if sub.size:

            def pick(t: dict[str, Any]) -> dict[str, np.ndarray]:
                return {k: np.broadcast_to(v, (n,))[sub] for k, v in t.items()}

            kw: dict[str, Any] = {"continuation": st.follow and sub.size > 1}
            if order:
                kw.update(velocity=pick(table[1]), order=order)
                kw["acceleration"] = pick(table[2]) if order >= 2 else None
                kw["jerk"] = pick(table[3]) if order >= 3 else None
            start = st.guess.get(id(self))
            guess = {v: c.drawn[v] for v in self.unknowns} if start is None else pick(start)
            m = c.system.solve(pick(table[0]), guess, **kw)
            states = [m.positions, m.velocity, m.acceleration, m.jerk][: order + 1]
            for k, state in enumerate(states):
                for var, arr in state.items():
                    full = np.full(n, np.nan)
                    full[sub] = arr
                    values[f"{k}:{var}"] = full
            sub_code = np.where(m.ok, OK, NO_ASSEMBLY).astype(np.int8)
            own = m.reason.reshape(-1)
            if start is not None or not kw["continuation"]:
                # each sample solved alone keeps no branch: it is checked against the drawing's
                signs = m.group_branch.reshape(len(m.groups), -1)
                off = m.ok.reshape(-1) & (signs != self.branch()[:, None]).any(axis=0)
                sub_code[off] = NO_ASSEMBLY
                own = np.where(off, OFF_BRANCH, own)
            sub_code[own == REASONS[LOOP_SINGULAR]] = SINGULAR
            code[sub] = sub_code
            reason[sub] = own
        st.solved[id(self)] = {v: values.get(f"0:{v}", np.full(n, np.nan)) for v in self.unknowns}
        self.place(st, values)
        st.reasons[id(self)] = reason
        return code

    def compiled(self) -> bool:
        """Whether the compiled kernels follow this group's sweeps now (:mod:`machdyn.jit`)."""
        from .. import jit
        from ..loops._jit_sweep import sweepable

        system = self.c.system
        return jit.active() and sweepable(system._checked(system._inputs))

    def branch(self) -> np.ndarray:
        """The drawn branch: the sign of each of the core's groups' determinants in the drawing."""
        if not hasattr(self, "_branch"):
            m = self.c.system.evaluate({v: np.array([x]) for v, x in self.c.drawn.items()})
            self._branch = m.group_branch.reshape(-1)
        return self._branch

    def var(self, values: dict[str, np.ndarray], k: int, name: Any, n: int) -> Any:
        """Order-``k`` value of a loop variable (or of a constant)."""
        if isinstance(name, str):
            return values.get(f"{k}:{name}", np.full(n, np.nan))
        return name if k == 0 else 0.0

    def place(self, st: State, values: dict[str, np.ndarray]) -> None:
        """Place the group's links along its spanning tree from the known bodies."""
        c, n, order = self.c, st.n, st.order
        ks = range(order + 1)
        rot: dict[str, list[Any]] = {}
        for link in self.group:
            v = c.rot_var[link]
            if v is None:
                rot[link] = [np.zeros(n)] * (order + 1)
            else:
                rot[link] = [self.var(values, k, v, n) for k in ks]
                rot[link][0] = rot[link][0] + c.rot_offset[link] - self.theta0[link]
        cross: dict[str, list[Any]] = {}
        for name, (lv, av, fixed) in c.cross_vars.items():
            d = [self.var(values, k, lv, n) for k in ks]
            phi = [self.var(values, k, av if av is not None else fixed, n) for k in ks]
            cross[name] = _vector_rates(d, phi, order)
        for name, parts in c.roll_parts.items():
            total = [0j] * (order + 1)
            for sign, length, ang in parts:
                d = [self.var(values, k, length, n) for k in ks]
                phi = [self.var(values, k, ang, n) for k in ks]
                part = _vector_rates(d, phi, order)
                total = [t + sign * p for t, p in zip(total, part, strict=True)]
            cross[name] = total
        for child, e, child_is_b in c.tree:
            par, p_key, c_key = (e.a, e.pa, e.pb) if child_is_b else (e.b, e.pb, e.pa)
            P = st.rates(self.ref(par, p_key))
            if e.kind != "R":
                s = 1.0 if child_is_b else -1.0
                P = [P[k] + s * cross[e.name][k] for k in ks]
            delta = rot[child][0]
            st.place(
                self.index[child],
                P,
                self.xy(c_key) - self.origin[child],
                np.exp(1j * delta),
                delta,
                rot[child][1:],
            )


Step = Crank | Motor | Slide | Dyad | RPR | RPP | General


@dataclass
class Program:
    """The steps of a linkage in solving order, and what each group depends on."""

    n_links: int
    steps: list[Any]
    group_of_step: list[int]  # the group each step solves
    deps: list[tuple[int, ...]]  # per group: the groups whose links it uses
    links: list[tuple[int, ...]]  # per group: the links it places
    unwrap: frozenset[int] = frozenset()  # links whose angle comes from atan2

    @property
    def encoded(self) -> Any:
        """The steps as rows for the kernel (:func:`machdyn.linkage.kernel.encode`), or None."""
        if not hasattr(self, "_encoded"):
            from .kernel import encode

            self._encoded = encode(self)
        return self._encoded

    def run(
        self,
        u: list[list[Any]],
        n: int,
        order: int,
        follow: bool = False,
        guess: dict[int, dict[str, np.ndarray]] | None = None,
    ) -> tuple[State, np.ndarray]:
        """Run every step over ``n`` samples; ``u[d]`` is driver d's value and rates.

        ``follow``: the samples are a path (a sweep from the drawn pose), along
        which the angles are unwrapped as each group is solved. ``guess``: per
        general step (its ``id``), its unknowns' values per sample to start the
        core from instead of the drawing (each sample is then solved alone and
        flagged where it lands off the drawn branch). Returns the state (the
        general groups' solutions in ``state.solved``) and each group's own
        status code per sample (the reasons of general groups in ``state.reasons``).
        """
        st = State(self.n_links, n, order)
        st.follow = follow
        st.guess = guess or {}
        codes = np.zeros((len(self.deps), n), np.int8)
        for g, step in zip(self.group_of_step, self.steps, strict=True):
            code = step.run(st, u)
            if code is not None:
                codes[g] = code
            if isinstance(step, General):
                st.reasons[g] = st.reasons.pop(id(step))
            if follow:
                for i in self.links[g]:
                    if i in self.unwrap:
                        st.ang[i] = unwrap(st.ang[i])
        return st, codes
