"""Compiled (numba) kernels for the four-bar's closed form.

Imported only by :mod:`machdyn.jit` when the compiled backend is loaded; the
NumPy functions in :mod:`machdyn.fourbar` are the reference they are tested
against, sample by sample.

Why not just ``math.sin`` inside ``@njit``: a loop that calls libm cannot be
vectorised (pip's llvmlite has no SVML), so it runs no faster than NumPy, which
calls the same libm. The elementary functions below are written with
polynomials and selects only, so LLVM turns every loop into SIMD code (AVX2:
four samples per instruction). They are accurate to about 2 ulp (the tests
compare them with NumPy's libm over millions of arguments):

- :func:`sincos`: Cody–Waite reduction by π/2 in three parts (the first two
  with 33 significant bits, so ``q · part`` is exact for ``|q| < 2^20``) and
  Taylor polynomials on ``|r| ≤ π/4`` (truncation below 1e-19). Valid for
  ``|x| ≤`` :data:`SINCOS_LIMIT`; the callers fall back to NumPy beyond it.
- :func:`angle`: the angle of ``(x, y)`` in ``[0, 2π)``, reduced to
  ``atan(t)``, ``0 ≤ t ≤ 1``, by octant; two half-angle steps
  ``tan(u/2) = t / (1 + √(1 + t²))`` bring ``t`` below ``tan(π/16)``, where a
  13-term Taylor series is exact to 1e-19.

The kernels repeat the NumPy path's arithmetic (see :mod:`machdyn.fourbar` for
the derivation): the diagonal O4A and the law of cosines give the unit vectors
of links 3 and 4; every derivative order is the same 2×2 system solved by
Cramer's rule. Status codes are those of :mod:`machdyn.fourbar`.
"""

from __future__ import annotations

import math

import llvmlite.binding
import numpy as np

from ._numba_cache import njit
from .fourbar import INDETERMINATE, NOT_ASSEMBLABLE, OK, TOGGLE, WRONG_FORM

# The solve kernels write up to 14 arrays; LLVM vectorises a loop only if it may check
# at run time that they do not overlap, and by default allows 8 such checks (the loop
# then runs 4x slower, scalar). These are process-wide LLVM settings: numba code that
# the process compiles later sees them too (it may vectorise more loops), and they
# replace any value set before.
llvmlite.binding.set_option("machdyn", "-runtime-memory-check-threshold=256")
llvmlite.binding.set_option("machdyn", "-vectorize-memory-check-threshold=256")

#: Largest |x| for which :func:`sincos` is accurate (q · π/2 parts stay exact).
SINCOS_LIMIT = 1.0e6

# π/2 = _PIO2_1 + _PIO2_2 + _PIO2_3 (the first two have 33 significant bits).
_PIO2_1 = 1.5707963267341256
_PIO2_2 = 6.077100506303966e-11
_PIO2_3 = 2.0222662487959506e-21
_TWO_OVER_PI = 0.6366197723675814
_PI = math.pi
_HALF_PI = 0.5 * math.pi
_TWO_PI = 2.0 * math.pi


_jit = njit(cache=True, nogil=True, error_model="numpy")
_inline = njit(inline="always", error_model="numpy")


@_inline
def sincos(x):  # pragma: no cover - compiled
    """``(sin x, cos x)`` for ``|x| ≤ SINCOS_LIMIT``, SIMD-friendly (no branches)."""
    q = math.floor(x * _TWO_OVER_PI + 0.5)
    r = ((x - q * _PIO2_1) - q * _PIO2_2) - q * _PIO2_3
    z = r * r
    s = r + r * z * (
        -1 / 6
        + z
        * (
            1 / 120
            + z
            * (
                -1 / 5040
                + z
                * (
                    1 / 362880
                    + z
                    * (
                        -1 / 39916800
                        + z * (1 / 6227020800 + z * (-1 / 1307674368000 + z / 355687428096000))
                    )
                )
            )
        )
    )
    c = (
        1.0
        - 0.5 * z
        + z
        * z
        * (
            1 / 24
            + z
            * (
                -1 / 720
                + z
                * (
                    1 / 40320
                    + z
                    * (
                        -1 / 3628800
                        + z
                        * (
                            1 / 479001600
                            + z
                            * (
                                -1 / 87178291200
                                + z * (1 / 20922789888000 + z * (-1 / 6402373705728000))
                            )
                        )
                    )
                )
            )
        )
    )
    quadrant = q - 4.0 * math.floor(q * 0.25)  # q mod 4, as a float: 0, 1, 2 or 3
    odd = (quadrant == 1.0) | (quadrant == 3.0)
    sin_r = c if odd else s
    cos_r = s if odd else c
    sin_x = -sin_r if quadrant >= 2.0 else sin_r
    cos_x = -cos_r if (quadrant == 1.0) | (quadrant == 2.0) else cos_r
    return sin_x, cos_x


