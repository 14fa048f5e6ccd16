"""Solving a linkage through the vector-loop core (:mod:`machdyn.loops`).

The general path: the whole linkage compiled into vector loops
(:func:`~machdyn.linkage.topology.compile_loops`), solved by Newton–Raphson
with continuation from the drawn pose. It serves linkages with a group the
closed forms do not cover, and :attr:`LinkageMotion.loop_motion`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import ModelError
from ..loops.result import Motion
from ._common import GROUND, _frozen, _ref_angle
from .kinematics import LinkageMotion, _cg_drawn
from .loopcompile import _Compiled

if TYPE_CHECKING:
    from .builder import Linkage


def solve_loops(
    lk: Linkage,
    vals: dict[str, np.ndarray],
    vel: dict[str, np.ndarray] | None,
    acc: dict[str, np.ndarray],
    cont: bool,
) -> LinkageMotion:
    """Positions, velocities and accelerations by the vector-loop core."""
    c = lk._compile().loops()
    drivers = tuple(lk._drivers)
    shape = np.broadcast_shapes(*(np.shape(v) for v in vals.values()))
    u = {
        var: np.broadcast_to(vals[d], shape) - off
        for d, var, off in zip(drivers, c.driver_vars, c.driver_offsets, strict=True)
    }
    unknowns = [n for n in c.drawn if n not in c.driver_vars]
    guess = {n: c.drawn[n] for n in unknowns}
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
        _loop=lm,
        angle_drivers=frozenset(d for d in vals if d in lk._links or d in lk._motors),
    )
