"""Running a linkage's program: NumPy, the compiled kernel, or its plain-Python twin.

Every closed-form step of :mod:`machdyn.linkage.program` is encoded as a row of
integers and a row of floats (:func:`encode`), once per linkage; the kernel of
:mod:`machdyn._linkage_kernels` interprets the rows a block of samples at a time. Which
engine runs a call:

* the **compiled kernel** when :mod:`machdyn.jit` serves compiled code (its
  ``auto`` rule, ``MACHDYN_JIT=on``), over slices in threads for big batches;
* the same kernel as **plain Python** for one or two poses otherwise (an editor
  dragging a point: NumPy's cost per call would dominate);
* the **NumPy** program otherwise, and always when a group is solved by the
  vector-loop core (its time counts toward the ``auto`` rule's budget).

All three return the same stacked arrays (:class:`Outputs`): one row per link
(angles and their rates), per point and centre of mass (positions and rates),
per slider/actuator length, per group (status codes).
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass, field
from types import ModuleType

import numpy as np

from .. import jit
from .program import RPP, RPR, Crank, Dyad, Motor, PArm, Program, RArm, Slide, State

#: Batches of at most this many poses go to the plain-Python twin (when not compiled).
SCALAR_MAX = 2
#: Largest step of a driver (radians; lengths in units of the typical link length)
#: between two points of the path along which a sweep's angles are unwrapped.
STEP = 0.2

_compiled: ModuleType | None = None
_failed = ""


@dataclass
class Outputs:
    """Stacked results of a run over ``n`` samples (rows as described in the module)."""

    ang: np.ndarray  # (n_moving, n): angles (wrapped where from atan2, unless unwrapped)
    rot: np.ndarray  # (order * n_moving, n): angular velocity, acceleration, jerk
    pts: np.ndarray  # ((order + 1) * n_points, n) complex: points then centres of mass
    lens: np.ndarray  # ((order + 1) * n_lengths, n)
    codes: np.ndarray  # (n_groups, n) int8
    reasons: dict[int, np.ndarray]  # a general group's reasons (the loop core's words)
    unwrapped: bool = False  # the angles already follow the sweep's path (compiled kernel)
    clean: bool | None = None  # every status code OK (None: not counted)


@dataclass
class Tables:
    """What a run reports (moving links, points and centres of mass, lengths) and how."""

    links: np.ndarray  # link indices
    pts_i: np.ndarray  # link of each point
    pts_f: np.ndarray  # drawn offsets, re/im interleaved
    lens_i: np.ndarray  # per length: kind (0 slide, 1 actuator), link a, link b, guide
    lens_f: np.ndarray  # per length: offset on a, offset on b, direction (re/im)
    exact: np.ndarray  # per link row: 1 if its angle is exact (a driver's), 0 if from atan2
    theta0: np.ndarray  # per link row: its drawn angle
    start: np.ndarray  # drawn value of every driver
    scale: np.ndarray  # per driver: 1 (an angle) or the typical length
    lists: tuple[list, ...] = ()  # the same as Python lists, for the plain-Python twin
    wrapped: np.ndarray = field(default_factory=lambda: np.zeros(0, int))  # rows from atan2
    # for the compiled kernel, per program run with these tables (:func:`pack`)
    packed: dict[int, tuple[Program, np.ndarray, np.ndarray]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.lists = tuple(
            a.tolist() for a in (self.links, self.pts_i, self.pts_f, self.lens_i, self.lens_f)
        )
        self.wrapped = np.flatnonzero(self.exact == 0)


@dataclass
class Encoded:
    """A program's steps as flat rows (``NI`` integers and ``NF`` floats each)."""

    pi: np.ndarray
    pf: np.ndarray
    ns: int
    lists: tuple[list, list] = ([], [])


def _c(z: complex) -> list[float]:
    return [z.real, z.imag]


def _arm(arm: RArm | PArm) -> tuple[list[int], list[float]]:
    if isinstance(arm, RArm):
        ints = [0, arm.centre[0], arm.link, arm.driver]
        return ints, [*_c(arm.centre[1]), *_c(arm.r), *_c(arm.u0), arm.length]
    return [1, arm.known, arm.link, -1], [*_c(arm.G[1]), *_c(arm.r), *_c(arm.u0), 0.0]