@_inline
def _atan01(t):  # pragma: no cover - compiled
    """``atan(t)`` for ``0 ≤ t ≤ 1``."""
    t = t / (1.0 + math.sqrt(1.0 + t * t))  # halve the angle: now ≤ π/8
    t = t / (1.0 + math.sqrt(1.0 + t * t))  # ≤ π/16, t ≤ 0.199
    z = t * t
    series = -1 / 3 + z * (
        1 / 5
        + z
        * (
            -1 / 7
            + z
            * (
                1 / 9
                + z
                * (
                    -1 / 11
                    + z
                    * (
                        1 / 13
                        + z
                        * (
                            -1 / 15
                            + z
                            * (
                                1 / 17
                                + z
                                * (-1 / 19 + z * (1 / 21 + z * (-1 / 23 + z * (1 / 25 - z / 27))))
                            )
                        )
                    )
                )
            )
        )
    )
    return 4.0 * (t + t * z * series)


@_inline
def angle(y, x):  # pragma: no cover - compiled
    """Angle of the vector ``(x, y)`` in ``[0, 2π)`` (NaN in, NaN out)."""
    ax = abs(x)
    ay = abs(y)
    steep = ay > ax
    a = _atan01((ax if steep else ay) / (ay if steep else ax))
    a = _HALF_PI - a if steep else a
    a = _PI - a if x < 0.0 else a
    a = _TWO_PI - a if y < 0.0 else a
    return 0.0 if a >= _TWO_PI else a


@_jit
def sincos_into(x, sin_out, cos_out):  # pragma: no cover - compiled
    """Element-wise :func:`sincos` (for the accuracy tests)."""
    for i in range(x.shape[0]):
        sin_out[i], cos_out[i] = sincos(x[i])


@_jit
def angle_into(y, x, out):  # pragma: no cover - compiled
    """Element-wise :func:`angle` (for the accuracy tests)."""
    for i in range(x.shape[0]):
        out[i] = angle(y[i], x[i])


@_inline
def _unit_vectors(r1, r2, r3, r4, c2, s2, branch, close_tol):  # pragma: no cover - compiled
    """Scaled lengths in, unit vectors of links 3 and 4 and a status code out."""
    ax = r2 * c2
    ay = r2 * s2
    sx = ax - r1
    dd = sx * sx + ay * ay
    inv = 1.0 / math.sqrt(dd)
    cg = (dd + (r4 * r4 - r3 * r3)) * inv * (1.0 / (2.0 * r4))
    status = OK if abs(cg) <= 1.0 + close_tol else NOT_ASSEMBLABLE
    status = INDETERMINATE if dd == 0.0 else status
    cg = min(max(cg, -1.0), 1.0)
    sg = branch * math.sqrt(1.0 - cg * cg)
    ux = sx * inv
    uy = ay * inv
    e4x = ux * cg + uy * sg
    e4y = uy * cg - ux * sg
    e3x = (r1 + r4 * e4x - ax) * (1.0 / r3)
    e3y = (r4 * e4y - ay) * (1.0 / r3)
    return e3x, e3y, e4x, e4y, status


