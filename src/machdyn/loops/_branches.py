"""Branches of a loop system, kept group by group.

A sweep's branch is the sign of every group's determinant at its start
(:mod:`machdyn.loops._compiled` explains the groups). When Newton lands on a
pose where a group has the other sign — after an assembly gap, past a change
point, from a poor prediction — the group is moved to its root of the wanted
sign and the groups after it are re-assembled (:func:`assemble`). A dyad's
loop, with everything before it known, reads ``K + P e^{jθa} + … = 0`` and its
two roots are mirror images (Norton, *Design of Machinery*, §4.5: the "open"
and "crossed" solutions), both in closed form:

* two unknown angles (circle–circle; ``P``, ``Q`` the signed lengths on each
  angle): the law of cosines in the triangle ``P``, ``Q``, ``−K``; the other
  root reflects both vectors across the line of ``K`` (angle ψ): ``θ' = 2ψ − θ``;
* an angle and a slide along a known direction ``E`` (circle–line):
  ``sin(θ − φ) = −Im(K e^{−jφ}) / P``; the other root is ``θ' = 2φ + π − θ``
  with the slide mirrored about the foot of the perpendicular;
* the angle and the length of one vector: ``θ = arg(−K)``, ``S d + P = |K|``;
  the other root turns the vector by π with its length through zero.

Linear groups have one root (one Newton step on the group solves them); other
groups (triads) are left to Newton.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._compiled import DYAD_ANGLES, DYAD_SAME, DYAD_SLIDE, LINEAR, Compiled, Group
from ._equations import residual_and_jacobian
from ._newton import NewtonResult, newton

__all__ = ["assemble", "fix_branches", "reflect", "wrong_groups"]

_TWO_PI = 2.0 * np.pi


@dataclass(frozen=True)
class _Dyad:
    """A dyad's loop at the states ``x``: its known part and unknown coefficients."""

    known: np.ndarray  # K, complex (N,)
    p: np.ndarray  # signed length(s) on the first angle (real)
    q: np.ndarray  # DYAD_ANGLES: on the second angle; SLIDE: E (complex); SAME: S


def _dyad(c: Compiled, g: Group, x: np.ndarray) -> _Dyad:
    terms = c.loop_terms[g.loop]
    a, b = g.angle, g.length
    n = x.shape[1]

    def unit(k: int) -> np.ndarray:
        av = int(c.angle_var[k])
        return np.exp(1j * (x[av] if av >= 0 else np.full(n, c.angle_const[k])))

    def length(k: int) -> np.ndarray:
        lv = int(c.length_var[k])
        return x[lv] if lv >= 0 else np.full(n, c.length_const[k])

    known, p, q = np.zeros(n, complex), np.zeros(n), np.zeros(n)
    if g.kind == DYAD_SLIDE:
        q = np.zeros(n, complex)
    for k, s in terms:
        av, lv = int(c.angle_var[k]), int(c.length_var[k])
        if av == a and lv != b:
            p = p + s * length(k)
        elif g.kind == DYAD_ANGLES and av == b:
            q = q + s * length(k)
        elif g.kind == DYAD_SLIDE and lv == b:
            q = q + s * unit(k)
        elif g.kind == DYAD_SAME and lv == b:
            q = q + s
        else:
            known = known + s * length(k) * unit(k)
    return _Dyad(known, p, q)


def reflect(c: Compiled, g: Group, x: np.ndarray) -> np.ndarray:
    """The state ``x`` (n_var, N) with dyad group ``g`` moved to its other root.

    Angles are shifted by whole turns to stay next to the values they replace
    (angles are not wrapped along a sweep).
    """
    d = _dyad(c, g, x)
    a, b = g.angle, g.length
    out = x.copy()
    with np.errstate(invalid="ignore", divide="ignore"):
        if g.kind == DYAD_ANGLES:
            psi = np.angle(d.known)
            out[a], out[b] = 2.0 * psi - x[a], 2.0 * psi - x[b]
            _near(out, x, (a, b))
        elif g.kind == DYAD_SLIDE:
            phi, e = np.angle(d.q), np.abs(d.q)
            out[a] = 2.0 * phi + np.pi - x[a]
            out[b] = -2.0 * (d.known * np.exp(-1j * phi)).real / e - x[b]
            _near(out, x, (a,))
        elif g.kind == DYAD_SAME:
            out[a] = x[a] + np.pi
            out[b] = -2.0 * d.p / d.q - x[b]
            _near(out, x, (a,))
    return out


def _a_root(c: Compiled, g: Group, x: np.ndarray) -> np.ndarray:
    """The state ``x`` with dyad group ``g`` at one of its roots (NaN where none).

    Angles are taken in the whole turn next to their values in ``x``.
    """
    d = _dyad(c, g, x)
    a, b = g.angle, g.length
    out = x.copy()
    with np.errstate(invalid="ignore", divide="ignore"):
        if g.kind == DYAD_ANGLES:
            v = -d.known  # P e^{jθa} + Q e^{jθb} = V
            p, q = np.abs(d.p), np.abs(d.q)
            r = np.abs(v)
            cos_t = (p * p + r * r - q * q) / (2.0 * p * r)
            alpha = np.angle(v) + np.arccos(np.where(np.abs(cos_t) <= 1.0, cos_t, np.nan))
            beta = np.angle(v - p * np.exp(1j * alpha))
            out[a] = alpha + np.where(d.p < 0, np.pi, 0.0)
            out[b] = beta + np.where(d.q < 0, np.pi, 0.0)
            _near(out, x, (a, b))
        elif g.kind == DYAD_SLIDE:
            phi, e = np.angle(d.q), np.abs(d.q)
            k = d.known * np.exp(-1j * phi)
            sin_t = -k.imag / d.p
            t = np.arcsin(np.where(np.abs(sin_t) <= 1.0, sin_t, np.nan))
            out[a] = phi + t
            out[b] = (-k.real - d.p * np.cos(t)) / e
            _near(out, x, (a,))
        elif g.kind == DYAD_SAME:
            out[a] = np.angle(-d.known)
            out[b] = (np.abs(d.known) - d.p) / d.q
            _near(out, x, (a,))
    return out


