"""Least-squares refinement of a placed four-bar onto target points, with an analytic Jacobian.

The unknowns are the design ``x = (r1, r2, r3, r4, p, δ, O2x, O2y, θ1)`` and
the input angle of each target: ``θ_k`` free (the point of the curve nearest
to target k, so at the optimum the residual *is* the point-to-curve
distance) or, with prescribed timing, ``θ_k = θ0 + Δ_k`` with one ``θ0``.
The residuals are ``G(x, θ_k) − T_k`` (x and y), with ``G = O2 + e^{jθ1} P``
and ``P = A + p e^{jδ} e^{jθ3}`` the coupler point of the notes' closed form.

Jacobian: differentiating the loop ``r2 e^{jθ2} + r3 e^{jθ3} − r4 e^{jθ4} − r1 = 0``
with respect to any unknown ``ξ`` gives ``w + j r3 e^{jθ3} θ3' − j r4 e^{jθ4} θ4' = 0``
(``w`` the loop's explicit derivative: ``−1, e^{jθ2}, e^{jθ3}, −e^{jθ4}, j r2 e^{jθ2}``
for ``r1, r2, r3, r4, θ2``), whose component along ``e^{jθ4}`` is
``θ3' = Re(w e^{−jθ4}) / (r3 sin(θ3 − θ4))`` (Norton, *Design of Machinery*,
sec. 6.7, the same 2×2 system as the velocity analysis). Then
``P' = A' + (p e^{jδ})' e^{jθ3} + j p e^{jδ} e^{jθ3} θ3'`` and ``G' = e^{jθ1} P'``.

Two requirements that the defect filter checks afterwards are also soft
constraints here (so a refinement does not walk out of them): link 2 turns
fully (``|r3 − r4| ≤ |r1 − r2|`` and ``r1 + r2 ≤ r3 + r4``), and the
transmission angle at the two extremes of a crank-rocker's motion stays above
``mu_min``. Those four rows depend on the lengths only; their derivatives are
taken by central differences.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

# Internal to machdyn.synthesis, which re-exports the public names (Atlas, build_atlas,
# open_atlas, path_from_atlas, curve_descriptor, ...); the fuzz suite fuzzes those.
__all__: list[str] = []

#: Weight of the soft constraints (per unit of violation, lengths over the target size).
_W_CONSTRAINT = 30.0


@dataclass(frozen=True)
class Refined:
    """The outcome of :func:`refine`."""

    x: np.ndarray  # r1, r2, r3, r4, p, delta, O2x, O2y, theta1
    theta: np.ndarray  # input angle at each target
    branch: np.ndarray  # assembly (sign of φ12) at each target
    rms: float  # RMS point residual
    success: bool


def coupler_and_jacobian(
    x: np.ndarray, theta: np.ndarray, branch: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Global coupler point at each ``theta`` and its derivatives.

    Returns ``G`` (K,) complex, ``dG/dx`` (K, 9) complex, ``dG/dθ`` (K,) complex
    and the clamped law-of-cosines excess ``|cos γ| − 1`` (K,) (positive where
    the linkage cannot be assembled at that angle).

    Examples
    --------
    Against central differences:

    >>> x = np.array([5.0, 2.0, 5.0, 4.0, 3.0, 0.6, 1.0, 2.0, 0.3])
    >>> th, br = np.array([0.4, 2.0]), np.array([1.0, 1.0])
    >>> G, J, Jt, _ = coupler_and_jacobian(x, th, br)
    >>> h = 1e-6
    >>> def G_of(x):
    ...     return coupler_and_jacobian(x, th, br)[0]
    >>> fd = np.array([(G_of(x + h * e) - G_of(x - h * e)) / (2 * h) for e in np.eye(9)])
    >>> bool(np.allclose(fd.T, J, atol=1e-7))
    True
    """
    r1, r2, r3, r4, p, delta, ox, oy, theta1 = x
    e2 = np.exp(1j * theta)
    a = r2 * e2
    s = a - r1  # O4 → A
    dd = np.abs(s) ** 2
    d = np.sqrt(dd)
    cg_raw = (r4 * r4 - r3 * r3 + dd) / (2.0 * r4 * d)
    excess = np.abs(cg_raw) - 1.0
    cg = np.clip(cg_raw, -1.0, 1.0)
    sg = np.sqrt(1.0 - cg * cg) * branch
    e4 = (s / d) * (cg - 1j * sg)
    b = r1 + r4 * e4
    e3 = (b - a) / r3
    ed = np.exp(1j * delta)
    P = a + p * ed * e3
    rot = np.exp(1j * theta1)
    G = ox + 1j * oy + rot * P
    sin34 = np.imag(e3 * np.conj(e4))  # sin(θ3 − θ4)
    safe = np.where(np.abs(sin34) > 1e-12, sin34, 1e-12)
    ce4 = np.conj(e4)
    tail = 1j * p * ed * e3  # ∂P/∂θ3

    def dtheta3(w: np.ndarray) -> np.ndarray:
        return np.real(w * ce4) / (r3 * safe)

    J = np.empty((theta.size, 9), dtype=complex)
    J[:, 0] = tail * dtheta3(-np.ones_like(e2))
    J[:, 1] = e2 + tail * dtheta3(e2)
    J[:, 2] = tail * dtheta3(e3)
    J[:, 3] = tail * dtheta3(-e4)
    J[:, 4] = ed * e3
    J[:, 5] = 1j * p * ed * e3
    J[:, :6] *= rot
    J[:, 6] = 1.0
    J[:, 7] = 1j
    J[:, 8] = 1j * rot * P
    jt = rot * (1j * a + tail * dtheta3(1j * a))
    return G, J, jt, excess


