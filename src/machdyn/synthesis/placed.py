"""A four-bar placed in the plane: its own frame mapped onto global coordinates.

:class:`~machdyn.fourbar.FourBar` works in its own frame (``O2`` at the
origin, the ground ``O2O4`` along +x). Synthesis produces pivots anywhere in
the plane, so a :class:`PlacedFourBar` adds the ground pivot ``O2`` and the
ground angle ``θ1``: a local point ``z`` is at ``O2 + z·e^{jθ1}`` globally.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import choice, complex_array, finite_array, finite_scalar, instance, point
from ..errors import InputError
from ..fourbar import FourBar, positions

__all__ = ["PlacedFourBar"]


@dataclass(frozen=True)
class PlacedFourBar:
    """A :class:`~machdyn.fourbar.FourBar` with its ground pivots placed in the plane.

    Attributes
    ----------
    fourbar : FourBar
        The linkage in its own frame (with the coupler point, if any).
    O2 : complex
        Global position of the input pivot.
    theta1 : float
        Angle of the ground line ``O2 → O4`` from global +x, radians.
    branch : int
        Sign of φ12 = θ4 − θ3 of the assembly this linkage works in (+1 or −1).

    Examples
    --------
    >>> pl = PlacedFourBar.from_pivots(O2=1j, O4=1j + 8, A=1j + 4, B=1j + 8 + 6j)
    >>> pl.fourbar.lengths, pl.branch
    ((8.0, 4.0, 7.211102550927978, 6.0), 1)
    >>> complex(pl.O4)
    (8+1j)
    """

    fourbar: FourBar
    O2: complex
    theta1: float
    branch: int

    def __post_init__(self) -> None:
        instance("fourbar", self.fourbar, FourBar)
        object.__setattr__(self, "O2", point("O2", self.O2))
        object.__setattr__(self, "theta1", finite_scalar("theta1", self.theta1, "radian"))
        object.__setattr__(self, "branch", choice("branch", self.branch, (1, -1)))

    @classmethod
    def from_pivots(
        cls, O2: complex, O4: complex, A: complex, B: complex, P: complex | None = None
    ) -> PlacedFourBar:
        """Build the linkage from its four joints (and coupler point) in one pose.

        Raises
        ------
        InputError
            If two joints that a link connects coincide (a zero-length link).
        """
        O2, O4, A, B = (point(k, v) for k, v in (("O2", O2), ("O4", O4), ("A", A), ("B", B)))
        names = {"r1 (O2O4)": O4 - O2, "r2 (O2A)": A - O2, "r3 (AB)": B - A, "r4 (O4B)": B - O4}
        scale = max(abs(O2), abs(O4), abs(A), abs(B), 1e-300)
        for name, vec in names.items():
            if abs(vec) <= 1e-9 * scale:
                raise InputError(name, "the two joints coincide, giving a link of zero length")
        r1, r2, r3, r4 = (abs(v) for v in names.values())
        coupler = None
        if P is not None:
            P = point("P", P)
            coupler = (abs(P - A), float(np.angle((P - A) / (B - A))) if P != A else 0.0)
        phi12 = np.angle((B - O4) / (B - A))  # θ4 − θ3
        branch = 1 if phi12 >= 0.0 else -1
        return cls(FourBar(r1, r2, r3, r4, coupler=coupler), O2, float(np.angle(O4 - O2)), branch)

    # -- geometry ------------------------------------------------------------------
    @property
    def O4(self) -> complex:
        """Global position of the output pivot."""
        return self.O2 + self.fourbar.r1 * np.exp(1j * self.theta1)

    @property
    def lengths(self) -> tuple[float, float, float, float]:
        """``(r1, r2, r3, r4)``."""
        return self.fourbar.lengths

    def to_global(self, z: Any) -> np.ndarray:
        """Map points of the linkage's own frame to the plane."""
        return self.O2 + complex_array("z", z) * np.exp(1j * self.theta1)

    def to_local(self, z: Any) -> np.ndarray:
        """Map points of the plane into the linkage's own frame."""
        return (complex_array("z", z) - self.O2) * np.exp(-1j * self.theta1)

    def theta2_of(self, A: Any) -> np.ndarray:
        """Local input angle θ2 (from the ground line) that puts the crank pin at ``A``."""
        return np.mod(
            np.angle((complex_array("A", A) - self.O2) * np.exp(-1j * self.theta1)), 2 * np.pi
        )

    def pose(self, theta2: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Global joints ``A``, ``B``, coupler point ``P`` and an ``ok`` mask at local ``theta2``.

        ``P`` equals ``A`` when the linkage has no coupler point. Samples that
        cannot be assembled are NaN with ``ok`` False.

        Examples
        --------
        >>> pl = PlacedFourBar.from_pivots(O2=0, O4=8, A=4, B=8 + 6j)
        >>> A, B, P, ok = pl.pose(0.0)
        >>> print(f"{B.real:.9f} {B.imag:.9f}", bool(ok))
        8.000000000 6.000000000 True
        """
        fb = self.fourbar
        theta2 = finite_array("theta2", theta2, "radian")
        th3, th4, ok = positions(*fb.lengths, theta2, self.branch)
        a_loc = fb.r2 * np.exp(1j * theta2)
        b_loc = fb.r1 + fb.r4 * np.exp(1j * th4)
        if fb.coupler is None:
            p_loc = a_loc
        else:
            p, delta = fb.coupler
            p_loc = a_loc + p * np.exp(1j * (th3 + delta))
        nan = complex(np.nan, np.nan)
        local = [np.where(ok, v, 0.0) for v in (a_loc, b_loc, p_loc)]  # NaN where unassembled
        out = [np.where(ok, self.to_global(v), nan) for v in local]
        return out[0], out[1], out[2], ok


def form_of(branch: Any) -> int | str:
    """The FourBar form (1 or 2) of assembly signs of φ12, or why there is none.

    Form 1 has φ12 = θ4 − θ3 of positive sine (the path synthesis' ``branch`` +1).

    Examples
    --------
    >>> form_of([-1, -1, -1]), form_of(1)
    (2, 1)
    """
    signs = set(np.atleast_1d(np.asarray(branch)).tolist())
    if len(signs) != 1:
        return "none: the positions lie on both forms (a circuit or branch defect)"
    return 1 if signs.pop() > 0 else 2
