"""Solving a linkage of closed-form groups over a batch of driver values.

The program of :mod:`machdyn.linkage.program` gives every group's pose on its
drawn assembly sign at each sample independently, so no sample can land on
another branch. What a sweep adds is the *representative* of each angle:
angles are not wrapped, they run continuously along a sweep. For a 1-D sweep
(or a single pose) the program is also run along a path from the drawn pose to
the first sample and between samples further apart than :data:`STEP`, and each
angle is unwrapped along that path, as the vector-loop core's continuation
would follow it; samples solved independently (``continuation=False``) take
the angle within π of the drawn one.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import ModelError
from ._common import GROUND, _frozen, _ref_angle, _typical_length
from .kinematics import LinkageMotion, _cg_drawn
from .program import NO_ASSEMBLY, OK, SINGULAR, Program, State

if TYPE_CHECKING:
    from .builder import Linkage
    from .topology import _Model

#: Largest step of a driver (radians; lengths in units of the typical link length)
#: between two samples of the path along which angles are unwrapped.
STEP = 0.2

Ref = tuple[int, complex]


@dataclass(frozen=True)
class _Info:
    """What a closed-form solve needs besides the program, built once per linkage."""

    start: np.ndarray  # drawn value of every driver
    scale: np.ndarray  # 1 for angle drivers, the typical length for length drivers
    links: tuple[tuple[str, int, float], ...]  # moving link, index, drawn angle
    points: tuple[tuple[str, Ref], ...]
    cgs: tuple[tuple[str, Ref], ...]
    slides: tuple[tuple[str, Ref, Ref, complex, int], ...]  # name, foot, at, u0, guide
    actuators: tuple[tuple[str, Ref, Ref], ...]
    group_links: tuple[tuple[int, ...], ...]
    texts: tuple[tuple[str, str, str], ...]  # per group: no assembly, singular, its name
    angle_drivers: frozenset[str]


def _info(lk: Linkage, model: _Model) -> _Info:
    if "sweep" in model.cache:
        return model.cache["sweep"]  # type: ignore[return-value]
    index = {GROUND: 0, **{n: i + 1 for i, n in enumerate(lk._links)}}
    origin = {GROUND: 0j, **{n: lk._points[ln.points[0]] for n, ln in lk._links.items()}}

    def ref(link: str, z: complex) -> Ref:
        return index[link], z - origin[link]

    edges = {e.name: e for e in model.edges}
    start, scale = [], []
    length = _typical_length(lk)
    for d in lk._drivers:
        if d in lk._links:
            start.append(_ref_angle(lk, d))
        elif d in lk._motors:
            a, b = lk._motor_links(d)
            start.append(_ref_angle(lk, b) - _ref_angle(lk, a))
        else:
            e = edges[d]
            z = lk._xy(e.pb) - lk._xy(e.pa)
            start.append(abs(z) if e.kind == "act" else (z * e.direction.conjugate()).real)
        scale.append(1.0 if d in lk._links or d in lk._motors else length)
    points, seen = [], set()
    owners = [(GROUND, lk._ground)] + [(n, ln.points) for n, ln in lk._links.items()]
    for n, pts in owners:
        for p in pts:
            if p not in seen:
                seen.add(p)
                points.append((p, ref(n, lk._points[p])))
    slides, actuators = [], []
    for e in model.edges:
        if e.kind in ("P", "slot"):
            foot, at = ref(e.a, lk._xy(e.pa)), ref(e.b, lk._xy(e.pb))
            slides.append((e.name, foot, at, e.direction, index[e.a]))
        elif e.kind == "act":
            actuators.append((e.name, ref(e.a, lk._xy(e.pa)), ref(e.b, lk._xy(e.pb))))
    texts = []
    groups = model.groups
    for g, grp in enumerate(groups):
        after = [h.name for h in groups[g + 1 :] if _depends(groups, g, h)]
        tail = f"; {', '.join(after)} depend{'s' if len(after) == 1 else ''} on it" if after else ""
        texts.append(
            (
                f"cannot assemble: {grp.name} does not close at this input{tail}",
                f"singular Jacobian (toggle or dead point) of {grp.name}: derivatives "
                f"undefined{tail}",
                f"{grp.name}{tail}",
            )
        )
    info = _Info(
        start=np.array(start, float),
        scale=np.array(scale, float),
        links=tuple((n, index[n], _ref_angle(lk, n)) for n in lk._links),
        points=tuple(points),
        cgs=tuple((n, ref(n, _cg_drawn(lk, ln))) for n, ln in lk._links.items()),
        slides=tuple(slides),
        actuators=tuple(actuators),
        group_links=tuple(tuple(index[n] for n in grp.links) for grp in groups),
        texts=tuple(texts),
        angle_drivers=frozenset(d for d in lk._drivers if d in lk._links or d in lk._motors),
    )
    _check_drawing(model.program, info, groups)
    model.cache["sweep"] = info
    return info


def _depends(groups, g: int, h) -> bool:
    """Whether group ``h`` uses (directly or through others) the links of group ``g``."""
    reach = set(groups[g].links)
    for grp in groups[g + 1 :]:
        if reach & set(grp.attached):
            reach |= set(grp.links)
        if grp is h:
            return bool(reach & set(h.links))
    return False


def _check_drawing(program: Program, info: _Info, groups) -> None:
    """Refuse a drawing at a toggle (the branches meet there, so it names none)."""
    u = [[np.array([v]), 0.0, 0.0, 0.0] for v in info.start]
    _, codes = program.run(u, 1, 0, False)
    for g, code in enumerate(codes[:, 0]):
        if code != OK:
            raise ModelError(
                "the drawing is at a toggle (two links in line), where the mechanism's "
                f"branches meet, so it cannot say which one to follow ({groups[g].name}): "
                "draw it in a pose away from the toggle"
            )


def _path(start: np.ndarray, scale: np.ndarray, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Driver values along a path drawn pose → samples, no step above :data:`STEP`.

    Returns the path ``(n_drivers, m)`` and, for each path point, the sample it
    stands for (a march point: the first; an inserted point: the one before it),
    with ``-1 - k`` marking sample ``k`` itself.
    """
    n = u.shape[1]
    span = float(np.max(np.abs(u[:, 0] - start) / scale)) if u.size else 0.0
    k_march = int(np.ceil(span / STEP)) if span > 1e-12 else 0
    if n > 1:
        steps = np.max(np.abs(np.diff(u, axis=1)) / scale[:, None], axis=0)
        counts = np.maximum(1, np.ceil(steps / STEP).astype(int))
    else:
        counts = np.zeros(0, int)
    if k_march == 0 and not (counts > 1).any():
        return u, -1 - np.arange(n)
    parts, tags = [], []
    if k_march:
        f = np.arange(k_march) / k_march
        parts.append(start[:, None] + f * (u[:, :1] - start[:, None]))
        tags.append(np.zeros(k_march, int))
    if n > 1:
        which = np.repeat(np.arange(n - 1), counts)
        first = np.concatenate(([0], np.cumsum(counts)[:-1]))
        frac = (np.arange(which.size) - np.repeat(first, counts)) / counts[which]
        parts.append(u[:, which] + frac * (u[:, which + 1] - u[:, which]))
        tag = which.copy()
        tag[frac == 0] = -1 - which[frac == 0]
        tags.append(tag)
    parts.append(u[:, -1:])
    tags.append(np.array([-1 - (n - 1)]))
    return np.concatenate(parts, axis=1), np.concatenate(tags)