def _constraints(lengths: np.ndarray, cos_mu: float, crank: bool, scale: float) -> np.ndarray:
    """Violations (≥ 0) of the crank and transmission-angle requirements, dimensionless."""
    if not crank:
        return np.zeros(0)
    return np.array(_violations(*(float(v) for v in lengths), cos_mu, scale))


def _violations(r1: float, r2: float, r3: float, r4: float, cos_mu: float, scale: float) -> list:
    """:func:`_constraints` on plain floats (the Jacobian's differences call it 8 times)."""
    out = [
        max(0.0, abs(r3 - r4) - abs(r1 - r2)) / scale,
        max(0.0, r1 + r2 - r3 - r4) / scale,
    ]
    for dgl in (abs(r1 - r2), r1 + r2):
        c = (r3 * r3 + r4 * r4 - dgl * dgl) / (2.0 * r3 * r4)
        out.append(max(0.0, abs(c) - cos_mu))
    return out


def _constraint_slopes(lengths: np.ndarray, cos_mu: float, scale: float) -> np.ndarray:
    """Central differences (4 × 4) of :func:`_constraints` in the lengths (crank required)."""
    h = 1e-7 * scale
    base = [float(v) for v in lengths]
    out = np.empty((4, 4))
    for j in range(4):
        up, down = base.copy(), base.copy()
        up[j] += h
        down[j] -= h
        hi = _violations(*up, cos_mu, scale)
        lo = _violations(*down, cos_mu, scale)
        out[:, j] = [(a - b) / (2 * h) for a, b in zip(hi, lo, strict=True)]
    return out


def _compiled(compiled: bool | None) -> bool:
    """Whether to use the compiled kernels (None: when :mod:`machdyn.jit` has them loaded)."""
    from .. import jit

    return jit.active() if compiled is None else bool(compiled)