def encode(program: Program) -> Encoded | None:
    """The program's steps as integer and float rows (None if a group is general)."""
    from ._scalar import NF, NI

    ints: list[list[int]] = []
    floats: list[list[float]] = []
    for g, step in zip(program.group_of_step, program.steps, strict=True):
        if isinstance(step, Crank):
            i = [0, step.link, step.pin[0], step.driver]
            f = [*_c(step.pin[1]), *_c(step.r), step.theta0]
        elif isinstance(step, Motor):
            i = [1, step.link, step.pin[0], step.source, step.driver]
            f = [*_c(step.pin[1]), *_c(step.r), step.sign, step.phi0]
        elif isinstance(step, Slide):
            i = [2, step.link, step.known, step.foot[0], step.at[0], step.driver]
            i.append(1 if step.moving_block else 0)
            f = [*_c(step.foot[1]), *_c(step.at[1]), *_c(step.u0)]
        elif isinstance(step, Dyad):
            i1, f1 = _arm(step.arm1)
            i2, f2 = _arm(step.arm2)
            i, f = [3, *i1, *i2], [*f1, *f2, step.sign]
        elif isinstance(step, RPR):
            i = [4, step.link1, step.A[0], step.C[0], step.link2]
            f = [*_c(step.A[1]), *_c(step.r1), *_c(step.C[1]), *_c(step.r2), step.e]
            f += [*_c(step.u0), step.sign]
        elif isinstance(step, RPP):
            i = [5, step.link1, step.A[0], step.known, step.link2]
            f = [*_c(step.A[1]), *_c(step.r1), *_c(step.G[1]), *_c(step.u1), *_c(step.u2)]
            f += _c(step.r2)
        else:
            return None
        row = [i[0], g, *i[1:]]
        ints.append(row + [0] * (NI - len(row)))
        floats.append(f + [0.0] * (NF - len(f)))
    pi = np.array(ints, np.int64).reshape(-1)
    pf = np.array(floats, float).reshape(-1)
    return Encoded(pi, pf, len(ints), (pi.tolist(), pf.tolist()))


def scalar_kernel() -> ModuleType:
    """The single-pose program in plain Python (:mod:`machdyn.linkage._scalar`)."""
    from . import _scalar

    return _scalar


def _kernel_failure(exc: Exception) -> bool:
    """Whether ``exc`` is the compiled kernel failing (not, say, a signal's timeout)."""
    own = (ArithmeticError, LookupError, RuntimeError, TypeError, ValueError, MemoryError,
           AssertionError, ImportError, OSError)  # fmt: skip
    return isinstance(exc, own) or type(exc).__module__.startswith("numba")


def compiled_kernel(n: int) -> ModuleType | None:
    """The compiled kernels if the jit rule serves a call of ``n`` poses with them."""
    global _compiled, _failed
    if _failed or jit.kernels(n) is None:
        return None
    if _compiled is None:
        try:
            from .. import _linkage_kernels as module

            jit.warm(module)
        except Exception as exc:  # an optional accelerator: NumPy serves
            if not _kernel_failure(exc):
                raise
            _failed = f"{type(exc).__name__}: {exc}"
            return None
        _compiled = module
    return _compiled


def run(program: Program, tables: Tables, U: np.ndarray, order: int, follow: bool) -> Outputs:
    """Run ``program`` at the samples ``U`` (rows: each driver's value and three rates).

    ``follow``: the samples are a path (NumPy: general groups are continued
    along it); the compiled kernel then also unwraps the angles along the
    sweep's path from the drawn pose (``Outputs.unwrapped``).
    """
    n = U.shape[1]
    enc = program.encoded
    if enc is not None:
        kern = compiled_kernel(n)
        if kern is not None:
            out = run_compiled(kern, program, tables, U, order, follow)
            if out is not None:
                return out
        elif n <= SCALAR_MAX:
            return _run_scalar(program, enc, tables, U, order)
    t0 = time.perf_counter()
    out = _run_numpy(program, tables, U, order, follow)
    jit.charge(time.perf_counter() - t0)
    return out


