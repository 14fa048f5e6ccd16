"""Solving a linkage of closed-form groups over a batch of driver values.

The program of :mod:`machdyn.linkage.program` gives every group's pose on its
drawn assembly sign at each sample independently, so no sample can land on
another branch. What a sweep adds is the *representative* of each angle:
angles are not wrapped, they run continuously along a sweep. For a 1-D sweep
(or a single pose) the program is also run along a path from the drawn pose to
the first sample and between samples further apart than :data:`STEP`, and each
angle is unwrapped along that path, as the vector-loop core's continuation
would follow it; samples solved independently (``continuation=False``) take
the angle within π of the drawn one. Which samples the drawing reaches (its
circuit) is :mod:`machdyn.linkage.circuit`'s.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import ModelError
from . import kernel
from ._common import GROUND, _ref_angle, _typical_length
from .circuit import flips, off_circuit
from .kernel import STEP, Outputs, Tables, has_general, run
from .kinematics import LinkageMotion, _cg_drawn
from .paths import _refine
from .program import NO_ASSEMBLY, OFF_BRANCH, OK, SINGULAR, Program, blank, unwrap

if TYPE_CHECKING:
    from .builder import Linkage
    from .topology import _Model


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
    tables: Tables  # the rows a run reports (moving links, points + centres, lengths)
    theta0: np.ndarray  # drawn angle of every moving link, as a column
    rows: dict[str, Any]  # names of the rows: links, points, centres of mass, lengths
    index: dict[str, dict[str, int]]  # the same names, each to its row
    point_group: np.ndarray  # per point (and centre) row: the group placing its link (-1: ground)
    length_groups: tuple[tuple[int, int], ...]  # per length: the groups of its two links


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
    cgs = [(n, ref(n, _cg_drawn(lk, ln))) for n, ln in lk._links.items()]
    refs = [r for _, r in points] + [r for _, r in cgs]
    lens_i, lens_f = [], []
    for _, foot, at, u0, guide in slides:
        lens_i += [0, foot[0], at[0], guide]
        lens_f += [foot[1].real, foot[1].imag, at[1].real, at[1].imag, u0.real, u0.imag]
    for _, s0, s1 in actuators:
        lens_i += [1, s0[0], s1[0], 0]
        lens_f += [s0[1].real, s0[1].imag, s1[1].real, s1[1].imag, 0.0, 0.0]
    tables = Tables(
        np.arange(1, len(lk._links) + 1, dtype=np.int64),
        np.array([i for i, _ in refs], np.int64),
        np.array([x for _, r in refs for x in (r.real, r.imag)], float),
        np.array(lens_i, np.int64),
        np.array(lens_f, float),
        np.array([0 if index[n] in model.program.unwrap else 1 for n in lk._links], np.int8),
        np.array([_ref_angle(lk, n) for n in lk._links], float),
        np.array(start, float),
        np.array(scale, float),
    )
    group_of = {GROUND: -1}
    for g, grp in enumerate(groups):
        for n in grp.links:
            group_of[n] = g
    by_index = {i: name for name, i in index.items()}
    edges_by = {e.name: e for e in model.edges}
    length_names = [name for name, *_ in slides] + [name for name, *_ in actuators]
    rows = {
        "links": tuple(lk._links),
        "points": tuple(p for p, _ in points),
        "cgs": tuple(lk._links),
        "lengths": tuple(length_names),
    }
    info = _Info(
        start=np.array(start, float),
        scale=np.array(scale, float),
        links=tuple((n, index[n], _ref_angle(lk, n)) for n in lk._links),
        points=tuple(points),
        cgs=tuple(cgs),
        slides=tuple(slides),
        actuators=tuple(actuators),
        group_links=tuple(tuple(index[n] for n in grp.links) for grp in groups),
        texts=tuple(texts),
        angle_drivers=frozenset(d for d in lk._drivers if d in lk._links or d in lk._motors),
        tables=tables,
        theta0=np.array([_ref_angle(lk, n) for n in lk._links]).reshape(-1, 1),
        rows=rows,
        index={k: {name: i for i, name in enumerate(v)} for k, v in rows.items()},
        point_group=np.array([group_of[by_index[i]] for i, _ in refs], int),
        length_groups=tuple(
            (group_of[edges_by[n].a], group_of[edges_by[n].b]) for n in length_names
        ),
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
    counts = np.zeros(0, int)
    if n > 1:
        steps = np.abs(np.diff(u, axis=1))
        if steps.max() > STEP * scale.min():  # a step larger than STEP somewhere
            steps = np.max(steps / scale[:, None], axis=0)
            counts = np.maximum(1, np.ceil(steps / STEP).astype(int))
    if k_march == 0 and not (counts > 1).any():
        return u, -1 - np.arange(n)
    if counts.size == 0 and n > 1:
        counts = np.ones(n - 1, int)
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
    """Solve ``lk`` group by group at every sample (see the module)."""
    info = _info(lk, model)
    program = model.program
    drivers = tuple(lk._drivers)
    n = math.prod(shape)
    order = 0 if vel is None else 3 if jrk is not None else 2
    given = (vals, vel, acc, jrk)[: order + 1]
    rows = [t[name] for name in drivers for t in given]  # each driver's value and rates
    if not shape:  # one pose (an editor's call): one small array, no row-by-row copies
        col, per = [0.0] * (4 * len(drivers)), order + 1
        for r, a in enumerate(rows):
            col[4 * (r // per) + r % per] = float(a)
        U = np.array(col).reshape(-1, 1)
    else:
        U = np.zeros((4 * len(drivers), n))
        for r, a in enumerate(rows):
            row = 4 * (r // (order + 1)) + r % (order + 1)
            U[row] = a if a.ndim == 0 else a.reshape(-1) if a.shape == shape else _flat(a, shape)
    out = None
    kern = kernel.compiled_kernel(n) if program.encoded is not None else None
    if kern is not None:  # the compiled kernel: the whole sweep in one call
        out = kernel.run_compiled(kern, program, info.tables, U, order, follow and n > 0)
    if out is None:
        out = (
            _follow(program, info, U, order)
            if follow and n
            else run(program, info.tables, U, order, False)
        )
    for other, mask in flips(lk, model, info, U[0], follow and n > 0):  # past change points
        _merge(out, run(other, info.tables, U[:, mask], order, False), mask, info, follow)
    codes = out.codes
    if any((r == OFF_BRANCH).any() for r in out.reasons.values()):
        codes = codes.copy()  # outside the drawn range, a pose on the other branch is away too
        for g, r in out.reasons.items():
            codes[g, r == OFF_BRANCH] = OK
    lost = off_circuit(lk, model, info, U[0::4], codes, follow and n > 0)
    stuck = None
    if lost is not None:  # poses of the drawn groups' other circuit: not this mechanism's
        stuck = (out.codes == NO_ASSEMBLY).any(axis=1)  # groups that really do not close
        out.codes[lost[0]] = NO_ASSEMBLY
        out.clean = False
    # the usual case: every group assembled, away from toggles
    clean = out.clean if out.clean is not None else not out.codes.any()
    if clean:
        ok, reason = _clean(n)
    else:
        ok, reason = _flags(out, model, info, n)
        if stuck is None:
            stuck = (out.codes == NO_ASSEMBLY).any(axis=1)
    for g in () if clean else np.flatnonzero(stuck):
        where = _reach(lk, model, info, int(g))
        if where:
            mine = reason == info.texts[g][0]
            reason[mine] = f"{info.texts[g][0]} ({where})"
    if lost is not None:
        reason[lost[1]] = lost[2]
    return _motion(lk, out, info, vals, shape, ok, reason, order)


def _merge(out: Outputs, part: Outputs, mask: np.ndarray, info: _Info, follow: bool) -> None:
    """Put the samples ``mask`` of ``part`` (the same rows) into ``out``."""
    out.ang[:, mask], out.rot[:, mask], out.pts[:, mask] = part.ang, part.rot, part.pts
    out.lens[:, mask], out.codes[:, mask] = part.lens, part.codes
    out.clean = None
    for j in info.tables.wrapped if follow else ():  # continuous across the change point
        out.ang[j] = unwrap(out.ang[j])


def _follow(program: Program, info: _Info, U: np.ndarray, order: int) -> Outputs:
    """Run a 1-D sweep with its angles unwrapped along a path from the drawn pose.

    The compiled kernel does it all (:func:`machdyn._linkage_kernels.run`);
    otherwise the program is run along the path (:func:`_path`: the drawn pose,
    the samples, and points in between where two are further apart than
    :data:`STEP`), each angle unwrapped along it, and the samples taken.
    """
    tables = info.tables
    unwrapped = tables.wrapped
    if not unwrapped.size and not has_general(program):
        return run(program, tables, U, order, True)
    kern = kernel.compiled_kernel(U.shape[1]) if program.encoded is not None else None
    if kern is not None:
        out = kernel.run_compiled(kern, program, tables, U, order, True)
        if out is not None and out.unwrapped:
            return out
    path, tags = _path(info.start, info.scale, U[0::4])
    take = np.flatnonzero(tags < 0)
    if take.size == tags.size:  # the path is the samples
        out = run(program, tables, U, order, True)
        for j in unwrapped:
            out.ang[j] = unwrap(out.ang[j])
        return out
    src = np.where(tags < 0, -1 - tags, tags)
    P = U[:, src]
    P[0::4] = path
    out = run(program, tables, P, order, True)
    for j in unwrapped:
        out.ang[j] = unwrap(out.ang[j])
    return Outputs(
        out.ang[:, take], out.rot[:, take], out.pts[:, take], out.lens[:, take],
        out.codes[:, take], {g: r[take] for g, r in out.reasons.items()},
    )  # fmt: skip


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
    drawn value) and each change of assembly refined (:func:`_refine`).
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
            a, b = _refine(a, b, closes, inside)
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


def _flags(out: Outputs, model: _Model, info: _Info, n: int):
    """Propagate each group's status to the groups depending on it; NaN what is undefined."""
    deps = model.program.deps
    codes = out.codes
    if not codes.any():
        return np.ones(n, bool), blank(n)
    pos_bad = codes == NO_ASSEMBLY
    rate_bad = codes != OK
    for g, dep in enumerate(deps):
        for h in dep:
            pos_bad[g] |= pos_bad[h]
            rate_bad[g] |= rate_bad[h]
    nm, npt = len(info.tables.links), len(info.tables.pts_i)
    nln = len(info.tables.lens_i) // 4
    order = out.rot.shape[0] // nm if nm else 0
    for g, links in enumerate(info.group_links):
        pb, rb = pos_bad[g], rate_bad[g]
        if not rb.any():
            continue
        for i in links:
            out.ang[i - 1, pb] = np.nan
            for k in range(order):
                out.rot[k * nm + i - 1, rb] = np.nan
        for p in np.flatnonzero(info.point_group == g):
            out.pts[p, pb] = np.nan
            for k in range(1, order + 1):
                out.pts[k * npt + p, rb] = np.nan
        for q, pair in enumerate(info.length_groups):
            if g in pair:
                out.lens[q, pb] = np.nan
                for k in range(1, order + 1):
                    out.lens[k * nln + q, rb] = np.nan
    ok = ~rate_bad.any(axis=0) if len(deps) else np.ones(n, bool)
    reason = blank(n)
    for g in range(len(deps) - 1, -1, -1):
        if g in out.reasons:  # a general group: the loop core's reason, naming the group
            bad = codes[g] != OK
            if bad.any():
                own = out.reasons[g][bad]
                reason[bad] = [f"{r or 'cannot assemble'} ({info.texts[g][2]})" for r in own]
            continue
        for code, text in ((NO_ASSEMBLY, info.texts[g][0]), (SINGULAR, info.texts[g][1])):
            reason[codes[g] == code] = text
    return ok, reason