def _evaluator(compiled: bool | None):
    """``(x, θ, branch) → (G, dG/dx, dG/dθ, excess)``: the compiled kernel or NumPy's."""
    if not _compiled(compiled):
        return coupler_and_jacobian
    from ._atlas_kernels import coupler_jacobian

    def evaluate(x, theta, branch):
        theta = np.ascontiguousarray(theta, dtype=float)
        k = theta.size
        G, J, jt = np.empty(k, complex), np.empty((k, 9), complex), np.empty(k, complex)
        excess = np.empty(k)
        coupler_jacobian(np.ascontiguousarray(x, dtype=float), theta,
                         np.ascontiguousarray(branch, dtype=float), G, J, jt, excess)  # fmt: skip
        return G, J, jt, excess

    return evaluate


def _levenberg_marquardt(z, free, lo, hi, max_nfev, problem) -> int:
    """Levenberg–Marquardt within bounds, in place on ``z``; the status (0: out of steps).

    ``problem(z) → (r, J)``. Marquardt's scaling (the largest column norms of J
    seen so far) and Nielsen's damping update; a variable at a bound whose
    gradient points out of the box is held for the step, and the step is cut
    back onto the box. Each evaluation counts against ``max_nfev``. Status 1: no
    gradient left; 2: relative decrease of the cost below :data:`_TOL`; 3: step
    below it (or the damping beyond any use).
    """
    r, J = problem(z)
    cost = 0.5 * float(r @ r)
    if not np.isfinite(cost):
        return 0
    D2 = np.zeros(z.size)
    lam, nu, nfev = 1e-3, 2.0, 1
    while nfev < max_nfev:
        g = J.T @ r
        A = J.T @ J
        D2 = np.maximum(D2, np.diag(A))
        act = free & ~((z <= lo) & (g > 0)) & ~((z >= hi) & (g < 0))
        if not np.any(act) or not np.max(np.abs(g[act])) > 0.0:
            return 1
        M = A + np.diag(lam * np.maximum(D2, 1e-24 * max(float(np.max(D2)), 1e-300)))
        M[~act, :] = 0.0
        M[:, ~act] = 0.0
        M[~act, ~act] = 1.0
        try:
            step = np.linalg.solve(M, np.where(act, -g, 0.0))
        except np.linalg.LinAlgError:
            return 0
        trial = np.where(free, np.clip(z + step, lo, hi), z)
        p = trial - z
        pred = -(float(g @ p) + 0.5 * float(p @ A @ p))
        r_new, J_new = problem(trial)
        nfev += 1
        cost_new = 0.5 * float(r_new @ r_new)
        actual = cost - cost_new if np.isfinite(cost_new) else -np.inf
        if pred > 0 and actual > 1e-4 * pred:
            z[:] = trial
            r, J, old, cost = r_new, J_new, cost, cost_new
            lam *= max(1.0 / 3.0, 1.0 - (2.0 * actual / pred - 1.0) ** 3)
            nu = 2.0
            if actual <= _TOL * old:
                return 2
            if np.sqrt(p @ p) <= _TOL * (_TOL + np.sqrt(z @ z)):
                return 3
        else:
            lam *= nu
            nu *= 2.0
            if lam > 1e20:
                return 3
    return 0


#: Convergence tolerances of the refinement (scipy's xtol, ftol, gtol; the LM's too).
_TOL = 1e-13


