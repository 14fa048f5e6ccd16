"""Kinematics of a drawn linkage: solving the compiled loops, and the motion result."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from .._validate import finite_array
from ..errors import ModelError
from ..loops.result import Motion
from ._common import GROUND, _frozen, _is_zero, _ref_angle
from .topology import _Compiled

if TYPE_CHECKING:
    from .builder import Linkage
    from .view import Link


def solve(
    lk: Linkage,
    values: Any,
    velocity: Any = None,
    acceleration: Any = 0.0,
    continuation: bool | None = None,
) -> LinkageMotion:
    """The body of :meth:`Linkage.solve` (see there)."""
    c = lk._compile()
    drivers = tuple(lk._drivers)
    vals = _per_driver("values", values, drivers, required=True)
    vel = None if velocity is None else _per_driver("velocity", velocity, drivers, True)
    acc = _per_driver("acceleration", acceleration, drivers, False)
    if vel is None and acceleration is not None and not _is_zero(acceleration):
        raise ModelError("acceleration needs the driver velocity too (velocity=...)")
    shape = np.broadcast_shapes(*(np.shape(v) for v in vals.values()))
    u = {
        var: np.broadcast_to(vals[d], shape) - off
        for d, var, off in zip(drivers, c.driver_vars, c.driver_offsets, strict=True)
    }
    unknowns = [n for n in c.drawn if n not in c.driver_vars]
    guess = {n: c.drawn[n] for n in unknowns}
    cont = continuation if continuation is not None else (len(shape) <= 1 and np.prod(shape) > 1)
    if cont or np.prod(shape) == 1:  # follow the drawn circuit to the first sample
        _check_drawn_pose(c)
        guess = _march(c, guess, {k: float(np.ravel(v)[0]) for k, v in u.items()})
    kw: dict[str, Any] = {"continuation": cont}
    if vel is not None:
        kw["velocity"] = {var: vel[d] for d, var in zip(drivers, c.driver_vars, strict=True)}
        kw["acceleration"] = {var: acc[d] for d, var in zip(drivers, c.driver_vars, strict=True)}
        kw["order"] = 2
    lm = c.system.solve(u, guess, **kw)
    return _motion(lk, c, lm, vals)


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
    >>> from machdyn.linkage import Linkage
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


def _cg_drawn(lk: Linkage, ln: Link) -> complex:
    p0 = lk._points[ln.points[0]]
    if ln.cg is None:
        return p0
    if isinstance(ln.cg, str):
        return lk._points[ln.cg]
    return p0 + ln.cg * np.exp(1j * _ref_angle(lk, ln.name))
