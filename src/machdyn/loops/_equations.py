"""The loop equations of the vector-loop core: residual, Jacobian, derivatives, points.

Arrays are laid out as ``(variable, sample)``. Each loop ``Σ s_k d_k e^{jθ_k} = 0``
gives a real and an imaginary row; each linear constraint ``Σ c_v x_v + c0 = 0``
gives one row (Norton, *Design of Machinery*, ch. 4 and 6; the notes' "vector
loop equation"). The Jacobian uses ``∂(d e^{jθ})/∂θ = j d e^{jθ}`` and
``∂(d e^{jθ})/∂d = e^{jθ}``.
"""

from __future__ import annotations

import numpy as np

from ._compiled import Compiled
from ._linalg import BlockFactor, solve

__all__ = ["derivatives", "point_motion", "residual_and_jacobian"]


def _vector_terms(c: Compiled, x: np.ndarray) -> tuple[list, list, list]:
    """Length, cos and sin of every vector for the states ``x`` (n_var, N).

    Constant parts stay Python floats (broadcast for free); vectors sharing an
    angle variable share its trigonometry.
    """
    d, cos, sin = [], [], []
    trig: dict[int, tuple[np.ndarray, np.ndarray]] = {}
    for k in range(len(c.length_const)):
        lv, av = int(c.length_var[k]), int(c.angle_var[k])
        d.append(x[lv] if lv >= 0 else float(c.length_const[k]))
        if av >= 0:
            if av not in trig:
                trig[av] = np.cos(x[av]), np.sin(x[av])
            cos.append(trig[av][0])
            sin.append(trig[av][1])
        else:
            cos.append(float(np.cos(c.angle_const[k])))
            sin.append(float(np.sin(c.angle_const[k])))
    return d, cos, sin


def _step_terms(
    c: Compiled, x: np.ndarray, terms: tuple[list, list, list], step: np.ndarray
) -> tuple[list, list, list]:
    """``_vector_terms`` after the unknowns moved by ``step`` (n_q, N), cheaply.

    Small angle changes rotate the known cos and sin (``cos(θ+δ) = cos θ cos δ −
    sin θ sin δ`` with 5th-order series for cos δ and sin δ, exact to rounding
    for ``|δ| ≤ 2e-3``), a few multiplications instead of two transcendental
    functions; larger ones are evaluated afresh.
    """
    d, cos, sin = (list(t) for t in terms)
    rotated: dict[int, tuple[np.ndarray, np.ndarray]] = {}
    row = c.unknown_row
    for k in range(len(c.length_const)):
        lv, av = int(c.length_var[k]), int(c.angle_var[k])
        if lv >= 0:
            d[k] = x[lv]
        if av not in row:
            continue
        if av not in rotated:
            delta = step[row[av]]
            if np.abs(delta).max() <= 2e-3:
                d2 = delta * delta
                cd = 1.0 - d2 * (0.5 - d2 / 24.0)
                sd = delta * (1.0 - d2 * (1.0 / 6.0 - d2 / 120.0))
                rotated[av] = cos[k] * cd - sin[k] * sd, sin[k] * cd + cos[k] * sd
            else:
                rotated[av] = np.cos(x[av]), np.sin(x[av])
        cos[k], sin[k] = rotated[av]
    return d, cos, sin