def _problem(targets, branch, timing, crank: bool, cos_mu: float, scale: float, weight: float,
             compiled: bool | None):  # fmt: skip
    """The refinement's unknowns → angles, residuals, Jacobian and the evaluation (cached).

    Unknowns ``z``: the nine design numbers, then ``θ0`` (with ``timing``: the
    angles are ``θ0 + Δ_k``) or each target's ``θ_k``. Rows: the misses over the
    size (x, then y), the assembly penalty, and with ``crank`` the crank and
    transmission-angle violations, weighted by ``weight``. The Jacobian has a
    column for every unknown (select the free ones).
    """
    k = targets.size
    timed = timing is not None

    def angles(z: np.ndarray) -> np.ndarray:
        return z[9] + timing if timed else z[9:]

    evaluate = _evaluator(compiled)
    last: list = [None, None]  # the design last evaluated and its values (trf asks twice)

    def at(z: np.ndarray):
        if last[0] is None or not np.array_equal(last[0], z):
            last[0], last[1] = z.copy(), evaluate(z[:9], angles(z), branch)
        return last[1]

    def residual(z: np.ndarray) -> np.ndarray:
        G, _, _, excess = at(z)
        d = (G - targets) / scale
        pen = weight * np.maximum(excess, 0.0)
        con = weight * _constraints(z[:4], cos_mu, crank, scale)
        return np.concatenate([d.real, d.imag, pen, con])

    rows = np.arange(k)

    def jacobian(z: np.ndarray) -> np.ndarray:
        _, J, jt, _ = at(z)
        out = np.zeros((3 * k + (4 if crank else 0), z.size))
        out[:k, :9], out[k : 2 * k, :9] = J.real / scale, J.imag / scale
        if timed:
            out[:k, 9], out[k : 2 * k, 9] = jt.real / scale, jt.imag / scale
        else:
            out[rows, 9 + rows], out[k + rows, 9 + rows] = jt.real / scale, jt.imag / scale
        # rows of the crank and transmission-angle constraints: by differences (rarely active)
        if crank:
            out[3 * k :, :4] = weight * _constraint_slopes(z[:4], cos_mu, scale)
        return out

    return angles, residual, jacobian, at