@_jit
def positions(r1, r2, r3, r4, branch, close_tol, theta2, theta3, theta4, ok):  # pragma: no cover
    """θ3, θ4 (NaN where not assembled) and ``ok`` for the lengths scaled by the longest.

    Returns the number of inputs beyond :data:`SINCOS_LIMIT` (their results are
    not accurate; the caller then uses NumPy).
    """
    nan = np.nan
    big = 0
    for i in range(theta2.shape[0]):
        big += 1 if abs(theta2[i]) > SINCOS_LIMIT else 0
        s2, c2 = sincos(theta2[i])
        e3x, e3y, e4x, e4y, status = _unit_vectors(r1, r2, r3, r4, c2, s2, branch, close_tol)
        good = status == OK
        theta3[i] = angle(e3y, e3x) if good else nan
        theta4[i] = angle(e4y, e4x) if good else nan
        ok[i] = good
    return big


@_jit
def coupler_points(lengths, offsets, cos2, sin2, close_tol, points, ok):  # pragma: no cover
    """Coupler points of N four-bars (rows) at M input angles (columns), in their frames.

    ``lengths`` (N, 4) holds R1…R4 of each candidate; ``offsets`` (N, 3) holds
    p cos δ, p sin δ and the branch (±1); ``cos2``, ``sin2`` (M,) the input
    angles' cosines and sines. Writes ``points`` (N, M) complex (NaN where not
    assembled) and ``ok`` (N, M). The same arithmetic as
    :func:`machdyn.synthesis.atlas.coupler_points`' NumPy kernel; no inverse
    trigonometric function is needed, so this one is only square roots and divisions.
    """
    nan = np.nan
    for k in range(lengths.shape[0]):
        r1, r2, r3, r4 = lengths[k, 0], lengths[k, 1], lengths[k, 2], lengths[k, 3]
        scale = max(max(r1, r2), max(r3, r4))
        s1, s2, s3, s4 = r1 / scale, r2 / scale, r3 / scale, r4 / scale
        pr, pi, branch = offsets[k, 0], offsets[k, 1], offsets[k, 2]
        for i in range(cos2.shape[0]):
            c, s = cos2[i], sin2[i]
            e3x, e3y, _, _, status = _unit_vectors(s1, s2, s3, s4, c, s, branch, close_tol)
            blank = 0.0 if status == OK else nan  # NaN where not assembled
            x = r2 * c + pr * e3x - pi * e3y + blank
            y = r2 * s + pr * e3y + pi * e3x + blank
            points[k, i] = complex(x, y)
            ok[k, i] = status == OK


# --------------------------------------------------------------------------------------
# FourBar.solve: one kernel per derivative order. LLVM does not vectorise a loop that
# branches on the order or on a "has a coupler point" flag, so the order picks the
# kernel and the coupler point's arrays are either arrays or None: numba compiles a
# specialisation for each and prunes ``if coupler is not None`` at compile time.
# Parameters are named like the fields of FourBarMotion (the caller passes them by name).


@_inline
def _pose(theta2, scaled, branch, side, close_tol, toggle_tol):  # pragma: no cover - compiled
    """Unit vectors e2, e3, e4, sin(θ3 − θ4) and the status; e3, e4 NaN unless OK or TOGGLE."""
    e2y, e2x = sincos(theta2)
    sa, sb, sc, sd = scaled[0], scaled[1], scaled[2], scaled[3]
    e3x, e3y, e4x, e4y, st = _unit_vectors(sd, sa, sb, sc, e2x, e2y, branch, close_tol)
    st = WRONG_FORM if (st == OK) & (side * e2y <= 0.0) & (side != 0.0) else st
    s34 = e3y * e4x - e3x * e4y
    st = TOGGLE if (st == OK) & (abs(s34) < toggle_tol) else st
    bad = (st != OK) & (st != TOGGLE)
    nan = np.nan
    e3x = nan if bad else e3x
    e3y = nan if bad else e3y
    e4x = nan if bad else e4x
    e4y = nan if bad else e4y
    return e2x, e2y, e3x, e3y, e4x, e4y, s34, st