def residual_and_jacobian(
    c: Compiled,
    x: np.ndarray,
    cols: np.ndarray | None = None,
    jacobian: bool = True,
    terms: tuple[list, list, list] | None = None,
) -> tuple[np.ndarray, np.ndarray | None]:
    """Residual ``F(x)`` and Jacobian ``∂F/∂x[cols]`` for a batch of states.

    Parameters
    ----------
    c : Compiled
    x : ndarray, shape (n_var, N)
    cols : ndarray of int, optional
        Variables to differentiate by (default: the unknowns).
    jacobian : bool
        Skip the Jacobian when False.
    terms : tuple, optional
        ``_vector_terms(c, x)`` when already computed.

    Returns
    -------
    F : ndarray, shape (n_eq, N)
    J : ndarray, shape (n_eq, len(cols), N) or None
    """
    cols = c.unknown if cols is None else cols
    n_samples = x.shape[1]
    d, cos, sin = _vector_terms(c, x) if terms is None else terms
    n_loop = c.loops.shape[0]
    f = np.empty((c.n_eq, n_samples))
    jac = np.zeros((c.n_eq, len(cols), n_samples)) if jacobian else None
    where = {int(v): i for i, v in enumerate(cols)}
    for l_idx, terms in enumerate(c.loop_terms):
        fx, fy = f[2 * l_idx], f[2 * l_idx + 1]
        fx[...] = 0.0
        fy[...] = 0.0
        for k, s in terms:
            sd = s * d[k]
            px, py = sd * cos[k], sd * sin[k]  # the term s d e^{jθ}, real and imaginary
            fx += px
            fy += py
            if jac is None:
                continue
            a_col = where.get(int(c.angle_var[k]))
            if a_col is not None:  # ∂/∂θ = j s d e^{jθ}
                jac[2 * l_idx, a_col] -= py
                jac[2 * l_idx + 1, a_col] += px
            l_col = where.get(int(c.length_var[k]))
            if l_col is not None:  # ∂/∂d = s e^{jθ}
                jac[2 * l_idx, l_col] += s * cos[k]
                jac[2 * l_idx + 1, l_col] += s * sin[k]
    if c.con.shape[0]:
        f[2 * n_loop :] = c.con @ x + c.con0[:, None]
        if jac is not None:
            jac[2 * n_loop :] = c.con[:, cols][:, :, None]
    return f, jac


def derivatives(
    c: Compiled,
    x0: np.ndarray,
    u_rates: list[np.ndarray],
    reuse: tuple | None = None,
) -> tuple[list[np.ndarray], BlockFactor]:
    """Velocity, acceleration and jerk of every variable, one linear solve each.

    Differentiating each loop ``Σ s R = 0`` with ``R = d e^{jθ}`` (DESIGN.md):

    * ``Ṙ = (ḋ + j d θ̇) e^{jθ}``
    * ``R̈ = (d̈ − d θ̇² + j(d θ̈ + 2 ḋ θ̇)) e^{jθ}``
    * ``R⃛ = (d⃛ − 3 ḋ θ̇² − 3 d θ̇ θ̈ + j(d θ⃛ + 3 ḋ θ̈ + 3 d̈ θ̇ − d θ̇³)) e^{jθ}``

    The highest derivatives enter as ``(d⁽ᵏ⁾ + j d θ⁽ᵏ⁾) e^{jθ}``, i.e. through
    the position Jacobian, so ``J_q`` is factored once and solved per order.

    Parameters
    ----------
    c : Compiled
    x0 : ndarray, shape (n_var, N)
        Positions of all variables.
    u_rates : list of ndarray, each (n_u, N)
        First, second, third time derivatives of the inputs (1 to 3 entries).
    reuse : tuple, optional
        ``(terms, jacobian, factor)`` already computed at exactly ``x0`` (the
        last Newton evaluation of the position solve; ``Positions.reuse``).

    Returns
    -------
    rates : list of ndarray, each (n_var, N)
        ẋ, ẍ, x⃛ (as many as ``u_rates``).
    factor : BlockFactor
        The factors of ``J_q`` (determinant and conditioning per sample).
    """
    nq = len(c.unknown)
    if reuse is None:
        cols = np.concatenate([c.unknown, c.inputs])
        terms = _vector_terms(c, x0)
        _, jac = residual_and_jacobian(c, x0, cols, terms=terms)
        fac = c.factor(jac[:, :nq])
    else:
        terms, jac, fac = reuse
    d, cos, sin = terms
    j_u = jac[:, nq:]
    rates: list[np.ndarray] = []
    n_loop = c.loops.shape[0]
    zero = 0.0
    for order, u_k in enumerate(u_rates, start=1):
        rhs = -np.einsum("eun,un->en", j_u, u_k)
        if order > 1:
            x1 = rates[0]
            x2 = rates[1] if order > 2 else None
            for l_idx in range(n_loop):
                for k in np.flatnonzero(c.loops[l_idx]):
                    s = c.loops[l_idx, k]
                    lv, av = c.length_var[k], c.angle_var[k]
                    if av < 0:  # constant angle: only the length's own derivatives
                        continue  # which enter through the Jacobian (no bias)
                    w1 = x1[av]
                    if lv < 0:  # constant length: the common case, fewer terms
                        if order == 2:
                            re, im = -d[k] * w1 * w1, zero
                        else:
                            w2 = x2[av]
                            re, im = -3.0 * d[k] * w1 * w2, -d[k] * w1 * w1 * w1
                    elif order == 2:
                        d1 = x1[lv]
                        re = -d[k] * w1 * w1
                        im = 2.0 * d1 * w1
                    else:
                        d1, d2, w2 = x1[lv], x2[lv], x2[av]
                        re = -3.0 * d1 * w1 * w1 - 3.0 * d[k] * w1 * w2
                        im = 3.0 * d1 * w2 + 3.0 * d2 * w1 - d[k] * w1 * w1 * w1
                    if im is zero:
                        rhs[2 * l_idx] -= s * (re * cos[k])
                        rhs[2 * l_idx + 1] -= s * (re * sin[k])
                        continue
                    rhs[2 * l_idx] -= s * (re * cos[k] - im * sin[k])
                    rhs[2 * l_idx + 1] -= s * (re * sin[k] + im * cos[k])
        xk = np.empty_like(x0)
        xk[c.inputs] = u_k
        xk[c.unknown] = solve(fac, rhs)
        rates.append(xk)
    return rates, fac


