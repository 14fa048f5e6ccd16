"""Shape descriptors of closed curves, and the fit of one curve onto another.

A coupler curve is compared with a target by its *shape* only: where it is,
how it is turned, how big it is, where it starts and which way round it runs
must not matter. The descriptor here is the normalised Fourier series of the
curve sampled evenly by arc length (elliptic Fourier descriptors in complex
form; Kuhl & Giardina, *Comput. Graph. Image Process.* 18, 1982, and, for
coupler curves, Ullah & Kota, *J. Mech. Des.* 119, 1997):

* with ``z_j`` (``j = 0 … m−1``) the curve at equal arc-length steps, its
  coefficients are ``c_k = (1/m) Σ_j z_j e^{−2πi jk/m}``;
* translation moves only ``c_0``: it is dropped;
* scale multiplies every ``c_k``: they are divided by the norm of the kept
  ones (``k = ±1 … ±K``), so the descriptor is a unit vector;
* a rotation by ``φ`` and a start moved by ``τ`` (radians of the arc-length
  parameter) multiply ``c_k`` by ``e^{i(φ + kτ)}``: choosing ``φ, τ`` so that
  ``c_1`` and ``c_{−1}`` become real and positive removes both, up to
  ``(φ, τ) + (π, π)``, which flips the sign of the even harmonics;
* running the curve the other way round swaps ``c_k`` and ``c_{−k}``.

The atlas stores one of the two sign choices; a query is compared in its four
variants (sign choice × direction) and the best counts. Because the descriptor
is a unit vector, the squared distance is ``2 − 2 q·x``: a nearest-neighbour
search is one matrix product (BLAS) and a partial sort.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..errors import InputError

# Internal to machdyn.synthesis, which re-exports the public names (Atlas, build_atlas,
# open_atlas, path_from_atlas, curve_descriptor, ...); the fuzz suite fuzzes those.
__all__: list[str] = []

#: Harmonics kept on each side (k = ±1 … ±HARMONICS): 4·HARMONICS floats per curve.
HARMONICS = 8
#: Arc-length samples per curve for the descriptor (a power of two for the FFT).
SAMPLES = 128


def resample_closed(z: Any, m: int = SAMPLES) -> np.ndarray:
    """Resample closed curves (rows) at ``m`` points evenly spaced by arc length.

    Parameters
    ----------
    z : array_like of complex, shape (..., n)
        Points along each closed curve, in order (the last joins the first).
    m : int
        Samples wanted per curve.

    Returns
    -------
    ndarray of complex, shape (..., m)
        Starting at each curve's first point. A curve of zero length gives
        its first point ``m`` times.

    Examples
    --------
    A square traced by 4 corners becomes 8 points, two per side:

    >>> resample_closed([0, 1, 1 + 1j, 1j], 8)
    array([0. +0.j , 0.5+0.j , 1. +0.j , 1. +0.5j, 1. +1.j , 0.5+1.j ,
           0. +1.j , 0. +0.5j])
    """
    z = np.asarray(z, dtype=complex)
    shape = z.shape
    z = z.reshape(-1, shape[-1])
    rows, n = z.shape
    seg = np.abs(np.roll(z, -1, axis=1) - z)
    cum = np.zeros((rows, n + 1))
    np.cumsum(seg, axis=1, out=cum[:, 1:])
    total = cum[:, -1:]
    safe = np.where(total > 0.0, total, 1.0)
    # one monotone array for all rows: row r's arc fractions lie in [r, r + 1]
    offsets = np.arange(rows, dtype=float)[:, None]
    flat = (cum / safe + offsets).ravel()
    wanted = (np.arange(m) / m + offsets).ravel()
    idx = np.searchsorted(flat, wanted, side="right") - 1
    idx = np.minimum(idx, flat.size - 2)
    row = idx // (n + 1)
    j = idx - row * (n + 1)
    j = np.minimum(j, n - 1)
    lo = flat[row * (n + 1) + j]
    hi = flat[row * (n + 1) + j + 1]
    width = hi - lo
    u = np.where(width > 0.0, (wanted - lo) / np.where(width > 0.0, width, 1.0), 0.0)
    a = z[row, j]
    b = z[row, (j + 1) % n]
    out = a + np.clip(u, 0.0, 1.0) * (b - a)
    return out.reshape(*shape[:-1], m)


def curve_descriptor(z: Any, harmonics: int = HARMONICS, *, resampled: bool = False) -> np.ndarray:
    """Normalised Fourier descriptor of closed curves (rows), as float32 unit vectors.

    Parameters
    ----------
    z : array_like of complex, shape (..., n)
        Closed curves (see :func:`resample_closed`).
    harmonics : int
        ``K``: harmonics kept on each side.
    resampled : bool
        True if ``z`` is already evenly spaced by arc length (skips resampling).

    Returns
    -------
    ndarray of float32, shape (..., 4K)
        ``Re, Im`` of ``c_{−K} … c_{−1}, c_1 … c_K`` after normalisation; zero
        for a curve of zero size.

    Examples
    --------
    An ellipse moved, turned, scaled and started elsewhere has the same descriptor:

    >>> t = np.linspace(0, 2 * np.pi, 200, endpoint=False)
    >>> e = 2 * np.cos(t) + 1j * (np.sin(t) + 0.3 * np.sin(2 * t))
    >>> d1 = curve_descriptor(e)
    >>> d2 = curve_descriptor(5 + 2j + 3 * np.exp(0.7j) * np.roll(e, 37))
    >>> bool(np.abs(d1 - d2).max() < 1e-4), round(float(d1 @ d1), 5)
    (True, 1.0)
    """
    from .._validate import boolean, integer

    harmonics = integer("harmonics", harmonics, minimum=1, maximum=1024)
    resampled = boolean("resampled", resampled)
    z = _curve("z", z)
    if not resampled:
        z = resample_closed(z, max(SAMPLES, 4 * harmonics))
    m = z.shape[-1]
    if m < 2 * harmonics + 1:
        raise InputError("harmonics", f"needs at least {2 * harmonics + 1} samples, got {m}")
    c = np.fft.fft(z, axis=-1) / m
    k = np.concatenate([np.arange(-harmonics, 0), np.arange(1, harmonics + 1)])
    c = c[..., k]
    norm = np.sqrt(np.sum(c.real**2 + c.imag**2, axis=-1, keepdims=True))
    c = c / np.where(norm > 0.0, norm, 1.0)
    a1 = np.angle(c[..., harmonics : harmonics + 1])  # c_1
    am1 = np.angle(c[..., harmonics - 1 : harmonics])  # c_{-1}
    phi = -0.5 * (a1 + am1)
    tau = -0.5 * (a1 - am1)
    c = c * np.exp(1j * (phi + k * tau))
    out = np.empty((*c.shape[:-1], 4 * harmonics), dtype=np.float32)
    out[..., 0::2] = c.real
    out[..., 1::2] = c.imag
    return out


def _curve(field: str, z: Any) -> np.ndarray:
    """Curves as a finite complex array with at least 3 points per curve, else InputError."""
    try:
        z = np.asarray(z)
    except (ValueError, TypeError):
        raise InputError(field, "must be an array of points (complex numbers)") from None
    if z.dtype.kind not in "fiuc" or z.ndim == 0 or z.shape[-1] < 3:
        raise InputError(field, "must be points (complex x + jy) along a curve, at least 3")
    z = z.astype(complex)
    if not np.all(np.isfinite(z)):
        raise InputError(field, "must be finite (no NaN or infinity)")
    return z


def descriptor_variants(d: Any) -> np.ndarray:
    """The four forms of descriptors ``d`` (..., 4K) that describe the same shape.

    Returns shape (4, ..., 4K): as given, even harmonics' signs flipped (the
    other choice of ``(φ, τ)``), and both of those for the curve run the other
    way round (``c_k ↔ c_{−k}``).

    Examples
    --------
    >>> t = np.linspace(0, 2 * np.pi, 128, endpoint=False)
    >>> z = np.cos(t) + 0.4j * np.sin(t) + 0.2 * np.exp(-2j * t)
    >>> v = descriptor_variants(curve_descriptor(z))
    >>> back = curve_descriptor(z[::-1])
    >>> bool(np.min(np.abs(v - back).max(axis=-1)) < 1e-3)
    True
    """
    d = np.asarray(d, dtype=np.float32)
    k2 = d.shape[-1] // 2  # complex coefficients
    harmonics = k2 // 2
    k = np.concatenate([np.arange(-harmonics, 0), np.arange(1, harmonics + 1)])
    sign = np.where(k % 2 == 0, -1.0, 1.0).astype(np.float32).repeat(2)
    flipped = d * sign
    # reverse: coefficient order k -> -k, i.e. reverse the complex pairs
    pairs = d.reshape(*d.shape[:-1], k2, 2)
    rev = pairs[..., ::-1, :].reshape(d.shape)
    return np.stack([d, flipped, rev, rev * sign])


def interpolate_closed(points: np.ndarray, m: int = 512) -> np.ndarray:
    """A smooth closed curve through points (periodic cubic spline in chord length).

    Examples
    --------
    >>> sq = interpolate_closed(np.array([1, 1j, -1, -1j]), 64)
    >>> bool(np.allclose(np.abs(sq), 1, atol=0.1)), sq.size
    (True, 64)
    """
    from scipy.interpolate import CubicSpline

    pts = np.asarray(points, dtype=complex)
    chord = np.abs(np.diff(np.concatenate([pts, pts[:1]])))
    s = np.concatenate([[0.0], np.cumsum(chord)])
    closed = np.concatenate([pts, pts[:1]])
    spline = CubicSpline(s, np.column_stack([closed.real, closed.imag]), bc_type="periodic")
    xy = spline(np.linspace(0.0, s[-1], m, endpoint=False))
    return xy[:, 0] + 1j * xy[:, 1]


def interpolate_open(points: np.ndarray, m: int = 256) -> np.ndarray:
    """A smooth open curve through points (natural cubic spline in chord length)."""
    from scipy.interpolate import CubicSpline

    pts = np.asarray(points, dtype=complex)
    s = np.concatenate([[0.0], np.cumsum(np.abs(np.diff(pts)))])
    spline = CubicSpline(s, np.column_stack([pts.real, pts.imag]), bc_type="natural")
    xy = spline(np.linspace(0.0, s[-1], m))
    return xy[:, 0] + 1j * xy[:, 1]


def align_closed(target: np.ndarray, curves: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Best similarity transform of each closed curve onto a closed target.

    ``target`` (m,) and ``curves`` (N, m) are sampled evenly by arc length.
    Over every cyclic shift of the start and both directions, the complex
    factor ``h`` and offset ``t`` minimising ``Σ |target_j − t − h b_j|²``
    (a rotation-and-scale Procrustes fit, in closed form; the shifts by FFT
    correlation) are found.

    Returns
    -------
    transform : ndarray of complex, shape (N, 2)
        ``h, t`` so that ``t + h·curve`` lies on the target.
    residual : ndarray, shape (N,)
        RMS distance between target and fitted curve, over the target's RMS radius.

    Examples
    --------
    >>> t = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    >>> b = np.cos(t) + 0.5j * np.sin(t) + 0.1 * np.exp(2j * t)
    >>> a = 3 - 1j + 2j * np.roll(b[::-1], 5)
    >>> (tr,), res = align_closed(a, b[None, :])
    >>> np.round(tr, 9), bool(res[0] < 1e-12)
    (array([0.+2.j, 3.-1.j]), True)
    """
    a = np.asarray(target, dtype=complex)
    b = np.asarray(curves, dtype=complex)
    m = a.size
    am = a.mean()
    a0 = a - am
    bm = b.mean(axis=1, keepdims=True)
    b0 = b - bm
    bb = np.sum(np.abs(b0) ** 2, axis=1)
    aa = float(np.sum(np.abs(a0) ** 2))
    fa = np.fft.fft(a0)
    best = np.full(b.shape[0], -1.0)
    h = np.zeros(b.shape[0], dtype=complex)
    shift_b = np.zeros(b.shape[0], dtype=complex)
    for curve, mean in ((b0, bm[:, 0]), (b0[:, ::-1], bm[:, 0])):
        # C(s) = Σ_j a_j conj(b_{j+s}) = (1/m) Σ_k A_k conj(B_k) e^{−2πi ks/m}: every shift at once
        corr = np.fft.fft(fa[None, :] * np.conj(np.fft.fft(curve, axis=1)), axis=1) / m
        s = np.argmax(np.abs(corr), axis=1)
        c = corr[np.arange(b.shape[0]), s]
        score = np.abs(c) ** 2
        better = score > best
        best = np.where(better, score, best)
        hh = c / np.where(bb > 0.0, bb, 1.0)
        h = np.where(better, hh, h)
        shift_b = np.where(better, mean, shift_b)
    residual = np.sqrt(np.maximum(aa - best / np.where(bb > 0.0, bb, 1.0), 0.0) / max(aa, 1e-300))
    offset = am - h * shift_b
    return np.column_stack([h, offset]), residual


