"""Coupler curves of many four-bars at once (the Hrones–Nelson atlas idea, as data).

Hrones and Nelson (1951) drew ~7000 coupler curves of crank-rockers with a
unit crank, over a grid of the other links and of coupler points; the notes
(Ch. 3, "Coupler Curves ... Hrones–Nelson atlas") use it to pick a linkage by
the shape of its curve. :func:`coupler_points` is the vectorised kernel behind
it and behind path synthesis: link lengths are *arrays* (one per candidate)
and the result is a 2-D (candidate, input angle) array, computed in chunks
without a Python loop over samples.

Closed form (the notes' "direct method", as in :mod:`machdyn.fourbar`): with
``A = a e^{jθ2}`` and the diagonal ``s = A − d``, the law of cosines in
triangle ``O4 A B`` gives ``cos γ = (c² − b² + |s|²) / (2 c |s|)``; link 4 is
``e^{jθ4} = (s/|s|) e^{−j·branch·γ}``, ``B = d + c e^{jθ4}``, and the coupler
point is ``P = A + (p e^{jδ} / b)(B − A)``.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import jit
from .._parallel import require_memory
from .._validate import TINY, choice, count, finite_array, positive
from ..errors import InputError
from ..fourbar import _CLOSE_TOL, OK, _unit_vectors

__all__ = ["CouplerAtlas", "atlas", "coupler_points"]

#: Elements (candidates × angles) per chunk: keeps the temporaries in cache.
_CHUNK_ELEMENTS = 1 << 13


def coupler_points(
    r1: Any,
    r2: Any,
    r3: Any,
    r4: Any,
    p: Any,
    delta: Any,
    theta2: Any,
    branch: Any = 1,
) -> tuple[np.ndarray, np.ndarray]:
    """Coupler-point positions of N four-bars at M input angles, in their own frames.

    Parameters
    ----------
    r1, r2, r3, r4 : array_like, shape (N,) or scalar
        Ground, input, coupler and output lengths of each candidate.
    p, delta : array_like, shape (N,) or scalar
        Coupler point: distance from A and angle from line AB (radians).
    theta2 : array_like, shape (M,)
        Input angles (shared by all candidates).
    branch : array_like of {1, −1}, shape (N,) or scalar
        Sign of φ12 = θ4 − θ3 (the assembly).

    Returns
    -------
    points : ndarray of complex, shape (N, M)
        Coupler points (``O2`` at the origin, ground along +x); NaN where
        the candidate cannot be assembled.
    ok : ndarray of bool, shape (N, M)
        False where it cannot be assembled at that input.

    Examples
    --------
    Two candidates at once; the first is the notes' HW 6 linkage with its
    coupler point at joint B (p = R3, δ = 0), so ``P`` is ``B``:

    >>> pts, ok = coupler_points([8, 8], [4, 4], [7, 7], [6, 6], [7, 3], [0, 0.5], [0.0, 1.0])
    >>> pts.shape, bool(ok.all())
    ((2, 2), True)
    >>> from machdyn.fourbar import FourBar
    >>> m = FourBar(8, 4, 7, 6).solve(np.array([0.0, 1.0]))
    >>> bool(np.allclose(pts[0], m.B))
    True
    """
    theta2 = np.ravel(finite_array("theta2", theta2, "radian"))
    if theta2.size == 0:
        raise InputError("theta2", "needs at least one input angle")
    arrays = [
        np.ravel(finite_array(n, v))
        for n, v in zip(_NAMES, (r1, r2, r3, r4, p, delta, branch), strict=True)
    ]
    n = max(a.size for a in arrays)
    cols = []
    for name, a in zip(_NAMES, arrays, strict=True):
        if a.size not in (1, n):
            raise InputError(name, f"must have one value per candidate ({n}) or be a scalar")
        cols.append(np.broadcast_to(a, (n,)))
    r1, r2, r3, r4, p, delta, branch = cols
    for name, a in zip(_NAMES[:4], (r1, r2, r3, r4), strict=True):
        if np.any(a < TINY):
            raise InputError(name, f"every length must be positive (at least {TINY:g})")
    if np.any(np.abs(branch) != 1.0):
        raise InputError("branch", "must be 1 or -1 (the sign of phi12) for every candidate")
    require_memory("theta2", 17 * n * theta2.size, f"{n:,} candidates x {theta2.size:,} angles")
    return _kernel(r1, r2, r3, r4, p, delta, theta2, branch)


def _kernel_inputs(r1, r2, r3, r4, p, delta, branch) -> tuple[np.ndarray, np.ndarray]:
    """The rows the compiled ``coupler_points`` kernels take, one per linkage.

    The lengths, and the coupler point's offsets with the branch's sign.
    """
    lengths = np.column_stack([r1, r2, r3, r4]).astype(float)
    sign = np.where(branch >= 0, 1.0, -1.0)
    return lengths, np.column_stack([p * np.cos(delta), p * np.sin(delta), sign])


def _kernel(
    r1: np.ndarray,
    r2: np.ndarray,
    r3: np.ndarray,
    r4: np.ndarray,
    p: np.ndarray,
    delta: np.ndarray,
    theta2: np.ndarray,
    branch: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`coupler_points` on validated 1-D arrays of one length (no checks).

    Compiled when :mod:`machdyn.jit` says so (it counts these evaluations like
    four-bar poses), NumPy otherwise.
    """
    n = r1.size
    m = theta2.size
    points = np.empty((n, m), dtype=complex)
    ok = np.empty((n, m), dtype=bool)
    c2, s2 = np.cos(theta2), np.sin(theta2)
    compiled = jit.kernels(n * m)
    if compiled is not None:
        lengths, offsets = _kernel_inputs(r1, r2, r3, r4, p, delta, branch)

        def kernel(sl: slice) -> None:
            compiled.coupler_points(
                lengths[sl], offsets[sl], c2, s2, _CLOSE_TOL, points[sl], ok[sl]
            )

        if jit.run(kernel, n):
            return points, ok
    start = time.perf_counter()
    # per-candidate constants, as column vectors: P = A + p e^{jδ} e^{jθ3}
    pr = (p * np.cos(delta))[:, None]
    pi = (p * np.sin(delta))[:, None]
    sign = np.where(branch >= 0, 1.0, -1.0)[:, None]
    r1c, r2c, r3c, r4c = (r[:, None] for r in (r1, r2, r3, r4))
    rows = max(1, _CHUNK_ELEMENTS // max(m, 1))
    for i in range(0, n, rows):
        sl = slice(i, min(n, i + rows))
        e3x, e3y, _, _, status = _unit_vectors(r1c[sl], r2c[sl], r3c[sl], r4c[sl], c2, s2, sign[sl])
        good = status == OK
        # NaN where not assembled, without a boolean scatter: add 0 or NaN
        blank = np.where(good, 0.0, np.nan)
        block = points[sl]
        block.real = r2c[sl] * c2 + pr[sl] * e3x - pi[sl] * e3y + blank
        block.imag = r2c[sl] * s2 + pr[sl] * e3y + pi[sl] * e3x + blank
        ok[sl] = good
    jit.charge(time.perf_counter() - start)
    return points, ok


_NAMES = ("r1", "r2", "r3", "r4", "p", "delta", "branch")


@dataclass(frozen=True, eq=False)
class CouplerAtlas:
    """Coupler curves of a grid of four-bars, as arrays.

    Attributes
    ----------
    lengths : ndarray, shape (N, 4)
        ``r1, r2, r3, r4`` of each linkage.
    coupler : ndarray, shape (N, 2)
        ``p, delta`` of each coupler point.
    theta2 : ndarray, shape (M,)
        Input angles.
    branch : int
        Sign of φ12 (the assembly) of every curve.
    points : ndarray of complex, shape (N, M)
        Coupler points, in each linkage's own frame (NaN where not assembled).
    ok : ndarray of bool, shape (N, M)
        Where each linkage is assembled.
    """

    lengths: np.ndarray
    coupler: np.ndarray
    theta2: np.ndarray
    branch: int
    points: np.ndarray
    ok: np.ndarray

    def __len__(self) -> int:
        return int(self.lengths.shape[0])

    @property
    def full_turn(self) -> np.ndarray:
        """True for linkages assembled at every input angle (the crank's whole curve)."""
        return self.ok.all(axis=1)

    def to_pandas(self):
        """Long table: one row per (linkage, angle) (pandas imported lazily)."""
        import pandas as pd

        n, m = self.points.shape
        idx = np.repeat(np.arange(n), m)
        return pd.DataFrame(
            {
                "linkage": idx,
                "r1": self.lengths[idx, 0],
                "r2": self.lengths[idx, 1],
                "r3": self.lengths[idx, 2],
                "r4": self.lengths[idx, 3],
                "p": self.coupler[idx, 0],
                "delta": self.coupler[idx, 1],
                "theta2": np.tile(self.theta2, n),
                "x": self.points.real.ravel(),
                "y": self.points.imag.ravel(),
                "ok": self.ok.ravel(),
            }
        )

    def plot(self, indices: Any = None, ax=None):
        """Plot some curves (matplotlib imported lazily); returns the axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots()
        chosen = range(min(len(self), 20)) if indices is None else np.ravel(indices)
        for i in chosen:
            ax.plot(self.points[i].real, self.points[i].imag, lw=0.8)
        ax.set_aspect("equal")
        ax.set_xlabel("x")
        ax.set_ylabel("y")
        return ax


def atlas(
    r1: Any,
    r3: Any,
    r4: Any,
    p: Any,
    delta: Any,
    *,
    r2: float = 1.0,
    n: int = 360,
    branch: int = 1,
) -> CouplerAtlas:
    """Coupler curves for every combination of the given values (a Hrones–Nelson grid).

    Parameters
    ----------
    r1, r3, r4 : array_like
        Values of the ground, coupler and output lengths (the grid's axes).
    p, delta : array_like
        Values of the coupler point's distance from A and angle from AB.
    r2 : float
        Crank length (1 in the atlas: every length is in crank lengths).
    n : int
        Input angles per curve, evenly spaced over a full turn.
    branch : {1, −1}
        Assembly (sign of φ12).

    Examples
    --------
    >>> at = atlas([2, 3], [2.5, 3], [2, 3], [1.0], np.radians([0, 60]), n=90)
    >>> len(at), at.points.shape
    (16, (16, 90))
    >>> bool(at.full_turn[0])        # 2, 1, 2.5, 2: a Grashof crank-rocker
    True
    """
    branch = choice("branch", branch, (1, -1))
    n = count("n", n, minimum=2, bytes_each=8)
    r2 = positive("r2", r2)
    axes = [
        np.ravel(finite_array(k, v))
        for k, v in zip(("r1", "r3", "r4", "p", "delta"), (r1, r3, r4, p, delta), strict=True)
    ]
    grid = np.meshgrid(*axes, indexing="ij")
    g1, g3, g4, gp, gd = (g.ravel() for g in grid)
    g2 = np.full_like(g1, float(r2))
    theta2 = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    points, ok = coupler_points(g1, g2, g3, g4, gp, gd, theta2, branch)
    return CouplerAtlas(
        np.column_stack([g1, g2, g3, g4]), np.column_stack([gp, gd]), theta2, branch, points, ok
    )