def point_motion(
    c: Compiled, x: list[np.ndarray], terms: tuple[list, list, list] | None = None
) -> list[np.ndarray]:
    """Positions (and derivatives) of the named points as complex arrays (n_point, N).

    ``x`` holds the positions followed by as many rates as known; ``terms``
    are ``_vector_terms(c, x[0])`` when already computed.
    """
    if not c.points.shape[0]:
        return [np.zeros((0, x[0].shape[1]), dtype=complex) for _ in x]
    d, cos, sin = _vector_terms(c, x[0]) if terms is None else terms
    n_samples = x[0].shape[1]
    out = []
    zero = 0.0

    def der(level: int, var: int) -> np.ndarray | float:
        return x[level][var] if var >= 0 else zero

    for order in range(len(x)):
        p = np.zeros((c.points.shape[0], n_samples), dtype=complex)
        for i in range(c.points.shape[0]):
            for k in np.flatnonzero(c.points[i]):
                s = c.points[i, k]
                lv, av = c.length_var[k], c.angle_var[k]
                dk = d[k]
                if order == 0:
                    re, im = dk, zero
                elif order == 1:
                    re, im = der(1, lv), dk * der(1, av)
                elif order == 2:
                    d1, w1 = der(1, lv), der(1, av)
                    re = der(2, lv) - dk * w1 * w1
                    im = dk * der(2, av) + 2.0 * d1 * w1
                else:
                    d1, w1 = der(1, lv), der(1, av)
                    d2, w2 = der(2, lv), der(2, av)
                    re = der(3, lv) - 3.0 * d1 * w1 * w1 - 3.0 * dk * w1 * w2
                    im = dk * der(3, av) + 3.0 * d1 * w2 + 3.0 * d2 * w1 - dk * w1 * w1 * w1
                p[i] += s * ((re * cos[k] - im * sin[k]) + 1j * (re * sin[k] + im * cos[k]))
        out.append(p)
    return out
