"""Path generation by optimisation: a four-bar whose coupler point passes near target points.

Graphical path synthesis (the notes' Ch. 3, Norton sec. 3.6) only handles a
few points; for N points the problem becomes a search (Norton ch. 5,
"optimisation methods"). Each candidate is 10 numbers — the four lengths, the
coupler point ``(p, δ)``, the placement ``O2, θ1`` and the assembly — and
scipy's differential evolution evolves a population of them. The population
is evaluated *at once* by :func:`~machdyn.synthesis.atlas.coupler_points`
(a 2-D candidate × angle array), which is what makes the search fast.

Objective (dimensionless, with ``L`` the size of the target set):

* without timing: the mean over targets of the squared distance to the
  nearest point of the candidate's coupler curve, over ``L²``;
* with prescribed timing (input angles ``θ2_k = θ2_0 + Δ_k``, ``θ2_0`` free):
  the mean squared distance of the coupler point at ``θ2_k`` to target k,
  where the placement ``O2, θ1`` is solved in closed form for each candidate
  (a complex Procrustes fit), so only 8 numbers are searched;

plus penalties for not being a full-turn crank on one assembly (the fraction
of input angles that cannot be assembled) and for a transmission angle below
``mu_min``. The result is checked for Grashof type, circuit and transmission
angle, and targets that are not reached within ``tolerance`` are reported.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import (
    boolean,
    count,
    finite_array,
    finite_scalar,
    in_range,
    integer,
    point,
    positive,
)
from ..classify import classify
from ..errors import AssemblyError, InputError
from ..fourbar import FourBar
from .atlas import _kernel
from .geometry import as_points
from .placed import PlacedFourBar

__all__ = ["PathSynthesis", "path_objective", "synthesize_path"]

#: Weight of the fraction of unassembled input angles in the objective.
_W_ASSEMBLY = 10.0
#: Weight of the squared transmission-angle shortfall (radians²).
_W_MU = 1.0
#: How many of the best candidates the final local search starts from.
_POLISH_STARTS = 3
#: The transmission-angle penalty is soft: a shortfall below this (0.5°) is not a defect.
_MU_SLACK = np.radians(0.5)


@dataclass(frozen=True, eq=False)
class PathSynthesis:
    """A four-bar found by path synthesis, with its checks.

    Attributes
    ----------
    linkage : PlacedFourBar
        The linkage placed in the plane; its coupler point traces the path.
    targets : ndarray of complex
        The target points.
    theta2 : ndarray
        Input angle (local, radians) at which the coupler point is closest to
        each target (the prescribed ones when timing is given).
    distance : ndarray
        Distance from each target to the coupler curve (or timed point).
    barker_class : str
        Class of the result (the search asks for a Grashof crank input).
    is_crank : bool
        True when link 2 turns fully on the assembly used.
    mu_min : float
        Smallest transmission angle over the motion, radians: a full turn of a
        crank input (for :func:`path_from_atlas`, a rocking input's travel from the
        first target to the last).
    in_order : bool
        True when the coupler point meets the targets in their order along
        the curve (one way round).
    objective : float
        Final value of the objective.
    defects : tuple of str
        What is wrong with the result (empty if nothing).
    """

    linkage: PlacedFourBar
    targets: np.ndarray
    theta2: np.ndarray
    distance: np.ndarray
    barker_class: str
    is_crank: bool
    mu_min: float
    in_order: bool
    objective: float
    defects: tuple[str, ...]

    @property
    def ok(self) -> bool:
        """True when no defect was found."""
        return not self.defects

    @property
    def fourbar(self) -> FourBar:
        """The linkage in its own frame."""
        return self.linkage.fourbar

    def curve(self, n: int = 360) -> np.ndarray:
        """The coupler curve in the plane (``n`` input angles over a turn)."""
        n = count("n", n, minimum=2, bytes_each=96)
        _, _, P, ok = self.linkage.pose(np.linspace(0.0, 2 * np.pi, n, endpoint=False))
        return P[ok]

    def plot(self, ax=None):
        """Plot the coupler curve and the targets (matplotlib imported lazily)."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots()
        c = self.curve()
        ax.plot(c.real, c.imag, lw=1.0, label="coupler curve")
        ax.plot(self.targets.real, self.targets.imag, "o", label="targets")
        pivots = np.array([self.linkage.O2, self.linkage.O4])
        ax.plot(pivots.real, pivots.imag, "k^", label="fixed pivots")
        ax.set_aspect("equal")
        ax.legend()
        return ax


