"""Roberts–Chebyshev cognates: the three four-bars that trace one coupler curve.

Roberts' theorem (Norton, *Design of Machinery*, 5th ed., §3.7 and Figure 3-24:
the Cayley diagram): a four-bar ``O2 A B O4`` whose coupler point ``P`` sits on
the coupler triangle ``A B P`` has two cognates whose coupler points trace the
same curve. With ``z = (P − A)/(B − A)`` (the triangle's shape, constant as the
coupler moves) the third ground pivot is ``O3 = O2 + z (O4 − O2)``: the ground
triangle ``O2 O4 O3`` is similar to ``A B P``. In complex numbers, with the
original's crank ``a = A − O2``, coupler ``b = B − A`` and rocker ``e = B − O4``,

* ``P = O2 + a + z b`` (the original),
* ``P = O2 + z b + a``: cognate 2, pivots ``O2`` and ``O3``, its crank ``z b`` (it
  turns with the original's coupler), coupler ``z a``, rocker ``z e``;
* ``P = O3 + (1 − z) a + z e``: cognate 3, pivots ``O3`` and ``O4``, its crank
  ``(1 − z) a`` (it turns with the original's crank: a cognate driven at ``O3``
  keeps the original's timing), coupler ``(1 − z) e``, rocker ``(z − 1) b``.
"""

from __future__ import annotations

import numpy as np

from .._validate import instance
from ..errors import InputError
from .placed import PlacedFourBar

__all__ = ["cognates"]


def cognates(linkage: PlacedFourBar) -> tuple[PlacedFourBar, PlacedFourBar]:
    """The two Roberts–Chebyshev cognates of a placed four-bar with a coupler point.

    Returns ``(cognate 2, cognate 3)`` (see the module's notes), each placed in the
    plane with its coupler point on the original's at every input angle: cognate 2
    driven at the original's ``O2`` (its crank turns with the original's coupler),
    cognate 3 driven at the new pivot ``O3`` (its crank turns with the original's
    crank, at a fixed angle from it: the same timing). Each is in the assembly the
    original's pose at ``θ2 = 0`` (or, if it cannot be assembled there, at the
    middle of its range) puts it in.

    Raises
    ------
    InputError
        ``linkage`` has no coupler point, or its coupler point lies on the line AB
        at A or B (a cognate would then have a link of zero length).

    Examples
    --------
    The coupler triangle's shape ``z = (3/5) e^{0.6j}``: cognate 2's links are the
    original's ground, coupler, crank and rocker times ``|z|`` = 0.6, cognate 3's
    its ground, crank, rocker and coupler times ``|1 − z|``:

    >>> from machdyn.fourbar import FourBar
    >>> pl = PlacedFourBar(FourBar(5.0, 2.0, 5.0, 4.0, coupler=(3.0, 0.6)), 0j, 0.0, 1)
    >>> c2, c3 = cognates(pl)
    >>> [round(r, 9) for r in c2.lengths]
    [3.0, 3.0, 1.2, 2.4]
    >>> k = float(abs(1 - 0.6 * np.exp(0.6j)))
    >>> [round(r / k, 9) for r in c3.lengths]
    [5.0, 2.0, 4.0, 5.0]
    """
    instance("linkage", linkage, PlacedFourBar)
    if linkage.fourbar.coupler is None:
        raise InputError("linkage", "has no coupler point: cognates share a coupler curve")
    theta = _some_pose(linkage)
    A, B, P, _ = (np.asarray(v)[0] for v in linkage.pose(np.array([theta])))
    O2, O4 = linkage.O2, linkage.O4
    family = _family(O2, A, B, O4, P)
    return tuple(
        PlacedFourBar.from_pivots(O2=o_in, O4=o_out, A=a, B=b, P=P)
        for o_in, a, b, o_out in family[1:]
    )  # type: ignore[return-value]


def _some_pose(linkage: PlacedFourBar) -> float:
    """An input angle at which the linkage can be assembled: 0, or the middle of its reach."""
    grid = np.linspace(0.0, 2.0 * np.pi, 721)
    ok = linkage.pose(grid)[3]
    if ok[0]:
        return 0.0
    return float(grid[np.flatnonzero(ok)[np.count_nonzero(ok) // 2]])


def _family(O2, A, B, O4, P) -> list[tuple]:
    """The original and its two cognates as ``(input pivot, crank pin, rocker pin, output pivot)``.

    Works on scalars or on arrays of poses (the same linkages at each). Raises
    InputError where a cognate would have a link of zero length (``P`` at ``A``
    or at ``B``: ``z`` is 0 or 1).
    """
    z = (P - A) / (B - A)
    zs = np.atleast_1d(z)
    scale = np.max(np.abs(np.atleast_1d(B - A)))
    if np.min(np.abs(zs)) * scale <= 1e-9 * scale or np.min(np.abs(1 - zs)) <= 1e-9:
        raise InputError("linkage", "its coupler point is at A or B: the cognates degenerate")
    O3 = O2 + z * (O4 - O2)
    a, b, e = A - O2, B - A, B - O4
    second = (O2, O2 + z * b, O3 + z * e, O3)
    third = (O3, O3 + (1 - z) * a, O4 + (z - 1) * b, O4)
    return [(O2, A, B, O4), second, third]