@_inline
def _store_pose(i, lengths, pose, theta3, theta4, A, B, status):  # pragma: no cover
    """Store the angles, joints A and B and the status of sample ``i``."""
    a, c, d = lengths[0], lengths[2], lengths[3]
    e2x, e2y, e3x, e3y, e4x, e4y, st = pose[0], pose[1], pose[2], pose[3], pose[4], pose[5], pose[7]
    status[i] = st
    theta3[i] = angle(e3y, e3x)
    theta4[i] = angle(e4y, e4x)
    A[i] = complex(a * e2x, a * e2y)
    B[i] = complex(d + c * e4x, c * e4y)


@_inline
def _coupler_point(lengths, offset, pose):  # pragma: no cover - compiled
    """The coupler point A + p e^{j(θ3 + δ)} and the unit vector e^{j(θ3 + δ)}."""
    a = lengths[0]
    p, cdelta, sdelta = offset[0], offset[1], offset[2]
    e2x, e2y, e3x, e3y = pose[0], pose[1], pose[2], pose[3]
    epx = cdelta * e3x - sdelta * e3y
    epy = cdelta * e3y + sdelta * e3x
    return a * e2x + p * epx, a * e2y + p * epy, epx, epy


@_inline
def _cramer(lengths, pose, kx, ky):  # pragma: no cover - compiled
    """Solve ``j b x3 e3 − j c x4 e4 = K``: x3 = −Re(K e^{−jθ4})/(b s34), x4 likewise."""
    e3x, e3y, e4x, e4y, s34, st = pose[2], pose[3], pose[4], pose[5], pose[6], pose[7]
    # NaN at a toggle. (Selecting NaN after dividing would stop LLVM vectorising the loop.)
    s34 = np.nan if st == TOGGLE else s34
    return -(kx * e4x + ky * e4y) / (lengths[1] * s34), -(kx * e3x + ky * e3y) / (lengths[2] * s34)


@_inline
def _velocity(lengths, pose, om2):  # pragma: no cover - compiled
    """ω3, ω4 from K = −j a ω2 e2, and V_P's input part j a ω2 e2."""
    a = lengths[0]
    e2x, e2y = pose[0], pose[1]
    w3, w4 = _cramer(lengths, pose, a * om2 * e2y, -a * om2 * e2x)
    return w3, w4, -a * om2 * e2y, a * om2 * e2x


@_inline
def _acceleration(lengths, pose, om2, w3, w4, alpha2):  # pragma: no cover - compiled
    """α3, α4 from K = −a(jα2 − ω2²) e2 + b ω3² e3 − c ω4² e4; and a(jα2 − ω2²) e2."""
    a, b, c = lengths[0], lengths[1], lengths[2]
    e2x, e2y, e3x, e3y, e4x, e4y = pose[0], pose[1], pose[2], pose[3], pose[4], pose[5]
    px = -a * om2 * om2 * e2x - a * alpha2 * e2y
    py = -a * om2 * om2 * e2y + a * alpha2 * e2x
    kx = -px + b * w3 * w3 * e3x - c * w4 * w4 * e4x
    ky = -py + b * w3 * w3 * e3y - c * w4 * w4 * e4y
    a3, a4 = _cramer(lengths, pose, kx, ky)
    return a3, a4, px, py


@_inline
def _jerk(lengths, pose, om2, w3, w4, alpha2, a3, a4, j2):  # pragma: no cover - compiled
    """Jerks from K = −a(jφ2 − 3α2ω2 − jω2³)e2 − b(−3α3ω3 − jω3³)e3 + c(−3α4ω4 − jω4³)e4.

    Also returns a(jφ2 − 3α2ω2 − jω2³) e2, J_P's input part.
    """
    a, b, c = lengths[0], lengths[1], lengths[2]
    e2x, e2y, e3x, e3y, e4x, e4y = pose[0], pose[1], pose[2], pose[3], pose[4], pose[5]
    g2r, g2i = -3.0 * alpha2 * om2, j2 - om2 * om2 * om2
    g3r, g3i = -3.0 * a3 * w3, -(w3 * w3 * w3)
    g4r, g4i = -3.0 * a4 * w4, -(w4 * w4 * w4)
    q2x, q2y = g2r * e2x - g2i * e2y, g2r * e2y + g2i * e2x
    q3x, q3y = g3r * e3x - g3i * e3y, g3r * e3y + g3i * e3x
    q4x, q4y = g4r * e4x - g4i * e4y, g4r * e4y + g4i * e4x
    j3, j4 = _cramer(lengths, pose, -a * q2x - b * q3x + c * q4x, -a * q2y - b * q3y + c * q4y)
    return j3, j4, a * q2x, a * q2y