def _empty(program: Program, tables: Tables, n: int, order: int) -> Outputs:
    nm, npt, nln = len(tables.links), len(tables.pts_i), len(tables.lens_i) // 4
    return Outputs(
        np.empty((nm, n)),
        np.empty((order * nm, n)),
        np.empty(((order + 1) * npt, n), complex),
        np.empty(((order + 1) * nln, n)),
        np.empty((len(program.deps), n), np.int8),
        {},
    )


#: Batches of at least this many poses are split over threads (:func:`machdyn.jit.run`).
THREADED = 20_000


def pack(program: Program, tables: Tables) -> tuple[np.ndarray, np.ndarray]:
    """The program and the tables in one integer and one float array (the kernel's layout).

    Integers: a header of ``NH`` entries (steps, links, rows of angles,
    points and lengths, then where each part ends, the number of groups),
    the step rows, the link rows, their exactness, each point's link, each
    length's links. Floats: the step rows, drawn angles, point offsets, length
    offsets, the drivers' drawn values and scales, and the path's step.
    """
    hit = tables.packed.get(id(program))
    if hit is not None and hit[0] is program:  # (the program kept: its id is not reused)
        return hit[1], hit[2]
    enc = program.encoded
    t = tables
    ints = [enc.pi, t.links, t.exact.astype(np.int64), t.pts_i, t.lens_i]
    floats = [enc.pf, t.theta0, t.pts_f, t.lens_f, t.start, t.scale, np.array([STEP])]
    nh = 17
    ends_i = np.cumsum([nh] + [len(a) for a in ints])[1:]
    ends_f = np.cumsum([len(a) for a in floats])[:-1]
    head = [enc.ns, program.n_links, len(t.links), len(t.pts_i), len(t.lens_i) // 4,
            *ends_i, *ends_f, len(program.deps)]  # fmt: skip
    ii = np.concatenate([np.array(head, np.int64), *[np.asarray(a, np.int64) for a in ints]])
    ff = np.concatenate([np.asarray(a, float) for a in floats])
    tables.packed[id(program)] = (program, ii, ff)
    return ii, ff


def run_compiled(kern, program, tables, U, order, follow) -> Outputs | None:
    """The compiled kernel over ``U`` (None, and NumPy serves from then on, if it fails)."""
    global _failed
    n = U.shape[1]
    nm, npt, nln = len(tables.links), len(tables.pts_i), len(tables.lens_i) // 4
    F = np.empty(((order + 1) * (nm + nln), n))
    pts = np.empty(((order + 1) * npt, n), complex)
    codes = np.empty((len(program.deps), n), np.int8)
    out = Outputs(F[:nm], F[nm : (order + 1) * nm], pts, F[(order + 1) * nm :], codes, {})
    if n == 0:  # nothing to do (and empty arrays would make numba compile another signature)
        out.unwrapped = True
        return out
    ii, ff = pack(program, tables)
    Pf = pts.view(float)
    # One layout for the kernel: U[:, mask] (the samples past a change point) is
    # F-ordered, and numba would compile the whole kernel again for it (a second
    # half-minute compile from an empty cache); the values read are the same.
    U = np.ascontiguousarray(U)
    try:
        if n < THREADED:
            out.clean = kern.run(0, n, ii, ff, U, order, F, Pf, codes, follow) == 0
        else:  # (jit.run takes a nonzero return for a failure: the count is not returned)
            if not jit.run(lambda sl: 0 * kern.run(sl.start, sl.stop, ii, ff, U, order, F, Pf,
                                                   codes, False), n):  # fmt: skip
                raise RuntimeError(jit.reason() or "the compiled linkage kernel failed")
            if follow:
                kern.run(0, 0, ii, ff, U, order, F, Pf, codes, True)
        out.unwrapped = bool(follow)
    except Exception as exc:  # NumPy is the reference: it serves from now on
        if not _kernel_failure(exc):
            raise
        _failed = f"{type(exc).__name__}: {exc}"
        warnings.warn(
            f"the compiled linkage kernel failed ({_failed}); NumPy serves",
            RuntimeWarning,
            stacklevel=4,
        )
        return None
    return out


