"""Compiled (numba) kernel of the atlas build: circuit curves resampled by arc length.

Imported only when :mod:`machdyn.jit` lets the compiled kernels serve (it is
loaded with them); :func:`machdyn.synthesis.circuits.circuit_points` followed
by :func:`machdyn.synthesis.descriptor.resample_closed` is the NumPy reference
it is tested against. One pass per linkage, no temporaries: the circuit's
points go to a small buffer, then straight to their evenly spaced samples.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .._kernels import _unit_vectors, sincos

__all__ = ["even_circuit_curves"]


@njit(cache=True, nogil=True, error_model="numpy")
def even_circuit_curves(params, m, out):  # pragma: no cover - compiled
    """Circuit curves of linkages resampled at ``out.shape[1]`` points evenly spaced by arc length.

    ``params`` (N, 10): r1 r2 r3 r4, p cos δ, p sin δ, circuit centre, half
    width, crank flag (1/0), circuit sign; ``m`` circuit samples; ``out`` (N, M)
    complex.
    """
    n_out = out.shape[1]
    xs = np.empty(m + 1)
    ys = np.empty(m + 1)
    cum = np.empty(m + 1)
    two_pi = 2.0 * math.pi
    for k in range(params.shape[0]):
        r1, r2, r3, r4 = params[k, 0], params[k, 1], params[k, 2], params[k, 3]
        pr, pi = params[k, 4], params[k, 5]
        centre, half, crank, sign = params[k, 6], params[k, 7], params[k, 8], params[k, 9]
        scale = max(max(r1, r2), max(r3, r4))
        s1, s2, s3, s4 = r1 / scale, r2 / scale, r3 / scale, r4 / scale
        for i in range(m):
            u = two_pi * i / m
            if crank > 0.5:
                theta2 = u
                branch = sign
            else:
                su, cu = sincos(u)
                theta2 = centre + half * cu
                branch = 1.0 if su >= 0.0 else -1.0
            s, c = sincos(theta2)
            e3x, e3y, _, _, _ = _unit_vectors(s1, s2, s3, s4, c, s, branch, 1.0)
            xs[i] = r2 * c + pr * e3x - pi * e3y
            ys[i] = r2 * s + pr * e3y + pi * e3x
        xs[m] = xs[0]
        ys[m] = ys[0]
        cum[0] = 0.0
        for i in range(m):
            cum[i + 1] = cum[i] + math.hypot(xs[i + 1] - xs[i], ys[i + 1] - ys[i])
        total = cum[m]
        j = 0
        for q in range(n_out):
            target = total * q / n_out
            while j < m - 1 and cum[j + 1] <= target:
                j += 1
            width = cum[j + 1] - cum[j]
            t = (target - cum[j]) / width if width > 0.0 else 0.0
            t = min(max(t, 0.0), 1.0)
            out[k, q] = complex(xs[j] + t * (xs[j + 1] - xs[j]), ys[j] + t * (ys[j + 1] - ys[j]))