@_inline
def _plus_relative(x0, y0, p, x, y, epx, epy):  # pragma: no cover - compiled
    """``(x0 + j y0) + p (x + j y) e_p``: joint A's motion plus the coupler point's about A."""
    return complex(x0 + p * (x * epx - y * epy), y0 + p * (x * epy + y * epx))


@_jit
def solve0(  # pragma: no cover - compiled
    lengths,
    scaled,
    offset,
    branch,
    side,
    tolerances,
    theta2,
    theta3,
    theta4,
    A,
    B,
    coupler,
    status,
):
    """Positions of every sample (see :func:`solve3` for the arguments)."""
    big = 0
    for i in range(theta2.shape[0]):
        big += 1 if abs(theta2[i]) > SINCOS_LIMIT else 0
        pose = _pose(theta2[i], scaled, branch, side, tolerances[0], tolerances[1])
        _store_pose(i, lengths, pose, theta3, theta4, A, B, status)
        if coupler is not None:
            px, py, _, _ = _coupler_point(lengths, offset, pose)
            coupler[i] = complex(px, py)
    return big


@_jit
def solve1(  # pragma: no cover - compiled
    lengths,
    scaled,
    offset,
    branch,
    side,
    tolerances,
    theta2,
    omega2,
    theta3,
    theta4,
    A,
    B,
    coupler,
    status,
    omega3,
    omega4,
    coupler_velocity,
):
    """Positions and velocities (see :func:`solve3` for the arguments)."""
    big = 0
    p = offset[0]
    for i in range(theta2.shape[0]):
        big += 1 if abs(theta2[i]) > SINCOS_LIMIT else 0
        pose = _pose(theta2[i], scaled, branch, side, tolerances[0], tolerances[1])
        _store_pose(i, lengths, pose, theta3, theta4, A, B, status)
        w3, w4, vx, vy = _velocity(lengths, pose, omega2[i])
        omega3[i], omega4[i] = w3, w4
        if coupler is not None:
            px, py, epx, epy = _coupler_point(lengths, offset, pose)
            coupler[i] = complex(px, py)
            coupler_velocity[i] = _plus_relative(vx, vy, p, 0.0, w3, epx, epy)
    return big


@_jit
def solve2(  # pragma: no cover - compiled
    lengths,
    scaled,
    offset,
    branch,
    side,
    tolerances,
    theta2,
    omega2,
    alpha2,
    theta3,
    theta4,
    A,
    B,
    coupler,
    status,
    omega3,
    omega4,
    coupler_velocity,
    alpha3,
    alpha4,
    coupler_acceleration,
):
    """Positions, velocities and accelerations (see :func:`solve3` for the arguments)."""
    big = 0
    p = offset[0]
    for i in range(theta2.shape[0]):
        big += 1 if abs(theta2[i]) > SINCOS_LIMIT else 0
        pose = _pose(theta2[i], scaled, branch, side, tolerances[0], tolerances[1])
        _store_pose(i, lengths, pose, theta3, theta4, A, B, status)
        w3, w4, vx, vy = _velocity(lengths, pose, omega2[i])
        omega3[i], omega4[i] = w3, w4
        a3, a4, ax, ay = _acceleration(lengths, pose, omega2[i], w3, w4, alpha2[i])
        alpha3[i], alpha4[i] = a3, a4
        if coupler is not None:
            px, py, epx, epy = _coupler_point(lengths, offset, pose)
            coupler[i] = complex(px, py)
            coupler_velocity[i] = _plus_relative(vx, vy, p, 0.0, w3, epx, epy)
            coupler_acceleration[i] = _plus_relative(ax, ay, p, -w3 * w3, a3, epx, epy)
    return big