_BLANK: np.ndarray = np.empty(0, object)
_BLANK.setflags(write=False)


def _clean(n: int) -> tuple[np.ndarray, np.ndarray]:
    """``ok`` and ``reason`` of a sweep of ``n`` samples, all assembled.

    The reasons (read-only, like every array of the motion but ``ok``) are
    shared by the calls of the same ``n``: ``n`` references to ``''`` cost as
    much as solving a few hundred poses.
    """
    global _BLANK
    reason = _BLANK
    if len(reason) != n:
        reason = blank(n)
        reason.setflags(write=False)
        _BLANK = reason
    return np.ones(n, bool), reason


def _motion(
    lk: Linkage,
    out: Outputs,
    info: _Info,
    vals: dict[str, np.ndarray],
    shape: tuple[int, ...],
    ok: np.ndarray,
    reason: np.ndarray,
    order: int,
) -> LinkageMotion:
    rows, index = info.rows, info.index
    nm, npt, nln = len(rows["links"]), len(rows["points"]), len(rows["lengths"])
    links, points, lengths = index["links"], index["points"], index["lengths"]
    for a in (out.ang, out.rot, out.pts, out.lens, reason):
        a.setflags(write=False)  # every view below inherits it
    R = out.rot.reshape(order, nm, *shape)
    P = out.pts.reshape(order + 1, len(info.tables.pts_i), *shape)
    L = out.lens.reshape(order + 1, nln, *shape)
    # one loop for the four tables (an editor's one-pose call pays for every microsecond)
    rot: list[Any] = [None] * 4  # rates not computed stay None
    pts, cgs, lens = rot[:], rot[:], rot[:]
    for k in range(order + 1):
        if k:
            rot[k - 1] = _Rows(links, R, k - 1)
        pts[k] = _Rows(points, P, k)
        cgs[k] = _Rows(links, P, k, npt)
        lens[k] = _Rows(lengths, L, k)
    inputs = {}
    for k, v in vals.items():
        a = np.array(v if v.shape == shape else np.broadcast_to(v, shape))
        a.setflags(write=False)
        inputs[k] = a
    return LinkageMotion._make(
        inputs=MappingProxyType(inputs),
        theta=_Rows(links, out.ang.reshape(1, nm, *shape), 0),
        omega=rot[0],
        alpha=rot[1],
        points=pts[0],
        point_velocity=pts[1],
        point_acceleration=pts[2],
        cg=cgs[0],
        cg_velocity=cgs[1],
        cg_acceleration=cgs[2],
        lengths=lens[0],
        length_rate=lens[1],
        length_acceleration=lens[2],
        ok=ok.reshape(shape),
        reason=reason.reshape(shape),
        angle_drivers=info.angle_drivers,
        jerk=rot[2],
        point_jerk=pts[3],
        cg_jerk=cgs[3],
        length_jerk=lens[3],
        _loop=lambda: _loop_motion(lk, vals, shape, order),
    )


