"""Checks of refined four-bars: defects, Grashof's change point, copies and distinct results.

Each refined fit is checked by the four-bar's own code
(:class:`~machdyn.synthesis.PlacedFourBar`): one circuit (by construction),
branch (no toggle between targets), order, Grashof/crank requirement and
minimum transmission angle; fits a hair past Grashof's change point are moved
onto it; copies of one linkage are dropped and the survivors thinned to
distinct linkages. Used by :mod:`~machdyn.synthesis.atlas_path` and
:mod:`~machdyn.synthesis.sixbar_path`.
"""

from __future__ import annotations

from itertools import pairwise

import numpy as np

from ..errors import InputError
from ..fourbar import FourBar, positions
from .path import PathSynthesis, _mu_min
from .placed import PlacedFourBar
from .refine import refine

__all__: list[str] = []


def _checked(fit, pts, timing, closed, crank, mu_min, tolerance) -> PathSynthesis | None:
    """The refined linkage as a PathSynthesis, checked by the four-bar's own code."""
    r1, r2, r3, r4, p, delta, ox, oy, theta1 = fit.x
    try:
        fb = FourBar(r1, r2, r3, r4, coupler=(p, delta))
    except InputError:
        return None
    except Exception:  # AssemblyError: lengths that cannot form a four-bar
        return None
    branches = np.unique(fit.branch)
    placed = PlacedFourBar(
        fb, complex(ox, oy), float(theta1), int(np.sign(np.sum(fit.branch)) or 1)
    )
    theta = np.mod(fit.theta, 2 * np.pi)
    P = np.empty(pts.size, dtype=complex)
    ok = np.ones(pts.size, dtype=bool)
    for b in branches:  # the four-bar's own solver, on each target's assembly
        sel = fit.branch == b
        other = PlacedFourBar(fb, placed.O2, placed.theta1, int(b))
        _, _, P[sel], ok[sel] = other.pose(theta[sel])
    distance = np.where(ok, np.abs(P - pts), np.inf)
    cls = fb.classification  # (classify(*fb.lengths), made by FourBar)
    is_crank = 2 in cls.cranks
    if is_crank:  # over a turn
        dense = np.linspace(0.0, 2 * np.pi, 720, endpoint=False)
    else:  # over the input's travel from the first target to the last, through the others
        travel = np.unwrap(fit.theta)
        dense = np.concatenate([np.linspace(a, b, 60) for a, b in pairwise(travel)])
    # (where the linkage assembles: the mask of placed.pose, without its points)
    okd = positions(*fb.lengths, dense, placed.branch)[2]
    lengths = {k: np.array([v]) for k, v in zip(("r1", "r2", "r3", "r4"), fb.lengths, strict=True)}
    mu = float(_mu_min(lengths, dense, okd[None, :])[0])
    in_order = _in_order(theta, closed, timing)
    defects = []
    if crank and not is_crank:
        defects.append(f"link 2 is not a full-turn crank ({cls.code})")
    if branches.size > 1:
        defects.append("branch defect: the linkage must pass a toggle between targets")
    if mu < mu_min - np.radians(0.5):
        defects.append(f"transmission angle falls to {np.degrees(mu):.1f} deg")
    if not in_order:
        defects.append("order defect: the coupler point meets the targets out of order")
    if not np.all(ok):
        defects.append("the linkage cannot be assembled at some target")
    if tolerance is not None:
        far = np.flatnonzero(~(distance <= tolerance))
        if far.size:
            defects.append(f"targets {[int(i) + 1 for i in far]} are farther than {tolerance:g}")
    return PathSynthesis(
        linkage=placed,
        targets=pts,
        theta2=theta,
        distance=distance,
        barker_class=cls.code,
        is_crank=is_crank,
        mu_min=mu,
        in_order=in_order,
        objective=fit.rms,
        defects=tuple(defects),
    )


#: Steps of the refinement along a change point (see _onto_grashof).
GRASHOF_NFEV = 60


def _grashof_excess(x) -> float:
    """``s + l − p − q`` of the lengths ``x[:4]`` (positive: not Grashof)."""
    srt = np.sort(np.asarray(x[:4], float))
    return float(srt[0] + srt[3] - srt[1] - srt[2])


