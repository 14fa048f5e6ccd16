"""A final polish of a refined four-bar: Levenberg–Marquardt with geodesic acceleration.

Targets on a short arc (an open path, or a few points of a closed one) fix a
four-bar poorly: many linkages trace nearly the same arc, and the least-squares
problem of :func:`~machdyn.synthesis.refine.refine` is *sloppy*: at the exact
linkage of a random crank-rocker through 9 points on a 1–3 rad arc the
Jacobian's singular values span 10^6 to 10^9. Its minimum lies at the end of a
long, narrow, curved valley, along which a trust-region or plain
Levenberg–Marquardt method crawls (measured: from starts 1–5 % off the exact
linkage, scipy's ``trf`` ends at 1e-7 … 1e-5 of the size after 400 evaluations).

Geodesic acceleration (Transtrum & Sethna, "Improvements to the
Levenberg–Marquardt algorithm for nonlinear least-squares minimization",
arXiv:1201.5885, 2012) follows the valley's bend: to the damped Gauss–Newton
step ``δv = −(JᵀJ + λD)⁻¹ Jᵀ r`` it adds ``½ δa`` with
``δa = −(JᵀJ + λD)⁻¹ Jᵀ r_vv``, where ``r_vv`` is the residual's second
derivative along ``δv`` (one extra residual evaluation:
``r_vv ≈ (2/h) ((r(z + h δv) − r(z))/h − J δv)``), and accepts the step only
while ``|δa| ≤ α |δv|``. From the same starts it reaches 1e-13 of the size in
0.1–0.2 s.

The residual rows are those of :func:`~machdyn.synthesis.refine.refine`
(coupler-point misses over the size; the assembly and crank penalties), so a
polished linkage meets the same requirements; held unknowns stay held, and a
step out of the length or pivot bounds is refused.
"""

from __future__ import annotations

import numpy as np

from .refine import _W_CONSTRAINT, Refined, _compiled, _problem

# Internal to machdyn.synthesis (used by path_from_atlas).
__all__: list[str] = []

#: Geodesic acceleration: finite-difference step along δv, and the largest |δa|/|δv|.
_H = 0.1
_ALPHA = 0.75
#: Stop once the RMS miss is below this share of the targets' size, or when the
#: sum of squares fell less than fourfold over the last _STALL iterations.
_DONE = 1e-11
_STALL = 60


