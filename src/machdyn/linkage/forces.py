"""Newton–Euler forces of a drawn linkage: one assembler over every sample at once."""

from __future__ import annotations

import functools
import itertools
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._summary import Summarized
from .._validate import finite_array, items, mapping, nonnegative
from ..errors import InputError, ModelError, UnknownNameError
from ..loops import lu_factor, lu_solve
from . import newton_euler
from ._common import (
    GROUND,
    _complex_point,
    _frozen,
    _name,
    _ref_angle,
    _typical_length,
    check_motion,
)
from .kinematics import LinkageMotion
from .topology import _Edge

#: Samples are assembled and solved in blocks of this size (bounded memory).
_CHUNK = 1 << 15
#: A force block whose pivot ratio (after equilibration) is below this is singular.
_SINGULAR_RCOND = 1e-12

#: Joints that slide: straight slider and slot, and their curved forms (arc: a pin in
#: a curved slot; arcP: a block on a curved guide, turning with the radius).
_ARCS = ("arc", "arcP")
#: Up to this many sliders with Coulomb friction every set of normal-force signs is
#: tried (2**n solves): wedging found exactly; above, one slider's sign flipped at a time.
_EVERY_SIGN = 6
_SLIDING = ("P", "slot", *_ARCS)
_WITH_COUPLE = ("P", "arcP")

FORCE_REASONS = {
    "singular": "singular force system (toggle or dead point): the joint forces are not "
    "determined by Newton–Euler",
    "coulomb": "Coulomb friction: no consistent sign of the normal force (self-locking)",
    "wedging": "Coulomb friction: two normal forces satisfy the equations (wedging): the "
    "joint forces are not determined",
    "spring": "a spring's two ends meet (zero length): the direction of its force is undefined",
}


