"""The report's self-checks: identities a correct motion satisfies, computed apart from the solver.

Each check takes the solved motion as *data* (point positions, velocities,
accelerations; link angular velocities and accelerations; forces) and tests an
identity that does not share the solver's code path:

* **loop closure** — every link is rigid: the distance between two of its
  points stays constant, and the velocity and acceleration fields obey
  ``v_q − v_p = jω (q − p)``, ``a_q − a_p = (jα − ω²)(q − p)`` (the vector
  loop and its two derivatives, Norton §6.7, §7.3);
* **finite differences** — five-point central differences of the positions
  along the (uniform) input sweep, times the input speed, against the
  velocities; and of the velocities against the accelerations;
* **power balance** — the input power plus the power of the loads equals the
  rate of change of kinetic energy, ``Σ m v_G·a_G + I_G ω α`` (Norton §11.3);
* **Kennedy** — the instant centre of every pair of links, found from the two
  velocity fields, is collinear with the other two centres of every triple
  (Norton §6.5);
* **link angles** — each link angle printed is the direction of the line
  through two of its points (θ3 = arg(B − A), ...), and μ follows from them;
* **equilibrium of each link** — with the joint forces printed, every moving
  link obeys ``ΣF = m a_G`` and ``ΣM_G = I_G α`` (Norton eq. 11.9), with
  ``a_G`` written here from the motion (D'Alembert);
* **momentum** — the shaking force and moment printed equal the external
  loads less the rate of change of the machine's linear and angular momentum
  (``F_s = ΣF_ext − Σ m a_G``, Norton §11.8), which involves no joint force;
* **momentum by differences** — the same balance with the rates of momentum
  taken by five-point differences of ``P = Σ m v_G`` and
  ``H = Σ(m G × v_G + I_G ω)`` along the sweep (velocities only), so a
  shaking force solved from wrong accelerations fails it;
* **flywheel energy** — ΔE is the spread of the running integral of
  ``T − T_avg`` over the cycle, integrated here by the trapezoid rule.

A wrong motion (e.g. accelerations scaled by 1.01) fails the acceleration
checks; Kennedy's rule is a velocity-level identity (accelerations do not
enter it), failed by a wrong angular velocity. ``docs/report.md`` lists which
check covers which printed quantity.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from itertools import combinations
from typing import Any

import numpy as np

__all__ = [
    "Body",
    "Check",
    "RigidMotion",
    "acute",
    "angles",
    "equilibrium",
    "finite_differences",
    "flywheel_energy",
    "kennedy",
    "loop_closure",
    "momentum",
    "momentum_differences",
    "power_balance",
    "power_of_loads",
]


@dataclass(frozen=True)
class Check:
    """One self-check: its value against a tolerance, and what it compared."""

    name: str
    value: float
    tolerance: float
    what: str
    samples: int

    @property
    def passed(self) -> bool:
        """True where the measured discrepancy is within the tolerance (and was measured)."""
        return bool(np.isfinite(self.value) and self.value <= self.tolerance and self.samples > 0)


@dataclass(frozen=True)
class RigidMotion:
    """A solved motion as data for the checks (one entry per sample).

    Attributes
    ----------
    x : ndarray
        The input variable of the sweep (uniform steps), e.g. θ2.
    xdot : float
        Its constant rate (the input speed).
    points : mapping of name to (position, velocity, acceleration)
        Complex arrays per sample.
    links : mapping of name to (point names, omega, alpha)
        Each rigid body with the points it carries (the ground with ω = α = 0).
    ok : ndarray of bool
    pins : mapping of (link, link) to point name
        The pins joining pairs of links (their primary instant centres).
    """

    x: np.ndarray
    xdot: float
    points: Mapping[str, tuple[np.ndarray, np.ndarray, np.ndarray]]
    links: Mapping[str, tuple[tuple[str, ...], np.ndarray, np.ndarray]]
    ok: np.ndarray
    pins: Mapping[tuple[str, str], str] = field(default_factory=dict)

    @property
    def size(self) -> float:
        """The largest span of the points (the scale of position residuals)."""
        z = np.concatenate([np.ravel(p[0][self.ok]) for p in self.points.values()])
        z = z[np.isfinite(z)]
        return max(float(np.ptp(z.real)), float(np.ptp(z.imag)), 1e-300) if z.size else 1.0


def _max(values: Sequence[np.ndarray]) -> float:
    vals = [np.nanmax(v) for v in values if np.size(v) and np.isfinite(v).any()]
    return float(max(vals)) if vals else float("nan")


def loop_closure(m: RigidMotion, tol: float = 1e-8) -> list[Check]:
    """Rigidity of every link at position, velocity and acceleration level (relative residuals)."""
    pos, vel, acc = [], [], []
    n = 0
    vscale = ascale = 0.0
    for _, v, a in m.points.values():
        vscale = max(vscale, float(np.nanmax(np.abs(v[m.ok]), initial=0.0)))
        ascale = max(ascale, float(np.nanmax(np.abs(a[m.ok]), initial=0.0)))
    vscale, ascale = max(vscale, 1e-300), max(ascale, 1e-300)
    for names, w, al in m.links.values():
        for i, j in combinations(names, 2):
            (p, v, a), (q, vq, aq) = m.points[i], m.points[j]
            ok = m.ok & np.isfinite(p) & np.isfinite(q)
            if not ok.any():
                continue
            r = q[ok] - p[ok]
            d = np.abs(r)
            pos.append(np.abs(d - np.median(d)) / m.size)
            good = ok & np.isfinite(w) & np.isfinite(vq) & np.isfinite(v)
            vel.append(np.abs(vq - v - 1j * w * (q - p))[good] / vscale)
            good &= np.isfinite(al) & np.isfinite(aq) & np.isfinite(a)
            acc.append(np.abs(aq - a - (1j * al - w * w) * (q - p))[good] / ascale)
            n += int(ok.sum())
    return [
        Check(
            "loop closure: positions",
            _max(pos),
            tol,
            "max |  |q − p| − its median  | / drawing size, over every pair of points on a link",
            n,
        ),
        Check(
            "loop closure: velocities",
            _max(vel),
            tol,
            "max | v_q − v_p − jω(q − p) | / max |v|, every pair on a link",
            n,
        ),
        Check(
            "loop closure: accelerations",
            _max(acc),
            tol,
            "max | a_q − a_p − (jα − ω²)(q − p) | / max |a|, every pair on a link",
            n,
        ),
    ]


def _d5(y: np.ndarray, h: float, every: int = 1) -> np.ndarray:
    """Five-point central difference dy/dx over samples ``every`` apart (NaN near the ends)."""
    out = np.full(y.shape, np.nan, dtype=y.dtype)
    k = 2 * every
    if y.size > 2 * k:
        e, n = every, y.size
        out[k : n - k] = (
            y[: n - 2 * k] - 8 * y[e : n - 3 * e] + 8 * y[3 * e : n - e] - y[2 * k :]
        ) / (12 * h * e)
    return out


def finite_differences(m: RigidMotion, tol: float = 1e-5) -> list[Check]:
    """Velocities and accelerations against five-point differences along the sweep.

    The differences' own truncation error is estimated by Richardson's rule
    (the same stencil over every other sample is 16 × less accurate:
    ``|D_h − D_2h| / 15``); the tolerance is ``tol`` or ten times that
    estimate, whichever is larger, so a coarse sweep is not failed for its
    step while a motion wrong by 1 % still is.
    """
    h = np.diff(m.x)
    if h.size < 8 or np.ptp(h) > 1e-9 * max(abs(h.mean()), 1e-300):
        nan = float("nan")
        return [
            Check("finite differences: velocity", nan, tol, "needs a uniform sweep", 0),
            Check("finite differences: acceleration", nan, tol, "needs a uniform sweep", 0),
        ]
    step = float(h.mean())
    near = np.convolve(~m.ok, np.ones(9), mode="same") == 0  # the stencils see only ok samples
    ev, ea, rv, ra, n = [], [], [], [], 0
    vs = max(
        max(float(np.nanmax(np.abs(v[m.ok]), initial=0)) for _, v, _ in m.points.values()), 1e-300
    )
    as_ = max(
        max(float(np.nanmax(np.abs(a[m.ok]), initial=0)) for _, _, a in m.points.values()), 1e-300
    )
    for p, v, a in m.points.values():
        for y, rate, errs, rich, scale in ((p, v, ev, rv, vs), (v, a, ea, ra, as_)):
            d1 = _d5(y, step) * m.xdot
            d2 = _d5(y, step, 2) * m.xdot
            good = near & np.isfinite(d1) & np.isfinite(d2) & np.isfinite(rate)
            errs.append(np.abs(d1 - rate)[good] / scale)
            rich.append(np.abs(d1 - d2)[good] / (15 * scale))
            n = max(n, int(good.sum()))
    tv = max(tol, 10 * _max(rv)) if np.isfinite(_max(rv)) else tol
    ta = max(tol, 10 * _max(ra)) if np.isfinite(_max(ra)) else tol
    return [
        Check(
            "finite differences: velocity",
            _max(ev),
            tv,
            "max | Δ⁵p/Δx · ẋ − v | / max |v|, five-point central differences "
            "(tolerance: 1e-5 or 10 × Richardson's estimate of their error)",
            n,
        ),
        Check(
            "finite differences: acceleration",
            _max(ea),
            ta,
            "max | Δ⁵v/Δx · ẋ − a | / max |a|, five-point central differences "
            "(tolerance: 1e-5 or 10 × Richardson's estimate of their error)",
            n,
        ),
    ]


def power_balance(
    power_in: np.ndarray,
    dke: np.ndarray,
    ok: np.ndarray,
    tol: float = 1e-8,
    scale: np.ndarray | None = None,
) -> Check:
    """Input power (drivers and loads) against the rate of change of kinetic energy.

    The residual is divided by the largest power that enters the balance
    (``scale``: the sum of the magnitudes of every term, per sample, when
    given), so a machine whose energy does not change is still measured.
    """
    good = ok & np.isfinite(power_in) & np.isfinite(dke)
    value, n = float("nan"), int(good.sum())
    if n:
        terms = np.abs(dke) + np.abs(power_in) if scale is None else np.abs(scale)
        value = float(np.abs(power_in - dke)[good].max()) / max(float(terms[good].max()), 1e-300)
    return Check(
        "power balance",
        value,
        tol,
        "max | P_in + P_loads − Σ(m v_G·a_G + I_G ω α) | / the largest power term",
        n,
    )


def kinetic_energy_rate(
    bodies: Mapping[str, tuple[float, float, np.ndarray, np.ndarray, np.ndarray, np.ndarray]],
) -> np.ndarray:
    """``Σ m Re(conj(v_G) a_G) + I_G ω α`` from (m, I_G, v_G, a_G, ω, α) per body."""
    total = 0.0
    for m, inertia, vg, ag, w, al in bodies.values():
        total = total + m * (np.conj(vg) * ag).real + inertia * w * al
    return np.asarray(total)


def kennedy(m: RigidMotion, tol: float = 1e-7) -> Check:
    """Kennedy's rule: each secondary centre lies on the line through two primary centres.

    For every triple of links in which two pairs are joined by pins (primary
    centres, at the pins' solved positions), the third pair's instant centre —
    found from the two links' velocity fields, ``v_i(P) = v_j(P)`` — must lie on
    the line through those two pins (Norton §6.5). The distance from that line
    is measured in drawing sizes. (Three rigid motions alone always have
    collinear centres; the pins are what make the check bite.)
    """
    ref = {
        name: (m.points[pts[0]][0], m.points[pts[0]][1], w) for name, (pts, w, _) in m.links.items()
    }

    def field_centre(i: str, j: str) -> np.ndarray:
        pi, vi, wi = ref[i]
        pj, vj, wj = ref[j]
        dw = wi - wj
        with np.errstate(all="ignore"):
            c = (vj - vi + 1j * wi * pi - 1j * wj * pj) / (1j * dw)
        far = ~np.isfinite(c) | (np.abs(dw) < 1e-9 * np.maximum(np.abs(wi), np.abs(wj)))
        return np.where(far, np.nan, c)

    def pin(i: str, j: str) -> str | None:
        return m.pins.get((i, j)) or m.pins.get((j, i))

    worst, n, size = [], 0, m.size
    for tri in combinations(m.links, 3):
        for a, b, c in (
            (tri[0], tri[1], tri[2]),
            (tri[1], tri[2], tri[0]),
            (tri[0], tri[2], tri[1]),
        ):
            # primary centres I_ab and I_bc (pins), secondary I_ac from the fields
            p1, p2 = pin(a, b), pin(b, c)
            if p1 is None or p2 is None or pin(a, c) is not None:
                continue
            P1, P2 = m.points[p1][0], m.points[p2][0]
            X = field_centre(a, c)
            u = P2 - P1
            with np.errstate(all="ignore"):
                dist = np.abs((np.conj(u) * (X - P1)).imag) / np.abs(u)
            good = m.ok & np.isfinite(dist) & (np.abs(u) > 1e-9 * size) & (np.abs(X) < 100 * size)
            if good.any():
                worst.append(dist[good] / size)
                n += int(good.sum())
    return Check(
        "Kennedy's rule",
        _max(worst),
        tol,
        "max distance of each secondary centre (from the velocity fields) from the line through "
        "its two primary centres (pins) / drawing size",
        n,
    )


def angles(
    pairs: Sequence[tuple[np.ndarray, np.ndarray]],
    ok: np.ndarray,
    tol: float = 1e-9,
    name: str = "link angles",
    what: str = "max |θ − arg(q − p)| (rad, wrapped): every angle printed against the line "
    "through two points of its link (μ against the two links' lines)",
) -> Check:
    """Each angle printed against the angle written from two points of its link.

    ``pairs`` holds ``(angle, expected)`` arrays (radians); the difference is
    wrapped to (−π, π] before it is measured.
    """
    worst, n = [], 0
    for theta, expected in pairs:
        with np.errstate(all="ignore"):
            r = np.angle(np.exp(1j * (np.ravel(theta) - np.ravel(expected))))
        good = ok & np.isfinite(r)
        if good.any():
            worst.append(np.abs(r[good]))
            n = max(n, int(good.sum()))
    return Check(name, _max(worst), tol, what, n)


def acute(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The acute angle between the lines along ``u`` and ``v`` (radians, [0, π/2])."""
    with np.errstate(all="ignore"):
        m = np.abs(np.angle(v / u))
    return np.minimum(m, np.pi - m)


@dataclass
class Body:
    """A moving link as data for the force checks (one entry per sample).

    ``loads`` are ``(force, point, source)`` acting on the body — ``source`` is
    ``"joint"`` (another moving link), ``"ground"`` (a reaction of the frame)
    or ``"external"`` (gravity, applied loads) — and ``torques`` are
    ``(torque, source)``. ``G``, ``vG``, ``aG`` (complex) and ``omega``,
    ``alpha`` are written by the check's caller from the solved motion.
    """

    name: str
    mass: float
    inertia: float
    G: np.ndarray
    vG: np.ndarray
    aG: np.ndarray
    omega: np.ndarray
    alpha: np.ndarray
    loads: list[tuple[np.ndarray, np.ndarray, str]] = field(default_factory=list)
    torques: list[tuple[np.ndarray, str]] = field(default_factory=list)

    def load(self, force: np.ndarray, point: np.ndarray, source: str) -> None:
        """Add a force acting on the body at ``point``."""
        self.loads.append((np.asarray(force, complex), np.asarray(point, complex), source))

    def torque(self, torque: np.ndarray, source: str) -> None:
        """Add a couple acting on the body."""
        self.torques.append((np.asarray(torque, float), source))


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return (np.conj(a) * b).imag


def _peak(x: Any, ok: np.ndarray) -> float:
    """Largest finite magnitude of ``x`` (broadcast to the samples) where ``ok``."""
    v = np.abs(np.broadcast_to(np.asarray(x), np.shape(ok)))[ok]
    v = v[np.isfinite(v)]
    return float(v.max()) if v.size else 0.0


def equilibrium(bodies: Sequence[Body], ok: np.ndarray, size: float, tol: float = 1e-8) -> Check:
    """``ΣF − m a_G`` and ``ΣM_G − I_G α`` of every moving link, relative to the largest force.

    The joint forces printed, the drive and the external loads are summed on
    each link; the moment is taken about its centre of mass. A wrong joint
    force, driving torque or acceleration fails it (Norton eq. 11.9).
    """
    residuals, scale = [], 0.0
    for b in bodies:
        F = -b.mass * b.aG
        M = -b.inertia * b.alpha
        scale = max(scale, _peak(b.mass * b.aG, ok))
        for force, point, _ in b.loads:
            F = F + force
            M = M + _cross(point - b.G, np.broadcast_to(force, np.shape(point)))
            scale = max(scale, _peak(force, ok))
        for torque, _ in b.torques:
            M = M + torque
        residuals.append(np.maximum(np.abs(F), np.abs(M) / max(size, 1e-300)))
    if not residuals:
        return Check("equilibrium of each link", float("nan"), tol, "no moving link", 0)
    r = np.max(residuals, axis=0) / max(scale, 1e-300)
    good = ok & np.isfinite(r)
    return Check(
        "equilibrium of each link",
        float(r[good].max()) if good.any() else float("nan"),
        tol,
        "max over links of |ΣF − m a_G| and |ΣM_G − I_G α| / size, / the largest force "
        "(joint forces, drive and loads as printed; a_G from the motion)",
        int(good.sum()),
    )


def momentum(
    bodies: Sequence[Body],
    shaking_force: np.ndarray,
    shaking_moment: np.ndarray | None,
    ok: np.ndarray,
    size: float,
    tol: float = 1e-8,
) -> Check:
    """The shaking force and moment against the external loads less the rate of momentum.

    ``F_s = ΣF_ext − Σ m a_G`` and ``M_s = ΣM_ext − Σ(m G × a_G + I_G α)``
    about the origin: the machine's momentum balance, with no joint force in
    it (``external`` loads only; the frame's reactions are what is checked).
    """
    Fs = np.zeros(np.shape(ok), complex)
    Ms = np.zeros(np.shape(ok))
    scale = _peak(shaking_force, ok)
    for b in bodies:
        Fs = Fs - b.mass * b.aG
        Ms = Ms - (b.mass * _cross(b.G, b.aG) + b.inertia * b.alpha)
        scale = max(scale, _peak(b.mass * b.aG, ok))
        for force, point, source in b.loads:
            if source == "external":
                Fs = Fs + force
                Ms = Ms + _cross(point, np.broadcast_to(force, np.shape(point)))
                scale = max(scale, _peak(force, ok))
        for torque, source in b.torques:
            if source == "external":
                Ms = Ms + torque
    r = np.abs(np.ravel(shaking_force) - Fs)
    if shaking_moment is not None:
        r = np.maximum(r, np.abs(np.ravel(shaking_moment) - Ms) / max(size, 1e-300))
    r = r / max(scale, 1e-300)
    good = ok & np.isfinite(r)
    return Check(
        "momentum: shaking force and moment",
        float(r[good].max()) if good.any() else float("nan"),
        tol,
        "max |F_s − (ΣF_ext − Σ m a_G)| and |M_s − (ΣM_ext − Σ(m G×a_G + I_G α))| / size, "
        "/ the largest force (no joint force enters)",
        int(good.sum()),
    )


def momentum_differences(
    bodies: Sequence[Body],
    shaking_force: np.ndarray,
    shaking_moment: np.ndarray | None,
    x: np.ndarray,
    xdot: float,
    ok: np.ndarray,
    size: float,
    tol: float = 1e-5,
) -> Check:
    """The shaking force and moment against differences of the momentum along the sweep.

    ``F_s = ΣF_ext − dP/dt`` and ``M_s = ΣM_ext − dH/dt`` (about the origin),
    with the linear momentum ``P = Σ m v_G`` and the angular momentum
    ``H = Σ(m G × v_G + I_G ω)`` written from positions and velocities only,
    differentiated by five-point central differences over the (uniform) input
    sweep times its rate ``ẋ``. Accelerations do not enter, so a shaking force
    solved from a wrong acceleration fails it. The tolerance is ``tol`` or ten
    times Richardson's estimate of the differences' own error.
    """
    x = np.ravel(np.asarray(x, float))
    ok = np.ravel(ok)
    h = np.diff(x)
    name = "momentum by differences"
    what = (
        "max |F_s − (ΣF_ext − ΔP/Δt)| and |M_s − (ΣM_ext − ΔH/Δt)| / size, / the largest "
        "force; P = Σ m v_G, H = Σ(m G×v_G + I_G ω) differenced (five points) along the sweep"
    )
    if h.size < 8 or np.ptp(h) > 1e-9 * max(abs(h.mean()), 1e-300) or not bodies:
        return Check(name, float("nan"), tol, "needs a uniform sweep and a moving mass", 0)
    step = float(h.mean())
    P = np.zeros(x.shape, complex)
    H = np.zeros(x.shape)
    Fe = np.zeros(x.shape, complex)
    Me = np.zeros(x.shape)
    terms = np.zeros(x.shape)  # Σ |m Δv_G/Δt|: the scale when the sum nearly cancels
    for b in bodies:
        P = P + b.mass * b.vG
        terms = terms + np.abs(b.mass * _d5(np.asarray(b.vG, complex), step) * xdot)
        H = H + b.mass * _cross(b.G, b.vG) + b.inertia * b.omega
        for force, point, source in b.loads:
            if source == "external":
                Fe = Fe + force
                Me = Me + _cross(point, np.broadcast_to(force, np.shape(point)))
        for torque, source in b.torques:
            if source == "external":
                Me = Me + torque
    near = np.convolve(~ok, np.ones(9), mode="same") == 0
    dP, dP2 = _d5(P, step) * xdot, _d5(P, step, 2) * xdot
    dH, dH2 = _d5(H, step) * xdot, _d5(H, step, 2) * xdot
    Fs = np.ravel(shaking_force)
    r = np.abs(Fs - (Fe - dP))
    rich = np.abs(dP - dP2) / 15
    if shaking_moment is not None:
        Ms = np.ravel(shaking_moment)
        s = max(size, 1e-300)
        r = np.maximum(r, np.abs(Ms - (Me - dH)) / s)
        rich = np.maximum(rich, np.abs(dH - dH2) / (15 * s))
    good = near & ok & np.isfinite(r) & np.isfinite(rich)
    if not good.any():
        return Check(name, float("nan"), tol, what, 0)
    scale = max(_peak(Fs, good), _peak(Fe, good), _peak(terms, good), 1e-300)
    value = float(r[good].max()) / scale
    return Check(name, value, max(tol, 10 * float(rich[good].max()) / scale), what, int(good.sum()))


def power_of_loads(bodies: Sequence[Body]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(P, dKE/dt, scale)``: the power of the frame's and the external loads, and dKE/dt.

    Joint forces between moving links do no net work and are left out; the
    point of application moves with the body (``v = v_G + jω (p − G)``).
    """
    power, dke, scale = 0.0, 0.0, 0.0
    for b in bodies:
        term = b.mass * (np.conj(b.vG) * b.aG).real + b.inertia * b.omega * b.alpha
        dke, scale = dke + term, scale + np.abs(term)
        for force, point, source in b.loads:
            if source != "joint":
                v = b.vG + 1j * b.omega * (point - b.G)
                term = (np.conj(v) * force).real
                power, scale = power + term, scale + np.abs(term)
        for torque, source in b.torques:
            if source != "joint":
                term = torque * b.omega
                power, scale = power + term, scale + np.abs(term)
    return np.asarray(power), np.asarray(dke), np.asarray(scale)


def flywheel_energy(theta: np.ndarray, torque: np.ndarray, result: Any, tol: float = 1e-3) -> Check:
    """ΔE of a flywheel against the trapezoid rule on the sampled torque curve.

    The running integral of ``T − T_avg`` over one cycle (``T_avg`` its mean
    by the same rule), its spread ``max − min`` against the ΔE printed, and
    ``I = ΔE / (k ω²)`` against the inertia printed. The sampled spread can
    miss an extreme between two samples: the tolerance is relative (1e-3).
    """
    th = np.append(np.ravel(theta), np.ravel(theta)[0] + 2 * np.pi)
    T = np.append(np.ravel(torque), np.ravel(torque)[0])
    area = np.concatenate([[0.0], np.cumsum(0.5 * (T[1:] + T[:-1]) * np.diff(th))])
    avg = area[-1] / (th[-1] - th[0])
    E = area - avg * (th - th[0])
    delta = float(E.max() - E.min())
    inertia = delta / (result.k * result.omega_avg**2)
    value = max(
        abs(delta - result.delta_e) / max(abs(result.delta_e), 1e-300),
        abs(inertia - result.inertia) / max(abs(result.inertia), 1e-300),
    )
    return Check(
        "flywheel energy",
        value,
        tol,
        "| ΔE − spread of ∫(T − T_avg)dθ (trapezoid rule) | / ΔE, and I = ΔE/(kω²) likewise",
        int(np.size(theta)),
    )


def describe(value: float) -> str:
    """A check's value as printed (scientific, 2 digits)."""
    return "not measured" if not np.isfinite(value) else f"{value:.2e}"
