"""Quick-return and swing design: a crank-rocker for a rocker swing and a time ratio.

The notes' "quick-return mechanism" (Ch. 3; Norton sec. 3.5). A
crank-rocker's rocker stops at the two toggles of crank and coupler: extended
(``|O2 B1| = a + b``) and folded (``|O2 B2| = b − a``). Between them the
crank turns ``π + δ`` one way and ``π − δ`` the other, where ``δ`` is the
angle ``B1 O2 B2``; so the time ratio of the slow to the quick stroke is

``TR = (π + δ) / (π − δ)``, i.e. ``δ = π (TR − 1) / (TR + 1)``.

With the rocker ``O4 B`` and its swing given, ``O2`` may be any point that
sees the chord ``B1B2`` under the angle ``δ``: a circular arc (the inscribed
angle theorem; a straight line through ``B1B2`` for ``TR = 1``). Each point
of the arc gives ``a = (|O2B1| − |O2B2|)/2`` and ``b = (|O2B1| + |O2B2|)/2``.
:func:`quick_return` evaluates the whole arc at once and keeps the Grashof
crank-rocker, with both toggles on one circuit and the ground no longer than
``max_ground`` rocker lengths, that has the largest minimum transmission angle.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validate import count, finite_scalar, positive
from ..errors import InputError
from .placed import PlacedFourBar

__all__ = ["QuickReturn", "quick_return", "time_ratio_angle"]


def time_ratio_angle(time_ratio: float) -> float:
    """The construction angle ``δ = π (TR − 1)/(TR + 1)`` for a time ratio (radians).

    Examples
    --------
    >>> round(float(np.degrees(time_ratio_angle(1.25))), 6)     # TR = 1.25
    20.0
    """
    tr = finite_scalar("time_ratio", time_ratio)
    if tr < 1.0:
        raise InputError("time_ratio", f"must be >= 1 (slow stroke over quick stroke), got {tr:g}")
    return float(np.pi * (tr - 1.0) / (tr + 1.0))


@dataclass(frozen=True)
class QuickReturn:
    """A crank-rocker designed for a rocker swing and a time ratio.

    Attributes
    ----------
    linkage : PlacedFourBar
        The crank-rocker; ``O4`` at the origin, the rocker's swing symmetric about +y.
    swing : float
        Rocker swing, radians.
    time_ratio : float
        Slow-stroke over quick-stroke crank angle.
    delta : float
        Construction angle ``B1 O2 B2``, radians.
    mu_min : float
        Minimum transmission angle over the motion, radians.
    B1, B2 : complex
        Rocker pin at the extended and the folded toggle.
    """

    linkage: PlacedFourBar
    swing: float
    time_ratio: float
    delta: float
    mu_min: float
    B1: complex
    B2: complex

    @property
    def fourbar(self):
        """The :class:`~machdyn.fourbar.FourBar` in its own frame."""
        return self.linkage.fourbar


def quick_return(
    swing: float, time_ratio: float, r4: float = 1.0, *, max_ground: float = 5.0, n: int = 2001
) -> QuickReturn:
    """Crank-rocker whose rocker of length ``r4`` swings ``swing`` with time ratio ``time_ratio``.

    Parameters
    ----------
    swing : float
        Rocker swing angle, radians, in ``(0, π)``.
    time_ratio : float
        ``TR >= 1``; 1 is a non-quick-return (both strokes take half a turn).
    r4 : float
        Rocker length (the scale).
    max_ground : float
        Largest ground length ``|O2 O4|`` considered, in rocker lengths.
    n : int
        Candidate crank pivots sampled along the locus.

    Raises
    ------
    InputError
        A swing outside ``(0, π)``, a time ratio below 1, or one so large that
        no Grashof crank-rocker exists on the locus.

    Examples
    --------
    45° of rocker swing with a time ratio of 1 : 1.25 (Norton sec. 3.5).

    >>> qr = quick_return(np.radians(45), 1.25, r4=2.0)
    >>> qr.fourbar.barker_class, round(float(np.degrees(qr.delta)), 6)
    ('GCRR', 20.0)
    """
    swing = finite_scalar("swing", swing, "radian")
    if not 1e-9 < swing < np.pi:  # a swing below 1e-9 rad has no chord to work with
        raise InputError("swing", f"must lie between 0 and 180 deg, got {np.degrees(swing):g} deg")
    delta = time_ratio_angle(time_ratio)
    r4 = positive("r4", r4)
    n = count("n", n, minimum=11, bytes_each=256)
    max_ground = positive("max_ground", max_ground)
    b1 = r4 * np.exp(1j * (0.5 * np.pi - 0.5 * swing))
    b2 = r4 * np.exp(1j * (0.5 * np.pi + 0.5 * swing))
    chord = b2 - b1
    mid = 0.5 * (b1 + b2)
    normal = 1j * chord / abs(chord)
    if delta < 1e-12:
        # TR = 1: O2 on the line B1B2 outside the segment (both sides)
        t = np.geomspace(1e-3, 2.0 * max_ground, n // 2) * r4
        u = chord / abs(chord)
        o2 = np.concatenate([b1 - t * u, b2 + t * u])
    else:
        radius = abs(chord) / (2.0 * np.sin(delta))
        # both circles through B1 and B2 with that radius; on each, the major arc sees
        # the chord under δ and the minor arc under π − δ (filtered out below)
        phis = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
        candidates = [
            mid + side * normal * radius * np.cos(delta) + radius * np.exp(1j * phis)
            for side in (1.0, -1.0)
        ]
        o2 = np.concatenate(candidates)
        # keep points that see B1B2 under δ (not π − δ)
        with np.errstate(invalid="ignore", divide="ignore"):
            seen = np.abs(np.angle((b2 - o2) / (b1 - o2)))
        o2 = o2[np.abs(seen - delta) < 1e-6]
    # extended at the farther pin: a + b = far, b − a = near
    f1, f2 = np.abs(b1 - o2), np.abs(b2 - o2)
    far, near = np.maximum(f1, f2), np.minimum(f1, f2)
    a = 0.5 * (far - near)
    b = 0.5 * (far + near)
    d = np.abs(o2)
    c = r4
    lengths = np.stack([d, a, b, np.full_like(d, c)])
    s = lengths.min(axis=0)
    big = lengths.max(axis=0)
    total = lengths.sum(axis=0)
    # both toggles on one assembly (sign of φ12 = arg((B − O4)/(B − A))); else the
    # "swing" would jump between the two circuits of the crank-rocker
    ext = np.where(f1 >= f2, b1, b2)
    fold = np.where(f1 >= f2, b2, b1)
    with np.errstate(invalid="ignore", divide="ignore"):
        u_ext = (ext - o2) / np.abs(ext - o2)
        u_fold = (fold - o2) / np.abs(fold - o2)
        side_ext = np.angle(ext / (ext - (o2 + a * u_ext)))
        side_fold = np.angle(fold / (fold - (o2 - a * u_fold)))
    one_circuit = np.sign(side_ext) == np.sign(side_fold)
    grashof_crank = (
        (a <= s)
        & (s + big < total - s - big)
        & (a > 1e-6 * r4)
        & one_circuit
        & (d <= max_ground * r4)
    )
    if not grashof_crank.any():
        raise InputError(
            "time_ratio",
            "no Grashof crank-rocker gives this swing and time ratio; lower the time ratio "
            "or the swing",
        )
    # minimum transmission angle of a crank-rocker: at θ2 = 0 or π (Norton sec. 4.10)
    cos_lo = (b * b + c * c - (d - a) ** 2) / (2.0 * b * c)
    cos_hi = (b * b + c * c - (d + a) ** 2) / (2.0 * b * c)
    mu = np.minimum(_acute(cos_lo), _acute(cos_hi))
    mu = np.where(grashof_crank, mu, -np.inf)
    i = int(np.argmax(mu))
    O2 = complex(o2[i])
    ext = b1 if f1[i] >= f2[i] else b2
    u = (ext - O2) / abs(ext - O2)
    A = O2 + a[i] * u  # extended toggle: A between O2 and B
    linkage = PlacedFourBar.from_pivots(O2, 0j, A, ext)
    folded = b2 if ext == b1 else b1
    return QuickReturn(
        linkage,
        swing,
        float(time_ratio),
        delta,
        float(mu[i]),
        complex(ext),
        complex(folded),
    )


def _acute(cos_phi: np.ndarray) -> np.ndarray:
    phi = np.arccos(np.clip(cos_phi, -1.0, 1.0))
    return np.minimum(phi, np.pi - phi)