class _Rows(Mapping):
    """A read-only mapping of names to rows of one stacked array (no copies).

    Name ``key`` is ``data[k, offset + index[key]]``; ``index`` (each name's
    row) is shared by every table of the same names, and ``data`` is
    read-only already (:func:`_motion` makes it so).
    """

    __slots__ = ("_data", "_index", "_k", "_offset")

    def __init__(self, index: dict[str, int], data: np.ndarray, k: int, offset: int = 0) -> None:
        self._index, self._data, self._k, self._offset = index, data, k, offset

    def __getitem__(self, key: str) -> np.ndarray:
        return self._data[self._k, self._offset + self._index[key]]

    def __contains__(self, key: object) -> bool:
        return key in self._index

    def __iter__(self):
        return iter(self._index)

    def __len__(self) -> int:
        return len(self._index)

    def __repr__(self) -> str:
        return f"<{len(self._index)} arrays: {', '.join(self._index)}>"


def _loop_motion(lk: Linkage, vals, shape, order):
    from .loopsolve import solve_loops

    n = int(np.prod(shape))
    vel = {d: 0.0 for d in vals} if order else None
    acc = {d: 0.0 for d in vals}
    return solve_loops(lk, vals, vel, acc, len(shape) <= 1 and n > 1).loop_motion