def align_partial(
    target: np.ndarray, curves: np.ndarray, fractions: Any = None, single: bool = False
) -> tuple[np.ndarray, np.ndarray]:
    """Best similarity fit of an open target onto any arc of each closed curve.

    ``target`` (L,) is sampled evenly along the open path, ``curves`` (N, m)
    evenly by arc length. For every arc that starts at any sample, spans a
    fraction ``f`` of the curve (``fractions``) and runs either way, the
    target's points are matched to evenly spaced points of the arc and the
    complex factor ``h`` and offset ``t`` of :func:`align_closed` are found
    (all starts at once, by FFT correlation). ``single``: the curves' FFTs and
    correlations in single precision (scipy.fft keeps complex64: half the time).
    Scores are then told apart to ~1e-6, residuals to ~3e-3 (a neighbouring start
    along the arc may win): enough to rank curves for a re-fit, not to place one.

    Returns
    -------
    transform : ndarray of complex, shape (N, 2)
        ``h, t`` of the best arc: ``t + h·curve`` passes near the target.
    residual : ndarray, shape (N,)
        RMS misfit over the target's RMS radius.

    Examples
    --------
    A quarter of a closed curve, moved and turned, is found on it:

    >>> t = np.linspace(0, 2 * np.pi, 128, endpoint=False)
    >>> ell = resample_closed(2 * np.cos(t) + 1j * np.sin(t) + 0.3 * np.exp(2j * t), 128)
    >>> arc = 1 + 2j + 1j * ell[64:97]
    >>> (tr,), res = align_partial(arc[::2], ell[None, :], [0.25])
    >>> np.round(tr, 6), bool(res[0] < 1e-9)
    (array([0.+1.j, 1.+2.j]), True)
    """
    from scipy import fft as sfft

    fft = sfft if single else np.fft  # (numpy's FFT returns complex128 whatever it is given)
    a = np.asarray(target, dtype=complex)
    kind = np.complex64 if single else complex
    b = np.asarray(curves, dtype=kind)
    n, m = b.shape
    el = a.size
    fractions = np.linspace(0.125, 1.0, 8) if fractions is None else np.ravel(fractions)
    am = a.mean()
    a0 = a - am
    aa = float(np.sum(np.abs(a0) ** 2))
    best = np.full(n, -1.0)
    h = np.zeros(n, dtype=complex)
    off = np.zeros(n, dtype=complex)
    floor, tiny = (1e-5, 1e-30) if single else (1e-12, 1e-300)  # (v below floor·Σ|b|²: a point)
    for curve in (b, b[:, ::-1]):
        fb = np.conj(fft.fft(curve, axis=1))
        fbb = np.conj(fft.fft((curve.real**2 + curve.imag**2).astype(kind), axis=1))
        for f in fractions:
            j = (
                np.round(np.arange(el) * (f * (m - 1 if f >= 1.0 else m) / (el - 1))).astype(int)
                % m
            )
            tmpl = np.zeros(m, dtype=complex)
            np.add.at(tmpl, j, a0)
            ind = np.zeros(m)
            np.add.at(ind, j, 1.0)
            ft, fi = np.fft.fft(tmpl).astype(kind), np.fft.fft(ind).astype(kind)
            # (÷m as ×(1/m), in place: the same numbers when m is a power of two, as the
            # atlas's 128 samples and every other one of them are, in two thirds of the time)
            c = fft.fft(ft[None, :] * fb, axis=1)
            c *= 1.0 / m  # Σ_l (a_l − ā) conj(b_{s+j_l})
            d = fft.fft(fi[None, :] * fb, axis=1)
            d *= 1.0 / m
            np.conj(d, out=d)  # Σ_l b_{s+j_l}
            sq = fft.fft(fi[None, :] * fbb, axis=1).real
            sq *= 1.0 / m  # Σ_l |b_{s+j_l}|²
            v = d.real**2
            v += d.imag**2
            v /= el
            np.subtract(sq, v, out=v)
            low = np.maximum(sq, tiny)
            low *= floor
            np.copyto(v, np.inf, where=~(v > low))
            score = c.real**2
            score += c.imag**2
            score /= v
            s = np.argmax(score, axis=1)
            rows = np.arange(n)
            sc = score[rows, s]
            better = sc > best
            hh = c[rows, s] / v[rows, s]
            best = np.where(better, sc, best)
            h = np.where(better, hh, h)
            off = np.where(better, am - hh * d[rows, s] / el, off)
    residual = np.sqrt(np.maximum(aa - best, 0.0) / max(aa, 1e-300))
    return np.column_stack([h, off]), residual