def polish(
    fit: Refined,
    targets: np.ndarray,
    *,
    timing: np.ndarray | None = None,
    crank: bool = True,
    mu_min: float = 0.0,
    fixed: dict[int, float] | None = None,
    max_length: float | None = None,
    pivot_box: tuple[float, float, float, float] | None = None,
    iterations: int = 300,
    stall: int | None = None,
    compiled: bool | None = None,
) -> Refined:
    """``fit`` moved down its valley by geodesic-acceleration Levenberg–Marquardt.

    Same unknowns, rows and options as :func:`~machdyn.synthesis.refine.refine`
    (``θ_k`` free, or ``θ0 + Δ_k`` with ``timing``); ``iterations`` Jacobians
    at most, stopping early once the sum of squares fell less than fourfold over
    the last ``stall`` of them (default :data:`_STALL`). ``compiled``: run the
    loop compiled (:func:`machdyn.synthesis._valley_kernels.descend`, the same
    steps up to rounding); None: when :mod:`machdyn.jit` has the compiled kernels
    loaded. Returns ``fit`` itself when no step lowered the misses.

    Examples
    --------
    A start 3 % off a linkage through 9 points of a short arc:

    >>> from machdyn.synthesis.refine import Refined, coupler_and_jacobian
    >>> x = np.array([3.0, 1.0, 4.0, 3.5, 2.0, 0.7, 0.0, 0.0, 0.0])
    >>> th = 1.0 + np.linspace(0, 1.5, 9)
    >>> T = coupler_and_jacobian(x, th, np.ones(9))[0]
    >>> start = Refined(x * 1.03, th + 0.02, np.ones(9), 1.0, False)
    >>> bool(polish(start, T).rms < 1e-9)
    True
    """
    targets = np.asarray(targets, dtype=complex)
    k = targets.size
    branch = np.asarray(fit.branch, dtype=float)
    scale = float(np.max(np.abs(targets - targets.mean()))) or 1.0
    cos_mu = float(np.cos(mu_min))
    timed = timing is not None
    z = np.concatenate([fit.x, [fit.theta[0] - timing[0]] if timed else fit.theta])
    free = np.ones(z.size, dtype=bool)
    for i, value in (fixed or {}).items():
        free[i] = False
        z[i] = value

    stall = _STALL if stall is None else int(stall)
    if _compiled(compiled):
        from ._valley_kernels import descend

        box = np.zeros(4) if pivot_box is None else np.asarray(pivot_box, dtype=float)
        G = descend(z, free, targets, np.ascontiguousarray(branch),
                    np.zeros(0) if timing is None else np.ascontiguousarray(timing, dtype=float),
                    timed, crank, cos_mu, scale, _W_CONSTRAINT,
                    np.inf if max_length is None else float(max_length), box,
                    pivot_box is not None, int(iterations), _H, _ALPHA, _DONE, stall)  # fmt: skip
        return _outcome(fit, z, G, targets, z[9] + timing if timed else z[9:])
    angles, residual, full_jacobian, at = _problem(targets, branch, timing, crank, cos_mu, scale,
                                                   _W_CONSTRAINT, None)  # fmt: skip

    def jacobian(z: np.ndarray) -> np.ndarray:
        return full_jacobian(z)[:, free]

    def allowed(z: np.ndarray) -> bool:
        if np.any(z[:4] <= 0.0) or z[4] < 0.0:
            return False
        if max_length is not None and np.any(z[:5] > max_length):
            return False
        if pivot_box is not None:
            x0, y0, x1, y1 = pivot_box
            return x0 <= z[6] <= x1 and y0 <= z[7] <= y1
        return True

    z = _descend(z, free, residual, jacobian, allowed, iterations, 2 * k, stall)
    G = at(z)[0]  # (the evaluation the last step made)
    return _outcome(fit, z, G, targets, angles(z))


def _outcome(fit: Refined, z: np.ndarray, G: np.ndarray, targets, theta) -> Refined:
    """The polished fit at ``z`` (points ``G``), or ``fit`` itself if it is no better."""
    rms = float(np.sqrt(np.mean(np.abs(G - targets) ** 2)))
    if not rms < fit.rms:
        return fit
    return Refined(z[:9].copy(), np.asarray(theta, dtype=float), fit.branch, rms, True)


def _descend(z, free, residual, jacobian, allowed, iterations, rows, stall=_STALL):
    """The geodesic-acceleration Levenberg–Marquardt loop (Marquardt's diagonal scaling).

    ``rows``: how many residual rows are point misses (for the stopping rule).
    """
    r = residual(z)
    cost = float(r @ r)
    lam = 1e-3
    before = cost
    for it in range(iterations):
        if cost <= _DONE**2 * rows:
            break
        if it and it % stall == 0:  # a minimum that is not zero, or a crawl: stop
            if cost > 0.25 * before:
                break
            before = cost
        J = jacobian(z)
        A = J.T @ J
        g = J.T @ r
        D = np.maximum(np.diag(A), 1e-30)
        while True:
            try:
                M = A + lam * np.diag(D)
                dv = -np.linalg.solve(M, g)
                zv = z.copy()
                zv[free] += _H * dv
                rvv = (2.0 / _H) * ((residual(zv) - r) / _H - J @ dv)
                da = -np.linalg.solve(M, J.T @ rvv)
            except np.linalg.LinAlgError:
                dv = da = None
            if dv is not None:
                # the accelerated step while the bend is mild, else the plain one
                bent = np.linalg.norm(da) > _ALPHA * np.linalg.norm(dv)
                zn = z.copy()
                zn[free] += dv if bent else dv + 0.5 * da
                if allowed(zn):
                    rn = residual(zn)
                    cn = float(rn @ rn)
                    if np.isfinite(cn) and cn < cost:
                        z, r, cost = zn, rn, cn
                        lam = max(lam / 3.0, 1e-15)
                        break
            lam *= 2.0
            if lam > 1e16:
                return z
    return z
