"""Six-bar coupler curves for the atlas: a crank-driven four-bar and one RRR dyad.

A Watt or Stephenson six-bar is a four-bar (links 1 ground, 2 crank, 3
coupler, 4 rocker) with a dyad of two more links (5, 6) pinned to two of the
four links at points ``C`` and ``D``: the two links that carry them become the
chain's ternary links. Adjacent ternaries make a Watt chain, opposite ones a
Stephenson chain (Norton, *Design of Machinery*, sec. 2.14):

=====  ===================  ============================================
 pair  chain                ternary links
=====  ===================  ============================================
 1–2   Watt II              ground and crank
 1–4   Watt II              ground and rocker (two four-bars in series)
 2–3   Watt I               crank and coupler
 3–4   Watt I               coupler and rocker
 1–3   Stephenson           ground and coupler
 2–4   Stephenson           crank and rocker
=====  ===================  ============================================

The coupler point is on a floating link of the dyad: link 6 (pinned at ``D``)
always, link 5 (pinned at ``C``) where ``C`` is not on the ground. (A point on
link 3 draws the four-bar's own curve, which the four-bar atlas holds.) Every
position is the engine's closed-form dyad :func:`machdyn.linkage.dyads.rrr`,
vectorised over linkages and crank angles at once — one solver for every dyad.

Points on link ``k`` are given in its frame, with the link's two pins as the
unit: ground ``O2 → O4``, crank ``O2 → A``, coupler ``A → B``, rocker
``O4 → B``; ``(u, v)`` is the point ``origin + (u + jv)(x-point − origin)``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

# Internal to machdyn.synthesis, which re-exports the public names (Atlas, build_atlas,
# open_atlas, path_from_atlas, curve_descriptor, ...); the fuzz suite fuzzes those.
__all__: list[str] = []

#: The dyad's attachment links, with the chain's name.
TOPOLOGIES = (
    ((1, 2), "Watt II"),
    ((1, 4), "Watt II"),
    ((2, 3), "Watt I"),
    ((3, 4), "Watt I"),
    ((1, 3), "Stephenson"),
    ((2, 4), "Stephenson"),
)

SIXBAR_DTYPE = np.dtype(
    [
        ("r1", "<f4"), ("r3", "<f4"), ("r4", "<f4"), ("cu", "<f4"), ("cv", "<f4"),
        ("du", "<f4"), ("dv", "<f4"), ("a", "<f4"), ("b", "<f4"), ("pu", "<f4"), ("pv", "<f4"),
        ("s4", "i1"), ("s6", "i1"), ("topology", "i1"), ("on", "i1"), ("barker", "i1"),
        ("circuit", "i1"),
    ]
)  # fmt: skip


def _frames(link: np.ndarray, O2, O4, A, B):
    """Origin and x-point of each link number (1–4), broadcast."""
    origin = np.where(link == 1, O2, np.where(link == 2, O2, np.where(link == 3, A, O4)))
    xpoint = np.where(link == 1, O4, np.where(link == 2, A, B))
    return origin, xpoint


def sixbar_points(meta: np.ndarray, theta2: Any, *, joints: bool = False):
    """Coupler points of six-bars (rows of :data:`SIXBAR_DTYPE`) at crank angles ``theta2``.

    Unit crank, ``O2`` at the origin, ground along +x. ``theta2`` broadcasts
    against the rows as columns: shape (M,) gives (N, M). Returns the points
    (NaN where a dyad cannot be assembled) and ``ok``; with ``joints=True``
    also a dict of every joint (``A B C D E``).

    Examples
    --------
    Two four-bars in series (Watt II): the dyad runs from a pivot C on the
    ground (frame O2 → O4, at (4, 2)) to the rocker's tip B (``d = 1 + 0j`` on
    O4 → B); the point is the middle of link 6 (D → E):

    >>> from machdyn.synthesis.sixbar import SIXBAR_DTYPE, sixbar_points
    >>> m = np.zeros(1, SIXBAR_DTYPE)
    >>> m[0] = (3, 3.5, 2.5, 4 / 3, 2 / 3, 1, 0, 3, 3, 0.5, 0, 1, 1, 1, 6, 2, 1)
    >>> P, ok, j = sixbar_points(m, np.linspace(0, 2 * np.pi, 8), joints=True)
    >>> link5 = np.allclose(np.abs(j["E"] - j["C"]), 3)
    >>> bool(ok.all()), link5, np.allclose(P, (j["E"] + j["D"]) / 2)
    (True, True, True)
    """
    from ..linkage.dyads import rrr

    f = {k: meta[k].astype(float)[:, None] for k in SIXBAR_DTYPE.names}
    th = np.asarray(theta2, dtype=float)
    th = th[None, :] if th.ndim == 1 else th
    O2 = np.zeros(1, complex)[:, None]
    O4 = f["r1"] + 0j
    A = np.exp(1j * th)
    pin = rrr(A, O4, f["r3"], f["r4"], f["s4"])
    B, ok4 = pin.B, pin.ok
    pairs = np.array([t[0] for t in TOPOLOGIES])[meta["topology"].astype(int)]
    o1, x1 = _frames(pairs[:, :1], O2, O4, A, B)
    o2, x2 = _frames(pairs[:, 1:], O2, O4, A, B)
    C = o1 + (f["cu"] + 1j * f["cv"]) * (x1 - o1)
    D = o2 + (f["du"] + 1j * f["dv"]) * (x2 - o2)
    pin = rrr(C, D, f["a"], f["b"], f["s6"])
    E, ok6 = pin.B, pin.ok
    on6 = f["on"] == 6
    base = np.where(on6, D, C)
    P = base + (f["pu"] + 1j * f["pv"]) * (E - base)
    ok = ok4 & ok6
    if joints:
        return P, ok, {"A": A, "B": B, "C": C, "D": D, "E": E}
    return P, ok


def sample_sixbars(rng: np.random.Generator, n: int, m: int = 256) -> np.ndarray:
    """``n`` random crank-driven six-bars, assembled over the whole turn (SIXBAR_DTYPE rows).

    The four-bar part as the four-bar atlas samples it, kept only where link 2
    is a crank; the attachment points ``C, D`` uniform over a disc of radius
    1.5 about the middle of their links (in link units); the dyad's pin ``E``
    drawn at θ2 = 0 within one ``|CD|`` of the middle of ``CD``, which fixes the
    lengths ``a, b`` and the assembly; the coupler point on a floating dyad
    link, uniform over a disc of radius 1.5 about the middle of that link.
    Linkages whose dyad comes apart anywhere over the turn (``m`` angles) are
    drawn again.
    """
    from .atlas_store import LENGTH_RANGE

    out = np.empty(n, dtype=SIXBAR_DTYPE)
    filled = 0
    lo, hi = np.log(LENGTH_RANGE[0]), np.log(LENGTH_RANGE[1])
    theta = np.linspace(0.0, 2 * np.pi, m, endpoint=False)
    while filled < n:
        rows = _draw(rng, 8 * (n - filled) + 64, lo, hi)
        rows = rows[_dyad_drawn(rows, rng)]
        rows = rows[sixbar_points(rows, theta)[1].all(axis=1)]  # assembled over the whole turn
        k = min(rows.size, n - filled)
        out[filled : filled + k] = rows[:k]
        filled += k
    return out


def _draw(rng: np.random.Generator, want: int, lo: float, hi: float) -> np.ndarray:
    """Crank-driven four-bars with random attachments and coupler points (dyad not yet drawn)."""
    from .atlas_store import barker_numbers
    from .circuits import circuit_range

    r1, r3, r4 = np.exp(rng.uniform(lo, hi, size=(3, want)))
    lengths = np.stack([r1, np.ones_like(r1), r3, r4])
    srt = np.sort(lengths, axis=0)
    keep = circuit_range(r1, 1.0, r3, r4)[2]
    keep &= np.abs(srt[0] + srt[3] - srt[1] - srt[2]) > 1e-3 * srt.sum(axis=0)
    k = int(keep.sum())
    rows = np.zeros(k, SIXBAR_DTYPE)
    rows["r1"], rows["r3"], rows["r4"] = r1[keep], r3[keep], r4[keep]
    rows["barker"] = barker_numbers(lengths[:, keep])
    rows["s4"] = rng.choice(np.array([-1, 1], np.int8), k)
    rows["circuit"] = rows["s4"]
    rows["topology"] = rng.integers(0, len(TOPOLOGIES), k)
    for name in ("c", "d", "p"):
        w = 0.5 + 1.5 * np.sqrt(rng.uniform(0, 1, k)) * np.exp(2j * np.pi * rng.uniform(0, 1, k))
        rows[name + "u"], rows[name + "v"] = w.real, w.imag
    ground_first = np.array([t[0][0] == 1 for t in TOPOLOGIES])[rows["topology"]]
    rows["on"] = np.where(ground_first | (rng.uniform(0, 1, k) < 0.5), 6, 5)
    return rows


def _dyad_drawn(rows: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Draw each dyad's pin E at θ2 = 0 near the middle of CD; set a, b, s6; which are usable."""
    from ..linkage.dyads import rrr

    rows["a"], rows["b"], rows["s6"] = 1.0, 1.0, 1
    _, _, j = sixbar_points(rows, np.zeros(1), joints=True)
    C, D = j["C"][:, 0], j["D"][:, 0]
    k = rows.size
    w = 0.5 + np.sqrt(rng.uniform(0, 1, k)) * np.exp(2j * np.pi * rng.uniform(0, 1, k))
    E = C + (D - C) * w
    rows["a"], rows["b"] = np.abs(E - C), np.abs(E - D)
    rows["s6"] = np.where(((D - C).conjugate() * (E - C)).imag >= 0, 1, -1)
    good = (rows["a"] > 0.05) & (rows["b"] > 0.05) & (np.abs(D - C) > 0.05)
    E0 = rrr(C, D, rows["a"].astype(float), rows["b"].astype(float), rows["s6"]).B
    return good & (np.abs(E0 - E) < 1e-4 * (1 + np.abs(E)))  # rrr's assembly is the drawn one