def _run_scalar(program, enc, tables, U, order) -> Outputs:
    k = scalar_kernel()
    n = U.shape[1]
    out = _empty(program, tables, n, order)
    nl = program.n_links
    links, pts_i, pts_f, lens_i, lens_f = tables.lists
    pi, pf = enc.lists
    for i in range(n):
        Og, E, A = [0j] * nl, [1 + 0j] * nl, [0.0] * nl
        V, W = [0j] * (order * nl), [0.0] * (order * nl)
        codes = [0] * len(program.deps)
        k.sample(pi, pf, enc.ns, U[:, i].tolist(), order, Og, E, A, V, W, nl, codes)
        out.codes[:, i] = codes
        k.outputs(i, Og, E, A, V, W, nl, order, links, pts_i, pts_f, lens_i, lens_f,
                  out.ang, out.rot, out.pts, out.lens)  # fmt: skip
    out.ang += tables.theta0[:, None]
    return out


def _run_numpy(
    program: Program, tables: Tables, U: np.ndarray, order: int, follow: bool
) -> Outputs:
    n = U.shape[1]
    u = [[U[4 * d + k] for k in range(4)] for d in range(U.shape[0] // 4)]
    st, codes = program.run(u, n, order, follow)
    out = _empty(program, tables, n, order)
    nm = len(tables.links)
    for j, i in enumerate(tables.links):
        out.ang[j] = st.ang[i] + tables.theta0[j]
        for k in range(order):
            out.rot[k * nm + j] = st.rot[k + 1][i]
    npt = len(tables.pts_i)
    for p, i in enumerate(tables.pts_i):
        r = complex(tables.pts_f[2 * p], tables.pts_f[2 * p + 1])
        for k, v in enumerate(st.rates((int(i), r))):
            out.pts[k * npt + p] = v
    _lengths(st, tables, order, out.lens)
    out.codes[:] = codes
    out.reasons.update(st.reasons)
    return out


def _lengths(st: State, tables: Tables, order: int, into: np.ndarray) -> None:
    """Slider and slot displacements, actuator lengths, and their rates (NumPy)."""
    nln = len(tables.lens_i) // 4
    for q in range(nln):
        kind, a, b, guide = (int(x) for x in tables.lens_i[4 * q : 4 * q + 4])
        f = tables.lens_f[6 * q : 6 * q + 6]
        S = st.rates((a, complex(f[0], f[1])))
        T = st.rates((b, complex(f[2], f[3])))
        r = [T[k] - S[k] for k in range(order + 1)]
        if kind == 0:
            uh = complex(f[4], f[5]) * st.E[guide]
            d = [(r[0] * np.conj(uh)).real]
            if order >= 1:
                d.append((r[1] * np.conj(uh)).real)
            if order >= 2:
                w = st.rot[1][guide]
                d.append((r[2] * np.conj(uh)).real + d[0] * w * w)
            if order >= 3:
                al = st.rot[2][guide]
                d.append((r[3] * np.conj(uh)).real + 3.0 * d[1] * w * w + 3.0 * d[0] * w * al)
        else:
            L = np.abs(r[0])
            with np.errstate(invalid="ignore", divide="ignore"):
                e = r[0] / L
            c = [r[k] * np.conj(e) for k in range(order + 1)]
            d = [L]
            if order >= 1:
                p1 = c[1].imag / L
                d.append(c[1].real)
            if order >= 2:
                p2 = (c[2].imag - 2.0 * d[1] * p1) / L
                d.append(c[2].real + L * p1 * p1)
            if order >= 3:
                d.append(c[3].real + 3.0 * d[1] * p1 * p1 + 3.0 * L * p1 * p2)
        for k in range(order + 1):
            into[k * nln + q] = d[k]


def has_general(program: Program) -> bool:
    """Whether a group is solved by the vector-loop core."""
    return program.encoded is None