def _flat(a: Any, shape: tuple[int, ...]) -> np.ndarray:
    return np.broadcast_to(np.asarray(a, float), shape).reshape(-1)


def solve_closed(
    lk: Linkage,
    model: _Model,
    vals: dict[str, np.ndarray],
    vel: dict[str, np.ndarray] | None,
    acc: dict[str, np.ndarray],
    jrk: dict[str, np.ndarray] | None,
    shape: tuple[int, ...],
    follow: bool,
) -> LinkageMotion:
    """Solve ``lk`` group by group in closed form at every sample (see the module)."""
    info = _info(lk, model)
    drivers = tuple(lk._drivers)
    n = int(np.prod(shape))
    order = 0 if vel is None else 3 if jrk is not None else 2
    U = np.stack([_flat(vals[d], shape) for d in drivers]) if n else np.zeros((len(drivers), 0))
    rates = [[_flat(t[d], shape) for d in drivers] for t in (vel, acc, jrk) if t is not None]
    if follow and n:
        path, tags = _path(info.start, info.scale, U)
    else:
        path, tags = U, -1 - np.arange(n)
    m = path.shape[1]
    on_path = m != n
    src = np.where(tags < 0, -1 - tags, tags)
    u = []
    for i in range(len(drivers)):
        row = [path[i]]
        for k in range(3):
            if k < len(rates):
                row.append(rates[k][i][src] if on_path else rates[k][i])
            else:
                row.append(np.zeros(m))
        u.append(row)
    st, codes = model.program.run(u, m, order, follow)
    if on_path:
        take = np.flatnonzero(tags < 0)
        _select(st, take)
        codes = codes[:, take]
        st.reasons = {g: r[take] for g, r in st.reasons.items()}
    ok, reason = _flags(st, codes, model, info, n)
    for g in np.flatnonzero((codes == NO_ASSEMBLY).any(axis=1)):
        where = _reach(lk, model, info, int(g))
        if where:
            mine = reason == info.texts[g][0]
            reason[mine] = f"{info.texts[g][0]} ({where})"
    return _motion(lk, st, info, vals, shape, ok, reason, order)