def _onto_grashof(fit, pts, options=None):
    """A fit that breaks Grashof's condition by a hair, moved onto the change point.

    The refinement holds link 2 a crank by a penalty, so an optimum on the
    boundary ``s + l = p + q`` (the literature's best linkages often sit there)
    ends a few millionths past it, where the four-bar check rightly finds no
    crank. The longest link is shortened by that excess (at most 1e-4 of the
    links' sum): the linkage lands on the change point, whose shortest link turns
    fully, and its coupler point moves little (near a change point, some ten times the
    excess). With the refinement's ``options``, it is then refined along the
    change point (``l = p + q − s`` held: :data:`GRASHOF_NFEV` steps of
    :func:`refine`'s Levenberg–Marquardt), kept if that lowers its misses.
    """
    from .refine import Refined, coupler_and_jacobian

    lengths = np.asarray(fit.x[:4], float)
    excess = _grashof_excess(lengths)
    near = abs(excess) <= 1e-4 * lengths.sum()
    if not near or (excess <= 0.0 and options is None):
        return fit
    x = fit.x.copy()
    onto = fit
    if excess > 0.0:
        x[int(np.argmax(lengths))] -= excess
        G = coupler_and_jacobian(x, fit.theta, fit.branch)[0]
        rms = float(np.sqrt(np.mean(np.abs(G - pts) ** 2)))
        onto = Refined(x, fit.theta, fit.branch, rms, fit.success)
    if options is None:
        return onto
    order = np.argsort(lengths)  # s, p, q, l: s + l − p − q = 0 held by one of them
    sign = np.array([1.0, -1.0, -1.0, 1.0])[np.argsort(order)]
    top = options.get("max_length")
    top = np.inf if top is None else top
    # the length solved for: the longest whose result keeps the length bound (the
    # others keep it by the refinement's bounds)
    for tied in (int(i) for i in order[::-1] if x[i] < top * (1 - 1e-9)):
        c = np.where(np.arange(4) == tied, 0.0, -sign / sign[tied])
        more = refine(x, fit.theta, fit.branch, pts, max_nfev=GRASHOF_NFEV, solver="lm",
                      tie=(tied, c), **options)  # fmt: skip
        if 0.0 < more.x[tied] <= top:
            good = _grashof_excess(more.x) <= max(_grashof_excess(x), 0.0)
            return more if good and more.rms < onto.rms else onto
    return onto


def _in_order(theta: np.ndarray, closed: bool, timing) -> bool:
    """True when the targets follow each other one way along the curve."""
    if timing is not None:
        return True
    steps = np.mod(np.diff(np.concatenate([theta, theta[:1]]) if closed else theta), 2 * np.pi)
    full = 2 * np.pi
    fwd = float(np.sum(steps))
    back = float(np.sum(np.mod(-steps, full)))
    limit = full + 1e-6
    return fwd <= limit or back <= limit


def _unique(fits: list, size: float) -> list:
    """``fits`` (best first) less the copies of one linkage (its best-converged copy stays).

    A copy is within :data:`SAME` of a better fit in every design number (lengths
    and pivot over the size, angles in radians) and on the same assemblies.
    """
    kept: list = []
    keys = None  # (the kept fits' keys, a row each: one comparison with all of them)
    for f in fits:
        key = _design_key(f, size)
        if keys is None:
            keys = np.empty((len(fits), key.size))
        m = len(kept)
        if np.all(np.max(np.abs(keys[:m] - key), axis=1) > SAME):
            keys[m] = key
            kept.append(f)
    return kept


#: Refined fits closer than this (see _unique) are one linkage.
SAME = 1e-6
#: Polished fits closer than this (see _polished) ended in one local minimum.
COPY = 1e-4


def _design_key(f, size: float) -> np.ndarray:
    """A fit's design numbers (lengths and pivot over the size, angles) and assemblies.

    The angles δ and θ1 enter as their cosines and sines: a fit and its copy a turn
    further round (θ1 and θ1 + 2π) have one key.
    """
    angles = f.x[[5, 8]]
    return np.concatenate([f.x[[0, 1, 2, 3, 4, 6, 7]] / size, np.cos(angles), np.sin(angles),
                           f.branch])  # fmt: skip


def _distinct(results: list[PathSynthesis], n: int, size: float) -> list[PathSynthesis]:
    """Up to ``n`` results whose pivots and lengths differ by more than 2 % of the size."""
    chosen: list[PathSynthesis] = []
    keys: list[np.ndarray] = []
    for r in results:
        pl = r.linkage
        key = np.array([*pl.lengths, pl.O2.real, pl.O2.imag, pl.O4.real, pl.O4.imag]) / size
        if all(np.max(np.abs(key - k)) > 0.02 for k in keys):
            chosen.append(r)
            keys.append(key)
        if len(chosen) == n:
            break
    return chosen