@_jit
def solve3(  # pragma: no cover - compiled
    lengths,
    scaled,
    offset,
    branch,
    side,
    tolerances,
    theta2,
    omega2,
    alpha2,
    jerk2,
    theta3,
    theta4,
    A,
    B,
    coupler,
    status,
    omega3,
    omega4,
    coupler_velocity,
    alpha3,
    alpha4,
    coupler_acceleration,
    jerk3,
    jerk4,
    coupler_jerk,
):
    """Positions, velocities, accelerations and jerks of every sample, in one pass.

    ``lengths`` = (a, b, c, d) = (R2, R3, R4, R1) and ``scaled`` the same divided
    by the longest; ``offset`` = (p, cos δ, sin δ) places the coupler point;
    ``branch`` is ±1; ``side`` is 0, or the sign θ2 must have (GRCR and GRRC
    forms); ``tolerances`` = (close, toggle). The inputs θ2, ω2, α2, jerk2 and
    the outputs are 1-D arrays of one length; the coupler point's outputs are
    None when it is not wanted. Returns the number of inputs beyond
    :data:`SINCOS_LIMIT` (see :func:`positions`).
    """
    big = 0
    p = offset[0]
    for i in range(theta2.shape[0]):
        big += 1 if abs(theta2[i]) > SINCOS_LIMIT else 0
        pose = _pose(theta2[i], scaled, branch, side, tolerances[0], tolerances[1])
        _store_pose(i, lengths, pose, theta3, theta4, A, B, status)
        w3, w4, vx, vy = _velocity(lengths, pose, omega2[i])
        omega3[i], omega4[i] = w3, w4
        a3, a4, ax, ay = _acceleration(lengths, pose, omega2[i], w3, w4, alpha2[i])
        alpha3[i], alpha4[i] = a3, a4
        j3, j4, jx, jy = _jerk(lengths, pose, omega2[i], w3, w4, alpha2[i], a3, a4, jerk2[i])
        jerk3[i], jerk4[i] = j3, j4
        if coupler is not None:
            px, py, epx, epy = _coupler_point(lengths, offset, pose)
            coupler[i] = complex(px, py)
            coupler_velocity[i] = _plus_relative(vx, vy, p, 0.0, w3, epx, epy)
            coupler_acceleration[i] = _plus_relative(ax, ay, p, -w3 * w3, a3, epx, epy)
            jr, ji = -3.0 * a3 * w3, j3 - w3 * w3 * w3
            coupler_jerk[i] = _plus_relative(jx, jy, p, jr, ji, epx, epy)
    return big


#: The kernel for each derivative order.
SOLVERS = (solve0, solve1, solve2, solve3)

#: Each solver's array parameters, in order (after the six fixed ones): the names of
#: the inputs (theta2 …) and of FourBarMotion's fields, so the caller passes by name.
ARRAYS = tuple(
    solver.py_func.__code__.co_varnames[6 : solver.py_func.__code__.co_argcount]
    for solver in SOLVERS
)


def warm_up() -> None:
    """Compile, or load from numba's cache, the kernels machdyn uses most.

    :func:`positions` and :func:`solve3` (with and without a coupler point);
    the lower orders' kernels are compiled when first used (then cached too).
    """
    x = np.zeros(1)
    positions(1.0, 0.5, 1.0, 1.0, 1.0, 1e-12, x, x.copy(), x.copy(), np.zeros(1, np.bool_))
    fixed = (np.ones(4), np.ones(4), np.zeros(3), 1.0, 0.0, np.array([1e-12, 2e-6]))
    for point in (None, np.zeros(1, complex)):
        solve3(
            *fixed,
            x, x, x, x,
            np.empty(1), np.empty(1), np.empty(1, complex), np.empty(1, complex),
            point, np.empty(1, np.uint8),
            np.empty(1), np.empty(1), None if point is None else point.copy(),
            np.empty(1), np.empty(1), None if point is None else point.copy(),
            np.empty(1), np.empty(1), None if point is None else point.copy(),
        )  # fmt: skip