def _select(st: State, take: np.ndarray) -> None:
    """Keep the samples ``take`` of every array of the state."""
    st.n = take.size
    for table in (st.O, st.E, st.ang, *st.lin, *st.rot):
        for i, v in enumerate(table):
            if np.ndim(v):
                table[i] = v[take]


def _pos_ok(model: _Model, codes: np.ndarray, g: int) -> np.ndarray:
    """Where group ``g`` and every group it depends on are placed."""
    bad = codes == NO_ASSEMBLY
    for h, dep in enumerate(model.program.deps[: g + 1]):
        for d in dep:
            bad[h] |= bad[d]
    return ~bad[g]


def _reach(lk: Linkage, model: _Model, info: _Info, g: int) -> str:
    """Where group ``g`` closes, as the range of the driver — for one angle driver.

    The closed forms are evaluated over a full turn of the driver (from the
    drawn value) and each change of assembly refined by bisection.
    """
    key = f"reach {g}"
    if key in model.cache:
        return model.cache[key]  # type: ignore[return-value]
    from .program import General

    text = ""
    steps = model.program.steps[: g + 1]
    driver = lk._drivers[0]
    if (
        len(lk._drivers) == 1
        and driver in info.angle_drivers
        and not any(isinstance(s, General) for s in steps)
    ):

        def closes(theta: np.ndarray) -> np.ndarray:
            u = [[theta, 0.0, 0.0, 0.0]]
            _, codes = model.program.run(u, theta.size, 0, False)
            return _pos_ok(model, codes, g)

        n = 720
        theta = info.start[0] + np.linspace(-np.pi, np.pi, n, endpoint=False)
        ok = closes(theta)
        if not ok.any():
            text = f"it closes at no value of {driver}"
        elif not ok.all():
            lo = np.flatnonzero(ok != np.roll(ok, -1))
            a, b = theta[lo], theta[lo] + 2 * np.pi / n
            inside = ok[lo]  # True: a closing edge (ok at a, not at b)
            for _ in range(44):
                mid = 0.5 * (a + b)
                same = closes(mid) == inside
                a, b = np.where(same, mid, a), np.where(same, b, mid)
            edges = 0.5 * (a + b)
            starts = edges[~inside]  # where it starts closing (going up)
            ends = edges[inside]
            if ok[0] and ok[-1]:  # the range that straddles −180° + drawn
                ends = np.roll(ends, -1) if ends.size else ends
            spans = []
            for s0 in starts:
                later = ends[(ends - s0) % (2 * np.pi) > 0]
                e0 = min(later, key=lambda e: (e - s0) % (2 * np.pi)) if later.size else s0
                spans.append((s0, s0 + (e0 - s0) % (2 * np.pi)))
            parts = [f"[{np.degrees(x):.5g}°, {np.degrees(y):.5g}°]" for x, y in sorted(spans)]
            text = f"it closes for {driver} in " + " and ".join(parts)
    model.cache[key] = text
    return text


def _flags(st: State, codes: np.ndarray, model: _Model, info: _Info, n: int):
    """Propagate each group's status to the groups depending on it; NaN what is undefined."""
    deps = model.program.deps
    pos_bad = codes == NO_ASSEMBLY
    rate_bad = codes != OK
    for g, dep in enumerate(deps):
        for h in dep:
            pos_bad[g] |= pos_bad[h]
            rate_bad[g] |= rate_bad[h]
    for g, links in enumerate(info.group_links):
        pb, rb = pos_bad[g], rate_bad[g]
        if not rb.any():
            continue
        for i in links:
            if pb.any():
                st.O[i] = np.where(pb, np.nan, st.O[i])
                st.E[i] = np.where(pb, np.nan, st.E[i])
                st.ang[i] = np.where(pb, np.nan, st.ang[i])
            for k in range(1, st.order + 1):
                st.lin[k][i] = np.where(rb, np.nan, st.lin[k][i])
                st.rot[k][i] = np.where(rb, np.nan, st.rot[k][i])
    ok = ~rate_bad.any(axis=0) if len(deps) else np.ones(n, bool)
    reason = np.full(n, "", dtype=object)
    for g in range(len(deps) - 1, -1, -1):
        if g in st.reasons:  # a general group: the loop core's reason, naming the group
            bad = codes[g] != OK
            if bad.any():
                own = st.reasons[g][bad]
                reason[bad] = [f"{r or 'cannot assemble'} ({info.texts[g][2]})" for r in own]
            continue
        for code, text in ((NO_ASSEMBLY, info.texts[g][0]), (SINGULAR, info.texts[g][1])):
            reason[codes[g] == code] = text
    return ok, reason