def _decode(x: np.ndarray, scale: float, centre: complex) -> dict[str, np.ndarray]:
    """Unpack design vectors (rows of ``x``, shape (10, S)) into linkage parameters."""
    r1, r2, r3, r4, p = (x[i] * scale for i in range(5))
    delta, ox, oy, theta1, branch = x[5], x[6], x[7], x[8], x[9]
    o2 = centre + scale * (ox + 1j * oy)
    return dict(
        r1=r1,
        r2=r2,
        r3=r3,
        r4=r4,
        p=p,
        delta=delta,
        O2=o2,
        theta1=theta1,
        branch=np.where(branch >= 0.0, 1.0, -1.0),
    )


def _decode_timed(x: np.ndarray, scale: float) -> dict[str, np.ndarray]:
    """Unpack timed design vectors (rows: r1..r4, p, delta, branch, θ2_0; shape (8, S))."""
    r1, r2, r3, r4, p = (x[i] * scale for i in range(5))
    return dict(
        r1=r1,
        r2=r2,
        r3=r3,
        r4=r4,
        p=p,
        delta=x[5],
        branch=np.where(x[6] >= 0.0, 1.0, -1.0),
        theta20=x[7],
    )


def _procrustes(
    q: dict[str, np.ndarray], timing: np.ndarray, targets: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Best placement of each candidate for timed targets, in closed form.

    With the candidate's coupler points ``Q_k`` (own frame) at ``θ2_0 + Δ_k``,
    the rotation ``r = e^{jθ1}`` and the pivot ``O2`` minimising
    ``Σ |T_k − O2 − r Q_k|²`` are ``r = h/|h|`` with ``h = Σ conj(Q_k − Q̄)(T_k − T̄)``
    and ``O2 = T̄ − r Q̄`` (orthogonal Procrustes in complex form). So the
    search never needs the placement as variables.

    Returns ``rot, O2, d2, ok``: shapes (S,), (S,), (S, K), (S, K).
    """
    th = q["theta20"][:, None] + timing[None, :]
    local, ok = _points_at(q, th)
    local = np.where(ok, local, 0.0)
    qm = local.mean(axis=1)
    tm = targets.mean()
    h = np.sum(np.conj(local - qm[:, None]) * (targets - tm)[None, :], axis=1)
    mag = np.abs(h)
    rot = np.where(mag > 0.0, h / np.where(mag > 0.0, mag, 1.0), 1.0)
    o2 = tm - rot * qm
    resid = targets[None, :] - (o2[:, None] + rot[:, None] * local)
    return rot, o2, resid.real**2 + resid.imag**2, ok


_BOUNDS = [
    (0.1, 3.0),  # r1 / L
    (0.05, 1.5),  # r2 / L
    (0.1, 3.0),  # r3 / L
    (0.1, 3.0),  # r4 / L
    (0.0, 3.0),  # p / L
    (-np.pi, np.pi),  # delta
    (-2.0, 2.0),  # O2 x offset / L
    (-2.0, 2.0),  # O2 y offset / L
    (-np.pi, np.pi),  # theta1
    (-1.0, 1.0),  # branch (sign)
]
#: With timing, the placement is solved in closed form: lengths, coupler, branch, θ2_0.
_BOUNDS_TIMED = [*_BOUNDS[:6], (-1.0, 1.0), (-np.pi, np.pi)]


def path_objective(
    x: np.ndarray,
    targets: np.ndarray,
    *,
    timing: np.ndarray | None = None,
    n: int = 120,
    mu_min: float = np.radians(30.0),
    scale: float | None = None,
    centre: complex | None = None,
) -> np.ndarray:
    """The path-synthesis objective for many design vectors at once.

    Parameters
    ----------
    x : ndarray, shape (10,) or (10, S); with timing (8,) or (8, S)
        Design vectors: ``r1, r2, r3, r4, p`` (over the targets' size), ``δ``,
        the placement ``O2`` (offset over the size) and ``θ1``, the branch sign;
        with timing ``r1 … δ``, the branch sign and ``θ2_0`` (the placement is
        then solved in closed form, see :func:`_procrustes`).
    targets : ndarray of complex, shape (K,)
        Target points.
    timing : ndarray, shape (K,), optional
        Input-angle increments ``Δ_k`` of the targets (radians).
    n : int
        Input angles per coupler curve.

    Returns
    -------
    ndarray, shape (S,)
        Objective values (lower is better; finite for every candidate).

    Examples
    --------
    The generating linkage of timed targets scores zero (lengths over the
    targets' size ``L``; branch +1; θ2_0 = 0):

    >>> from machdyn.fourbar import FourBar
    >>> known = PlacedFourBar(FourBar(5, 2, 5, 4, coupler=(3.0, 0.6)), 1 + 2j, 0.3, 1)
    >>> theta2 = np.radians([0, 90, 180, 270])
    >>> targets = known.pose(theta2)[2]
    >>> L = float(np.max(np.abs(targets - targets.mean())))
    >>> x = np.array([5 / L, 2 / L, 5 / L, 4 / L, 3 / L, 0.6, 1.0, 0.0])
    >>> bool(path_objective(x, targets, timing=theta2) < 1e-20)
    True
    """
    x = finite_array("x", x)
    size = 10 if timing is None else 8
    if x.ndim not in (1, 2) or x.shape[0] != size:
        raise InputError("x", f"must have shape ({size},) or ({size}, S), got {x.shape}")
    single = x.ndim == 1
    x = x.reshape(x.shape[0], -1)
    targets = as_points("targets", targets)
    if timing is not None:
        timing = np.ravel(finite_array("timing", timing, "radian"))
        from ..units import warn_if_degrees

        warn_if_degrees("timing", timing - timing[:1], stacklevel=3)  # degrees meant
        if timing.size != targets.size:
            raise InputError("timing", f"needs one angle per target ({targets.size})")
    mu_min = in_range("mu_min", mu_min, 0.0, 0.5 * np.pi, unit="radian")
    n = count("n", n, minimum=3, bytes_each=64 * x.shape[1])
    if targets.size < 2:
        raise InputError("targets", f"needs at least 2 points, got {targets.size}")
    scale = None if scale is None else positive("scale", scale)
    centre = None if centre is None else point("centre", centre)
    if scale is None or centre is None:
        own_scale, own_centre = _frame(targets)
        if own_scale <= 0.0:
            raise InputError("targets", "all target points coincide")
        scale = own_scale if scale is None else scale
        centre = own_centre if centre is None else centre
    theta2 = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    if timing is None:
        q = _decode(x, scale, centre)
        local, ok = _kernel(
            q["r1"], q["r2"], q["r3"], q["r4"], q["p"], q["delta"], theta2, q["branch"]
        )
        curve = q["O2"][:, None] + np.exp(1j * q["theta1"])[:, None] * local  # (S, n)
        nearest = _distance_to_polyline(curve, targets) ** 2
    else:
        q = _decode_timed(x, scale)
        _, ok = _kernel(q["r1"], q["r2"], q["r3"], q["r4"], q["p"], q["delta"], theta2, q["branch"])
        _, _, d2, okk = _procrustes(q, timing, targets)
        nearest = np.where(okk, d2, np.inf)
    bad_fraction = 1.0 - ok.mean(axis=1)
    nearest = np.minimum(nearest, 1e6 * scale * scale)
    fit = nearest.mean(axis=1) / (scale * scale)
    mu = _mu_min(q, theta2, ok)
    shortfall = np.maximum(0.0, mu_min - mu)
    out = fit + _W_ASSEMBLY * bad_fraction + _W_MU * shortfall**2
    return out[0] if single else out


def _distance_to_polyline(curve: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """Distance from each target to each closed curve (S, n), shape (S, K).

    The nearest sample is found first; then the distance to the two chords
    next to it, so the result is second-order accurate in the sampling step
    (a smooth objective for the search). NaN samples count as far away.
    """
    s, n = curve.shape
    diff = curve[:, None, :] - targets[None, :, None]  # (S, K, n)
    d2 = diff.real**2 + diff.imag**2
    d2 = np.where(np.isnan(d2), np.inf, d2)
    i = np.argmin(d2, axis=2)  # (S, K)
    rows = np.arange(s)[:, None]
    best = np.sqrt(np.take_along_axis(d2, i[..., None], axis=2)[..., 0])
    q = curve[rows, i]
    t = targets[None, :]
    for j in ((i + 1) % n, (i - 1) % n):
        other = curve[rows, j]
        seg = other - q
        len2 = seg.real**2 + seg.imag**2
        with np.errstate(invalid="ignore", divide="ignore"):
            u = np.clip(((t - q) * np.conj(seg)).real / len2, 0.0, 1.0)
        proj = np.abs(q + u * seg - t)
        best = np.where(np.isfinite(proj), np.minimum(best, proj), best)
    return best


def _points_at(q: dict[str, np.ndarray], theta2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Coupler points (own frame) of candidate s at its own angles ``theta2[s, :]``."""
    s, k = theta2.shape
    rep = {name: np.repeat(q[name], k) for name in ("r1", "r2", "r3", "r4", "p", "delta", "branch")}
    local, ok = _coupler_points_diag(rep, theta2.ravel())
    return local.reshape(s, k), ok.reshape(s, k)


def _coupler_points_diag(rep: dict[str, np.ndarray], theta2: np.ndarray):
    """Coupler points of candidate i at angle ``theta2[i]`` (one angle each)."""
    # the same closed form as atlas.coupler_points, one angle per candidate
    r1, r2, r3, r4, p, delta, br = (
        rep[k] for k in ("r1", "r2", "r3", "r4", "p", "delta", "branch")
    )
    ax, ay = r2 * np.cos(theta2), r2 * np.sin(theta2)
    sx = ax - r1
    dd = sx * sx + ay * ay
    with np.errstate(invalid="ignore", divide="ignore"):
        inv = 1.0 / np.sqrt(dd)
        cg = (r4 * r4 - r3 * r3 + dd) * inv * (0.5 / r4)
        ok = np.abs(cg) <= 1.0
        sg = np.sqrt(1.0 - cg * cg) * br
    ux, uy = sx * inv, ay * inv
    dx = r4 * (ux * cg + uy * sg) - sx
    dy = r4 * (uy * cg - ux * sg) - ay
    kr, ki = p * np.cos(delta) / r3, p * np.sin(delta) / r3
    pts = (ax + kr * dx - ki * dy) + 1j * (ay + kr * dy + ki * dx)
    return np.where(ok, pts, np.nan), ok


def _mu_min(q: dict[str, np.ndarray], theta2: np.ndarray, ok: np.ndarray) -> np.ndarray:
    """Smallest transmission angle over the assembled samples of each candidate."""
    r1, r2, r3, r4 = (q[k][:, None] for k in ("r1", "r2", "r3", "r4"))
    # cos φ12 from the diagonal: |O4 A|² = b² + c² − 2bc cos φ12
    dd = r1 * r1 + r2 * r2 - 2.0 * r1 * r2 * np.cos(theta2)
    cos12 = (r3 * r3 + r4 * r4 - dd) / (2.0 * r3 * r4)
    mu = np.arcsin(np.sqrt(np.clip(1.0 - cos12 * cos12, 0.0, 1.0)))
    mu = np.where(ok, mu, np.inf)
    out = mu.min(axis=1)
    return np.where(np.isfinite(out), out, 0.0)


def _frame(targets: np.ndarray) -> tuple[float, complex]:
    centre = complex(targets.mean())
    scale = float(np.max(np.abs(targets - centre)))
    return scale, centre


def synthesize_path(
    targets: Any,
    *,
    timing: Any = None,
    mu_min: float = np.radians(30.0),
    tolerance: float | None = None,
    n: int = 120,
    popsize: int = 30,
    maxiter: int = 400,
    seed: int | None = 0,
    polish: bool = True,
) -> PathSynthesis:
    """Find a crank-driven four-bar whose coupler point passes near the targets.

    Parameters
    ----------
    targets : sequence of complex or (x, y)
        At least 3 target points.
    timing : sequence of float, optional
        Input-angle increments (radians) at which the targets must be reached,
        relative to the first (prescribed timing). Without it the targets may
        be met anywhere on the curve.
    mu_min : float
        Transmission angle below which a candidate is penalised (radians).
    tolerance : float, optional
        Distance within which every target must be reached; targets farther
        away are reported in ``defects``.
    n : int
        Input angles per coupler curve during the search.
    popsize, maxiter, seed :
        Passed to :func:`scipy.optimize.differential_evolution`.
    polish : bool
        Refine the best candidate with a local search (Nelder–Mead) at the end.

    Returns
    -------
    PathSynthesis

    Raises
    ------
    InputError
        Fewer than 3 targets, coincident targets, or a timing list of the wrong length.

    Examples
    --------
    Six timed points of a known crank-rocker's coupler curve; the search
    finds a linkage through them (here the original one):

    >>> from machdyn.fourbar import FourBar
    >>> known = PlacedFourBar(FourBar(5, 2, 5, 4, coupler=(3.0, 0.6)), 1 + 2j, 0.3, 1)
    >>> theta2 = np.radians([0, 60, 120, 180, 240, 300])
    >>> targets = known.pose(theta2)[2]
    >>> res = synthesize_path(targets, timing=theta2, popsize=15, maxiter=150, seed=0)
    >>> res.ok, res.barker_class, bool(res.distance.max() < 1e-6)
    (True, 'GCRR', True)
    """
    from scipy.optimize import differential_evolution, minimize

    targets = as_points("targets", targets)
    if targets.size < 3:
        raise InputError("targets", f"needs at least 3 points, got {targets.size}")
    scale, centre = _frame(targets)
    if scale <= 0.0:
        raise InputError("targets", "all target points coincide")
    if timing is not None:
        timing = np.ravel(finite_array("timing", timing, "radian"))
        if timing.size != targets.size:
            raise InputError(
                "timing", f"needs one angle per target ({targets.size}), got {timing.size}"
            )
        timing = timing - timing[0]
    mu_min = in_range("mu_min", mu_min, 0.0, 0.5 * np.pi, unit="radian")
    popsize = integer("popsize", popsize, minimum=5, maximum=10_000)
    maxiter = integer("maxiter", maxiter, minimum=1, maximum=1_000_000)
    n = count("n", n, minimum=12, bytes_each=2 * 64 * 10 * popsize, what="curve samples")
    seed = None if seed is None else integer("seed", seed, minimum=0, maximum=2**32 - 1)
    polish = boolean("polish", polish)
    bounds = list(_BOUNDS) if timing is None else list(_BOUNDS_TIMED)

    def objective(x: np.ndarray) -> np.ndarray:
        return path_objective(
            x, targets, timing=timing, n=n, mu_min=mu_min, scale=scale, centre=centre
        )

    res = differential_evolution(
        objective,
        bounds,
        popsize=popsize,
        maxiter=maxiter,
        seed=seed,
        tol=1e-10,
        atol=1e-12,
        strategy="currenttobest1bin",
        mutation=(0.5, 1.0),
        recombination=0.9,
        polish=False,
        vectorized=True,
        updating="deferred",
    )
    best, value = res.x, float(res.fun)
    if polish:
        # refine the best few members of the final population (they often sit in
        # different basins) by a local search on a finer curve; keep the best
        def fine(v: np.ndarray) -> float:
            return float(
                path_objective(
                    v, targets, timing=timing, n=2 * n, mu_min=mu_min, scale=scale, centre=centre
                )
            )

        order = np.argsort(res.population_energies)[:_POLISH_STARTS]
        for start in res.population[order]:
            local = minimize(
                fine,
                start,
                method="Nelder-Mead",
                bounds=bounds,
                options={"maxiter": 1200, "xatol": 1e-10, "fatol": 1e-14},
            )
            if local.fun < value:
                best, value = local.x, float(local.fun)
    return _result(best, value, targets, timing, scale, centre, mu_min, tolerance)


def _result(best, value, targets, timing, scale, centre, mu_min, tolerance) -> PathSynthesis:
    if timing is None:
        q = _decode(best.reshape(-1, 1), scale, centre)
        O2, theta1 = complex(q["O2"][0]), float(q["theta1"][0])
    else:
        q = _decode_timed(best.reshape(-1, 1), scale)
        rot, o2, _, _ = _procrustes(q, timing, targets)
        O2, theta1 = complex(o2[0]), float(np.angle(rot[0]))
    r1, r2, r3, r4, p, delta = (float(q[k][0]) for k in ("r1", "r2", "r3", "r4", "p", "delta"))
    branch = int(q["branch"][0])
    try:
        fb = FourBar(r1, r2, r3, r4, coupler=(p, delta))
    except AssemblyError:
        raise AssemblyError(
            "no candidate linkage reaches the targets: the best one cannot even be assembled; "
            "check the targets (are they a path a four-bar can trace?)"
        ) from None
    linkage = PlacedFourBar(fb, O2, theta1, branch)
    dense = np.linspace(0.0, 2 * np.pi, 3600, endpoint=False)
    _, _, P, ok = linkage.pose(dense)
    if timing is None:
        d = np.abs(P[None, :] - targets[:, None])
        d = np.where(ok[None, :], d, np.inf)
        idx = np.argmin(d, axis=1)
        theta2 = dense[idx]
        distance = d[np.arange(targets.size), idx]
        steps = np.diff(np.concatenate([idx, idx[:1]]))
        in_order = bool(
            np.sum(np.mod(steps, dense.size)) == dense.size
            or np.sum(np.mod(-steps, dense.size)) == dense.size
        )
    else:
        theta2 = np.mod(float(best[7]) + timing, 2 * np.pi)
        _, _, Pk, okk = linkage.pose(theta2)
        distance = np.where(okk, np.abs(Pk - targets), np.inf)
        in_order = True
    cls = classify(*fb.lengths)
    is_crank = bool(ok.all())
    mu = _mu_min(
        {k: np.array([v]) for k, v in zip(("r1", "r2", "r3", "r4"), fb.lengths, strict=True)},
        dense,
        ok[None, :],
    )[0]
    defects: list[str] = []
    if not is_crank:
        defects.append(
            f"link 2 is not a full-turn crank ({cls.code}); it cannot be driven round by a motor"
        )
    if mu < mu_min - _MU_SLACK:
        defects.append(
            f"transmission angle falls to {np.degrees(mu):.1f} deg (limit {np.degrees(mu_min):.1f})"
        )
    if not in_order:
        defects.append("order defect: the coupler point meets the targets out of order")
    if tolerance is not None:
        tolerance = finite_scalar("tolerance", tolerance)
        missed = np.flatnonzero(~(distance <= tolerance))
        if missed.size:
            defects.append(
                f"targets {[int(i) + 1 for i in missed]} are not reached within {tolerance:g} "
                f"(worst {np.max(distance[missed]):.4g})"
            )
    return PathSynthesis(
        linkage=linkage,
        targets=targets,
        theta2=theta2,
        distance=distance,
        barker_class=cls.code,
        is_crank=is_crank,
        mu_min=float(mu),
        in_order=in_order,
        objective=value,
        defects=tuple(defects),
    )