@dataclass(frozen=True)
class LinkageForces(Summarized):
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
    >>> from machdyn.linkage import Linkage
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
        _name("a", a), _name("p", p)
        if (a, p) in self.pins:
            return self.pins[(a, p)]
        if (p, a) in self.pins:
            return -self.pins[(p, a)]
        raise UnknownNameError(
            "F", f"no pin joins {a!r} and {p!r}; pins: {', '.join(map(str, self.pins))}"
        )

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

        from ..units import columns

        spec: list[tuple[str, str | None, Any]] = []

        def xy(name: str, v: Any, kind: str | None = "force") -> None:
            spec.extend(
                ((f"{name}_x", kind, np.ravel(v).real), (f"{name}_y", kind, np.ravel(v).imag))
            )

        for (a, p), v in self.pins.items():
            xy(f"F_{a}_{p}", v)
        for k, v in self.sliders.items():
            xy(f"F_{k}", v)
        spec += [(f"N_{k}", "force", v) for k, v in self.normal.items()]
        spec += [(f"M_{k}", "torque", v) for k, v in self.couple.items()]
        for k, v in self.rolling.items():
            xy(f"F_{k}", v)
        angles = self.motion.angle_drivers
        spec += [
            (f"driver_{k}", "torque" if k in angles else "force", v) for k, v in self.driver.items()
        ]
        for k, v in self.elements.items():  # a spring's or a torsion spring's: not labelled
            spec += [
                (f"T_{k}", None, np.ravel(v)),
                (f"L_{k}", None, np.ravel(self.element_length[k])),
            ]
            spec.append((f"Ldot_{k}", None, np.ravel(self.element_rate[k])))
        xy("shaking_force", self.shaking_force)
        spec += [("shaking_moment", "torque", self.shaking_moment)]
        spec += [("ok", None, self.ok), ("reason", None, self.reason)]
        cols = columns(self.motion.units, spec)
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
    check_motion(lk, motion)
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
    for e in edges:  # a curved slot or slider slides along the tangent, normal to C→P
        if e.kind in _ARCS:
            radial = P[e.pb] - P[e.pa]
            slide_u[e.name] = 1j * radial / np.where(np.abs(radial) > 0, np.abs(radial), 1.0)
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

    current_kappa: dict[str, Any] = {}

    def build(kappa: Mapping[str, Any]) -> None:
        """Columns of the unknowns; ``kappa[slider]`` adds Coulomb friction κ·N·û."""
        current_kappa.clear()
        current_kappa.update(kappa)
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
        elif e.kind in _SLIDING:
            X = P[e.pb]
            uhat = slide_u[e.name]
            un = 1j * uhat + kappa.get(e.name, 0.0) * uhat
            force_col([(e.b, X, un, 1.0), (e.a, X, un, -1.0)], ("normal", e.name))
            if e.kind in _WITH_COUPLE:
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

    for item in items("external_forces", external_forces, what="(link, point, force) triples"):
        try:
            link, point, force = item
        except (TypeError, ValueError):
            raise InputError(
                "external_forces", f"each is (link, point, force), got {item!r}"
            ) from None
        if _name("external_forces", link) not in lk._links:
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
        external_torques.items()
        if isinstance(external_torques, Mapping)
        else items("external_torques", external_torques, what="(link, torque) pairs")
    )
    for pair in torques:
        if not isinstance(pair, tuple | list) or len(pair) != 2:
            raise InputError("external_torques", f"each is (link, torque), got {pair!r}")
        link, T = pair
        if _name("external_torques", link) not in lk._links:
            raise ModelError(f"external torque on unknown link {link!r}; links: {lk._names()}")
        b[:, row[link] + 2] -= flat(finite_array(f"external torque on {link}", T))
    friction: dict[str, np.ndarray] = {}
    for name, beta in mapping("viscous", viscous, "friction coefficients β").items():
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
            spec = _closed_form(rows, cols, labels, moving, edges, lk)
            blocks.append((rows, cols, inner, coupling, spec))
        for lo in range(0, n_s, _CHUNK):
            sl = slice(lo, min(lo + _CHUNK, n_s))
            size = sl.stop - sl.start
            skip = bad[sl]
            for rows, cols, inner, coupling, spec in blocks:
                nb = len(rows)
                rhs = b[sl, rows].T
                for i, k, coef in coupling:
                    rhs[i] -= (coef[sl] if np.ndim(coef) else coef) * x[sl, k]
                if spec is not None:  # a driver, an RRR or an RRP dyad: in closed form
                    geo = {"G": G, "P": P, "u": slide_u, "kappa": current_kappa, "sl": sl}
                    sol, sing = _solve_closed(spec, rhs, geo)
                    singular[sl] |= sing & ~skip
                    for k, val in zip(cols, sol, strict=True):  # (0 where not solved, as LU's)
                        x[sl, k] = np.where(skip, 0.0, val) if skip.any() else val
                    continue
                A = np.zeros((nb, nb, size))  # layout of machdyn.loops.lu_factor
                for i, j, coef in inner:
                    A[i, j] += coef[sl] if np.ndim(coef) else coef
                if skip.any():
                    A[:, :, skip] = np.eye(nb)[:, :, None]
                    rhs[:, skip] = 0.0
                fac = lu_factor(A, row_scale[rows], col_scale[cols])
                singular[sl] |= ~(fac.rcond > _SINGULAR_RCOND)
                x[sl, cols] = lu_solve(fac, rhs).T
        x[bad | singular] = np.nan
        return x, singular

    x, singular = solve_system()

    @functools.cache  # one scale for every Coulomb slider of the call
    def rest_scale() -> np.ndarray:
        """The speed scale per sample a slide's rate is at rest against (``_slip_sign``).

        The linkage's typical length times its fastest link's rate, plus the fastest slide's.
        """
        rates = [np.abs(flat(np.nan_to_num(motion.omega[n]))) for n in moving]
        slides = [np.abs(flat(np.nan_to_num(r))) for r in motion.length_rate.values()]
        return length * np.max(rates, axis=0) + np.max([np.zeros(n_s), *slides], axis=0)

    def normal(x_: np.ndarray, m: str) -> np.ndarray:
        return x_[:, labels.index(("normal", m))]

    def sign_of(N: np.ndarray) -> np.ndarray:
        return np.where(N < 0, -1.0, 1.0)

    def consistent(x_: np.ndarray, signs: Mapping[str, np.ndarray], idle) -> np.ndarray:
        """Samples where each slider's normal force has the sign its friction was given.

        ``idle[m]``: the samples where slider ``m`` has no friction (μ = 0, or at rest
        with no acceleration): any sign of its normal force agrees there.
        """
        agree = np.ones(n_s, bool)
        for m, s_m in signs.items():
            N = normal(x_, m)
            agree &= ((sign_of(N) == s_m) | idle[m]) & np.isfinite(N)
        return agree

    def every_sign(slipping: Mapping[str, tuple], singular: np.ndarray) -> tuple:
        """Every set of normal-force signs tried: the one that agrees, or wedging.

        A sample has one answer where exactly one set of signs gives normal forces of
        those signs; none: self-locking (``coulomb``); more: wedging. A slider whose
        friction vanishes (μ = 0, or at rest with no acceleration) counts with + only.
        """
        names = [m for m, (mu, _) in slipping.items() if mu]
        idle = {m: slipping[m][1] == 0 for m in names}
        count = np.zeros(n_s, int)
        x_one = np.full((n_s, n_eq), np.nan)
        singular_one = np.zeros(n_s, bool)
        chosen = {m: np.ones(n_s) for m in slipping}
        for pattern in itertools.product((1.0, -1.0), repeat=len(names)):
            signs = {m: np.full(n_s, p) for m, p in zip(names, pattern, strict=True)}
            build({m: -mu * signs.get(m, 1.0) * sv for m, (mu, sv) in slipping.items()})
            x_p, singular_p = solve_system()
            agree = consistent(x_p, signs, idle)
            for m, p in zip(names, pattern, strict=True):
                agree &= ~idle[m] | (p > 0)  # no friction there: the sign is no choice
            count += agree
            x_one[agree] = x_p[agree]
            singular_one[agree] = singular_p[agree]
            for m in names:
                chosen[m] = np.where(agree, signs[m], chosen[m])
        kappa_ = {m: -mu * chosen[m] * sv for m, (mu, sv) in slipping.items()}
        build(kappa_)
        singular_one = np.where(count == 0, singular, singular_one)  # as the smooth solve
        return x_one, singular_one, count == 0, count >= 2, kappa_

    def one_flip(slipping: Mapping[str, tuple], sign_n: dict) -> np.ndarray:
        """Wedging with many sliders, one slider at a time.

        That slider's sign is held the other way and the others' are found as the
        iteration does; a sample wedges where those signs all agree.
        """
        wedged = np.zeros(n_s, bool)
        idle = {m: (sv_m == 0) | (mu_m == 0) for m, (mu_m, sv_m) in slipping.items()}
        for n, (mu, sv) in slipping.items():
            if not mu:
                continue
            other = {m: s_m.copy() for m, s_m in sign_n.items()}
            other[n] = -sign_n[n]
            for _ in range(8):
                build({m: -mu_m * other[m] * sv_m for m, (mu_m, sv_m) in slipping.items()})
                x_other, _ = solve_system()
                agree = consistent(x_other, other, idle) & (sv != 0) & (normal(x_other, n) != 0)
                for m in slipping:
                    if m != n:
                        other[m] = sign_of(normal(x_other, m))
                if agree.all():
                    break
            wedged |= agree
        return wedged

    kappa: dict[str, Any] = {}
    slipping = {}
    for name, mu in mapping("coulomb", coulomb, "friction coefficients μ").items():
        edge = next((e for e in edges if e.name == name and e.kind in ("P", "slot")), None)
        if edge is None and name in lk._curved:
            raise ModelError(
                f"Coulomb friction at {name!r}: friction on a curved slide is not supported yet "
                "(only straight sliders and slots); leave it out or use a straight guide"
            )
        if edge is None:
            raise ModelError(
                f"Coulomb friction at {name!r}: no such slider or slot; joints: "
                f"{', '.join([*lk._sliders, *lk._slots]) or '(none)'}"
            )
        mu = nonnegative(f"coulomb[{name}]", mu)
        v = flat(np.nan_to_num(motion.length_rate[name]))
        a = flat(np.nan_to_num(motion.length_acceleration[name]))
        slipping[name] = (mu, newton_euler._slip_sign(v, a, rest_scale()))
    friction_bad = np.zeros(n_s, bool)
    if slipping and len(slipping) <= _EVERY_SIGN:
        x, singular, friction_bad, wedged, kappa = every_sign(slipping, singular)
    elif slipping:
        # the sign of N is unknown beforehand: start from the smooth solution and
        # re-solve with the signs found until they agree (the notes' ±μN)
        sign_n = {n: sign_of(normal(x, n)) for n in slipping}
        for _ in range(8):
            kappa = {n: -mu * sign_n[n] * sv for n, (mu, sv) in slipping.items()}
            build(kappa)
            x, singular = solve_system()
            friction_bad[:] = False
            for n in slipping:
                N = normal(x, n)
                new = sign_of(N)
                wrong = (new != sign_n[n]) & np.isfinite(N) & (np.abs(N) > 0)
                friction_bad |= wrong
                sign_n[n] = new
            if not friction_bad.any():
                break
        # wedging: a second set of normal-force signs satisfies the equations too
        wedged = one_flip(slipping, sign_n)
        build(kappa)
    else:
        wedged = np.zeros(n_s, bool)
    friction_bad |= wedged
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
        if e.kind in _SLIDING:
            N = col_of("normal", e.name)
            F = N * (1j + kappa.get(e.name, 0.0)) * slide_u[e.name]
            normal[e.name] = N.reshape(shape)
            if e.kind in _WITH_COUPLE:
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
    reasons[wedged & ~bad & ~singular] = FORCE_REASONS["wedging"]
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