def refine(
    x0: np.ndarray,
    theta0: np.ndarray,
    branch: np.ndarray,
    targets: np.ndarray,
    *,
    timing: np.ndarray | None = None,
    crank: bool = True,
    mu_min: float = 0.0,
    max_nfev: int = 60,
    fixed: dict[int, float] | None = None,
    max_length: float | None = None,
    pivot_box: tuple[float, float, float, float] | None = None,
    weight: float = _W_CONSTRAINT,
    compiled: bool | None = None,
    solver: str = "trf",
    tie: tuple[int, np.ndarray] | None = None,
) -> Refined:
    """Refine a placed four-bar so its coupler curve passes through ``targets``.

    Parameters
    ----------
    x0 : ndarray, shape (9,)
        Starting design ``r1, r2, r3, r4, p, δ, O2x, O2y, θ1``.
    theta0 : ndarray, shape (K,)
        Starting input angle at each target (with ``timing``: ``θ0 + Δ_k``).
    branch : ndarray, shape (K,)
        Assembly at each target (kept).
    targets : ndarray of complex, shape (K,)
    timing : ndarray, shape (K,), optional
        Prescribed input-angle increments ``Δ_k``.
    crank, mu_min :
        Soft constraints: link 2 a crank, transmission angle above ``mu_min``.
    fixed : dict, optional
        Unknowns held at given values, by index into ``(x, θ…)``: 6, 7 for the
        pivot ``O2``, 8 for ``θ1``, 9 for ``θ0`` with timing (0: the timing is
        the input angle itself, measured from the ground line).
    max_length : float, optional
        Upper bound on the link lengths ``r1 … r4`` and on ``p`` (the coupler
        point's distance from A).
    pivot_box : (xmin, ymin, xmax, ymax), optional
        Bounds on the pivot ``O2``.
    weight : float
        Weight of the soft constraints' rows (per unit of violation over the size).
    compiled : bool, optional
        Evaluate the coupler points and their derivatives with the compiled
        kernel (:func:`machdyn.synthesis._atlas_kernels.coupler_jacobian`);
        None: when :mod:`machdyn.jit` has the compiled kernels loaded.
    solver : {"trf", "lm"}
        scipy's trust-region reflective least squares, or this module's
        Levenberg–Marquardt (:func:`_levenberg_marquardt`: several times less
        overhead per step; the synthesis screens timed starts with it). With
        the compiled kernels the LM's whole loop runs compiled
        (:func:`machdyn.synthesis._atlas_kernels.lm_refine`, the same steps).
    tie : (int, ndarray of 4), optional
        ``solver="lm"`` only: the length ``x[i]`` is held at ``c · x[:4]`` (e.g. a
        Grashof change point ``l = p + q − s``), the other lengths free.

    Examples
    --------
    A perturbed linkage slides back onto points of the original's curve:

    >>> x = np.array([5.0, 2.0, 5.0, 4.0, 3.0, 0.6, 1.0, 2.0, 0.3])
    >>> th = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    >>> T = coupler_and_jacobian(x, th, np.ones(12))[0]
    >>> r = refine(x * 1.03, th + 0.05, np.ones(12), T)
    >>> r.success, bool(r.rms < 1e-9)
    (True, True)
    """
    from scipy.optimize import least_squares

    targets = np.asarray(targets, dtype=complex)
    k = targets.size
    scale = float(np.max(np.abs(targets - targets.mean()))) or 1.0
    cos_mu = float(np.cos(mu_min))
    timed = timing is not None
    nvar = 9 + (1 if timed else k)
    z0 = np.concatenate([x0, [theta0[0] - timing[0]] if timed else theta0])

    angles, residual, jacobian, at = _problem(targets, branch, timing, crank, cos_mu, scale,
                                              weight, compiled)  # fmt: skip

    lo = np.full(nvar, -np.inf)
    lo[:4] = 1e-6 * scale
    lo[4] = 0.0
    hi = np.full(nvar, np.inf)
    if max_length is not None:
        hi[:5] = max_length
    if pivot_box is not None:
        lo[6], lo[7], hi[6], hi[7] = pivot_box
    free = np.ones(nvar, dtype=bool)
    for i, value in (fixed or {}).items():
        free[i] = False
        z0[i] = value
    z0 = np.where(free, np.clip(z0, lo + 1e-12 * scale, hi - 1e-12 * scale), z0)

    def full(y: np.ndarray) -> np.ndarray:
        z = z0.copy()
        z[free] = y
        return z

    if tie is not None and solver != "lm":
        raise ValueError("tie needs solver='lm'")
    tied, tie_c = (-1, np.zeros(4)) if tie is None else (int(tie[0]), np.asarray(tie[1], float))
    if tied >= 0:
        free[tied] = False
    if solver == "lm" and _compiled(compiled):  # the whole loop compiled (same steps)
        from ._atlas_kernels import lm_refine

        z, G = z0.copy(), np.empty(k, dtype=complex)
        status = lm_refine(z, free, lo, hi, int(max_nfev), _TOL, targets,
                           np.ascontiguousarray(branch, dtype=float),
                           np.zeros(0) if timing is None else np.ascontiguousarray(timing, float),
                           timed, crank, cos_mu, scale, float(weight), tied, tie_c, G)  # fmt: skip
        rms = float(np.sqrt(np.mean(np.abs(G - targets) ** 2)))
        return Refined(z[:9].copy(), np.asarray(angles(z), dtype=float), branch, rms, status > 0)
    if solver == "lm":
        z = z0.copy()

        def problem(z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            if tied >= 0:  # the held length first (in place), its column into the others
                z[tied] = float(tie_c @ z[:4])
            r, J = residual(z), jacobian(z)
            if tied >= 0:
                J[:, :4] += np.outer(J[:, tied], np.where(np.arange(4) == tied, 0.0, tie_c))
            return r, J

        ok = _levenberg_marquardt(z, free, lo, hi, max_nfev, problem) > 0
    else:
        try:
            sol = least_squares(
                lambda y: residual(full(y)), z0[free], jac=lambda y: jacobian(full(y))[:, free],
                bounds=(lo[free], hi[free]), method="trf", x_scale="jac",
                max_nfev=max_nfev, xtol=_TOL, ftol=_TOL, gtol=_TOL,
            )  # fmt: skip
            z, ok = full(sol.x), bool(sol.status > 0)
        except (ValueError, np.linalg.LinAlgError):
            z, ok = z0, False
    G = at(z)[0]
    rms = float(np.sqrt(np.mean(np.abs(G - targets) ** 2)))
    return Refined(z[:9].copy(), np.asarray(angles(z), dtype=float), branch, rms, ok)