def _motion(
    lk: Linkage,
    st: State,
    info: _Info,
    vals: dict[str, np.ndarray],
    shape: tuple[int, ...],
    ok: np.ndarray,
    reason: np.ndarray,
    order: int,
) -> LinkageMotion:
    n = st.n

    def full(v: Any) -> np.ndarray:
        return np.array(np.broadcast_to(v, (n,)), copy=True).reshape(shape)

    def table(items) -> Any:
        return _frozen({k: full(v) for k, v in items})

    ks = range(1, order + 1)
    theta = table((name, th0 + st.ang[i]) for name, i, th0 in info.links)
    rot = [table((name, st.rot[k][i]) for name, i, _ in info.links) for k in ks]
    pts = [st.rates(r) for _, r in info.points]
    cgs = [st.rates(r) for _, r in info.cgs]
    points = [
        table((p, v[k]) for (p, _), v in zip(info.points, pts, strict=True))
        for k in range(order + 1)
    ]
    cg = [
        table((c, v[k]) for (c, _), v in zip(info.cgs, cgs, strict=True)) for k in range(order + 1)
    ]
    lengths = _lengths(st, info, order)
    lens = [table((name, v[k]) for name, v in lengths) for k in range(order + 1)]

    def at(seq: list, k: int) -> Any:
        return seq[k] if k < len(seq) else None

    return LinkageMotion(
        inputs=_frozen({k: full(np.ravel(np.broadcast_to(v, shape))) for k, v in vals.items()}),
        theta=theta,
        omega=at(rot, 0),
        alpha=at(rot, 1),
        points=points[0],
        point_velocity=at(points, 1),
        point_acceleration=at(points, 2),
        cg=cg[0],
        cg_velocity=at(cg, 1),
        cg_acceleration=at(cg, 2),
        lengths=lens[0],
        length_rate=at(lens, 1),
        length_acceleration=at(lens, 2),
        ok=ok.reshape(shape),
        reason=reason.reshape(shape),
        angle_drivers=info.angle_drivers,
        jerk=at(rot, 2),
        point_jerk=at(points, 3),
        cg_jerk=at(cg, 3),
        length_jerk=at(lens, 3),
        _loop=lambda: _loop_motion(lk, vals, shape, order),
    )


def _loop_motion(lk: Linkage, vals, shape, order):
    from .loopsolve import solve_loops

    n = int(np.prod(shape))
    vel = {d: 0.0 for d in vals} if order else None
    acc = {d: 0.0 for d in vals}
    return solve_loops(lk, vals, vel, acc, len(shape) <= 1 and n > 1).loop_motion


def _lengths(st: State, info: _Info, order: int) -> list[tuple[str, list[Any]]]:
    """Slider and slot displacements, actuator lengths, and their rates."""
    out = []
    for name, foot, at, u0, guide in info.slides:
        F, P = st.rates(foot), st.rates(at)
        uh = u0 * st.E[guide]
        w = [st.rot[k][guide] for k in range(1, order + 1)]
        r = [P[k] - F[k] for k in range(order + 1)]
        d = [(r[0] * np.conj(uh)).real]
        if order >= 1:
            d.append((r[1] * np.conj(uh)).real)
        if order >= 2:
            d.append((r[2] * np.conj(uh)).real + d[0] * w[0] * w[0])
        if order >= 3:
            d.append(
                (r[3] * np.conj(uh)).real + 3.0 * d[1] * w[0] * w[0] + 3.0 * d[0] * w[0] * w[1]
            )
        out.append((name, d))
    for name, start, end in info.actuators:
        S, T = st.rates(start), st.rates(end)
        r = [T[k] - S[k] for k in range(order + 1)]
        L = np.abs(r[0])
        e = r[0] / L
        out_l = [L]
        if order >= 1:
            p1 = (r[1] * np.conj(e)).imag / L
            out_l.append((r[1] * np.conj(e)).real)
        if order >= 2:
            p2 = ((r[2] * np.conj(e)).imag - 2.0 * out_l[1] * p1) / L
            out_l.append((r[2] * np.conj(e)).real + L * p1 * p1)
        if order >= 3:
            out_l.append((r[3] * np.conj(e)).real + 3.0 * out_l[1] * p1 * p1 + 3.0 * L * p1 * p2)
        out.append((name, out_l))
    return out