def _near(out: np.ndarray, ref: np.ndarray, angles: tuple[int, ...]) -> None:
    """Shift the angles ``out[angles]`` by whole turns to lie within π of ``ref``."""
    for v in angles:
        turns = np.round((out[v] - ref[v]) / _TWO_PI)
        out[v] -= _TWO_PI * np.where(np.isfinite(turns), turns, 0.0)


def wrong_groups(
    c: Compiled, gdet: np.ndarray, grc: np.ndarray, want: np.ndarray, sing_tol: float
) -> np.ndarray:
    """(n_groups, N) mask: the group's determinant has the other sign than ``want``.

    Groups at a toggle (reciprocal condition below ``sing_tol``: the two roots
    meet, the sign means nothing) and samples without a determinant (NaN) are
    not counted.
    """
    with np.errstate(invalid="ignore"):
        return (np.sign(gdet) == -want[:, None]) & (grc >= sing_tol)


def assemble(
    c: Compiled, x: np.ndarray, want: np.ndarray, start: int = 0
) -> tuple[np.ndarray, np.ndarray]:
    """Assemble the groups from ``start`` on, in solving order, on the branch ``want``.

    Each dyad is put at its root with the wanted determinant sign (closed form),
    each linear group solved by one Newton step on its own rows; other groups
    keep their values in ``x`` (n_var, N) for Newton to finish. Returns the new
    states and, per sample, the first group that cannot be assembled (-1: none).
    """
    x = x.copy()
    failed = np.full(x.shape[1], -1, dtype=np.int16)
    for gi in range(start, len(c.groups)):
        g = c.groups[gi]
        if g.kind.startswith("dyad"):
            x = _a_root(c, g, x)
            sign = np.sign(_group_det(c, g, x))
            x = np.where(sign == -want[gi], reflect(c, g, x), x)
        elif g.kind == LINEAR:
            rows, cols = list(g.rows), c.unknown[list(g.cols)]
            f, jac = residual_and_jacobian(c, np.nan_to_num(x), cols)
            block = np.moveaxis(jac[rows], -1, 0)
            with np.errstate(invalid="ignore", divide="ignore"):
                step = np.linalg.solve(block, -f[rows].T[..., None])[..., 0].T
            x[cols] += step
        bad = ~np.isfinite(x[c.unknown]).all(axis=0) & (failed < 0)
        failed[bad] = gi
    return x, failed


def _group_det(c: Compiled, g: Group, x: np.ndarray) -> np.ndarray:
    """The determinant of group ``g``'s block of ``J_q`` at the states ``x``."""
    rows = list(g.rows)
    _, jac = residual_and_jacobian(c, np.nan_to_num(x), c.unknown[list(g.cols)])
    block = jac[rows]
    return block[0, 0] * block[1, 1] - block[0, 1] * block[1, 0]


def fix_branches(
    c: Compiled,
    res: NewtonResult,
    u: np.ndarray,
    want: np.ndarray,
    sing_tol: float,
    tol: float,
    max_iter: int = 30,
) -> NewtonResult:
    """Move the converged samples of ``res`` whose groups have the wrong sign to ``want``.

    The first dyad (in solving order) with the other sign is reflected to its
    other root, the groups after it are re-assembled (:func:`assemble`), and the
    pose is polished by Newton. Samples whose wrong group is no dyad, or whose
    re-assembled pose does not converge, are left as they are: the caller flags
    them (:func:`wrong_groups` says which group).
    """
    wrong = res.converged & wrong_groups(c, res.gdet, res.grc, want, sing_tol)
    if not wrong.any():
        return res
    first = np.where(wrong.any(axis=0), wrong.argmax(axis=0), -1)
    for gi, g in enumerate(c.groups):
        bad = np.flatnonzero(first == gi)
        if bad.size == 0 or not g.kind.startswith("dyad"):
            continue
        x = np.empty((len(c.names), bad.size))
        x[c.inputs] = u[:, bad]
        x[c.unknown] = res.q[:, bad]
        x, _ = assemble(c, reflect(c, g, x), want, gi + 1)
        seed = x[c.unknown]
        ok = np.isfinite(seed).all(axis=0)
        if not ok.any():
            continue
        new = newton(c, seed[:, ok], u[:, bad[ok]], max_iter=max_iter, tol=tol)
        good = new.converged & ~wrong_groups(c, new.gdet, new.grc, want, sing_tol).any(axis=0)
        if good.any():
            res = _replace(res, bad[ok][good], new.take(good))
    return res


def _replace(res: NewtonResult, idx: np.ndarray, new: NewtonResult) -> NewtonResult:
    """``res`` with the samples ``idx`` replaced by ``new``'s."""
    fields = {}
    for name in ("q", "converged", "residual", "tan", "det", "rcond", "gdet", "grc"):
        arr = getattr(res, name).copy()
        arr[..., idx] = getattr(new, name)
        fields[name] = arr
    return NewtonResult(**fields)