# ---------------------------------------------------------------------- Assur blocks in closed form
def _closed_form(rows, cols, labels, moving, edges, lk) -> tuple | None:
    """The closed form of a block of the force system, or None (then an LU solves it).

    A block with one link, one pin and a driving torque is a driver; two links
    with three pins an RRR dyad; two links with two pins and a slider with its
    couple an RRP dyad (:mod:`machdyn.linkage.newton_euler`).
    """
    links = list(dict.fromkeys(moving[r // 3] for r in rows))
    if len(rows) != 3 * len(links):
        return None
    pin_of = {f"{e.a}|{e.b}|{c}": (e, c) for e in edges if e.kind == "R" for c in "xy"}
    pins: dict[_Edge, dict[str, int]] = {}
    other = []
    for j, k in enumerate(cols):
        kind, name = labels[k]
        if kind == "pin" and name in pin_of:
            e, comp = pin_of[name]
            pins.setdefault(e, {})[comp] = j
        else:
            other.append((j, kind, name))
    if any(len(v) != 2 for v in pins.values()):
        return None
    inner = [e for e in pins if e.a in links and e.b in links]
    if len(links) == 1 and len(pins) == 1 and len(other) == 1 and other[0][1] == "driver":
        (L,), (e,) = links, pins
        d = other[0][2]
        if d in lk._links:
            sign = 1.0
        elif d in lk._motors:
            sign = 1.0 if lk._motor_links(d)[1] == L else -1.0
        else:
            return None
        return ("crank", L, e, pins[e], other[0][0], sign)
    if len(links) != 2 or len(inner) != 1:
        return None
    mid = inner[0]
    outer = {L: [e for e in pins if e is not mid and L in (e.a, e.b)] for L in links}
    if len(pins) == 3 and not other and all(len(v) == 1 for v in outer.values()):
        L1, L2 = links
        e1, e3 = outer[L1][0], outer[L2][0]
        return ("rrr", L1, L2, e1, mid, e3, pins[e1], pins[mid], pins[e3])
    kinds = {kind: (j, name) for j, kind, name in other}
    if len(pins) == 2 and len(other) == 2 and set(kinds) == {"normal", "couple"}:
        name = kinds["normal"][1]
        if kinds["couple"][1] != name:
            return None
        slide = next((e for e in edges if e.name == name and e.kind == "P"), None)
        if slide is None or slide.b not in links or slide.a in links:
            return None
        block = slide.b
        rod = next(L for L in links if block != L)
        if len(outer[rod]) != 1 or outer[block]:
            return None
        e1 = outer[rod][0]
        return ("rrp", rod, block, e1, mid, slide, pins[e1], pins[mid],
                kinds["normal"][0], kinds["couple"][0], links.index(rod))  # fmt: skip
    return None


def _solve_closed(spec: tuple, rhs: np.ndarray, geo: dict) -> tuple[list, np.ndarray]:
    """Solve a block in closed form: its unknowns (in the block's column order), singular."""
    sl, G, P = geo["sl"], geo["G"], geo["P"]
    n_cols = len(rhs)
    sol: list[Any] = [None] * n_cols

    def load(i: int, L: str, Q: Any) -> tuple[Any, Any]:
        """Link L's known load (the block's row triple i): resultant, moment about Q."""
        F = -(rhs[3 * i] + 1j * rhs[3 * i + 1])
        return F, -rhs[3 * i + 2] + _cross(G[L][sl] - Q, F)

    def put(cols: dict[str, int], e: _Edge, on: str, F: Any) -> None:
        """A pin's columns: the force on the edge's ``b`` from its ``a``; F is on ``on``."""
        F = F if e.b == on else -F
        sol[cols["x"]], sol[cols["y"]] = F.real, F.imag

    if spec[0] == "crank":
        _, L, e, cols, jT, sign = spec
        X = P[e.pa][sl]
        F_pin = rhs[0] + 1j * rhs[1]  # the unknown forces on the link sum to the rows
        sol[jT] = sign * (rhs[2] - _cross(X - G[L][sl], F_pin))
        put(cols, e, L, F_pin)
        return sol, np.zeros(len(X), bool)
    if spec[0] == "rrr":
        _, L1, L2, e1, mid, e3, c1, cm, c3 = spec
        A, B, C = P[e1.pa][sl], P[mid.pa][sl], P[e3.pa][sl]
        F1, M1 = load(0, L1, A)
        F2, M2 = load(1, L2, C)
        F_A, F_B, F_C, det = newton_euler.rrr(B - A, B - C, F1, M1, F2, M2)
        put(c1, e1, L1, F_A)
        put(cm, mid, L1, F_B)
        put(c3, e3, L2, F_C)
        return sol, ~(np.abs(det) > 1e-12 * np.abs(B - A) * np.abs(B - C))
    _, rod, block, e1, mid, slide, c1, cm, jN, jC, i_rod = spec
    A, B, X = P[e1.pa][sl], P[mid.pa][sl], P[slide.pb][sl]
    u = geo["u"][slide.name][sl]
    kappa = geo["kappa"].get(slide.name, 0.0)
    v = 1j * u + (kappa[sl] if np.ndim(kappa) else kappa) * u
    F1, M1 = load(i_rod, rod, A)
    F2, M2 = load(1 - i_rod, block, B)
    F_A, F_B, N, Cp, den = newton_euler.rrp(B - A, X - B, v, F1, M1, F2, M2)
    put(c1, e1, rod, F_A)
    put(cm, mid, rod, F_B)
    sol[jN], sol[jC] = N, Cp
    return sol, ~(np.abs(den) > 1e-12 * np.abs(B - A) * np.abs(v))
