"""Shaking-force balance of a four-bar by counterweights on links 2 and 4.

The shaking force of a linkage without external loads is ``Fs = −Σ m_i aG_i``
(Norton sec. 11.8): it vanishes for every motion exactly when the total centre
of mass stays put. Berkof and Lowen's method of linearly independent vectors
(Norton, *Design of Machinery*, sec. 12.4 "Complete force balance of linkages")
writes the total mass moment about O2 with the loop closure
``e^{jθ3} = (r1 + r4 e^{jθ4} − r2 e^{jθ2}) / r3`` and asks the coefficients of
the independent vectors ``e^{jθ2}`` and ``e^{jθ4}`` to vanish:

    Σ m rG = [m2 c2 + m3 r2 (1 − c3 / r3)] e^{jθ2}
           + [m4 c4 + m3 c3 r4 / r3] e^{jθ4} + m4 r1 + m3 c3 r1 / r3,

with each ``c`` the centre of mass as a complex number in its link's frame
(origin at O2, A, O4; x toward A, B, B). Hence the balanced links need

    m2 c2 = −m3 r2 (1 − c3 / r3),     m4 c4 = −m3 c3 r4 / r3,

and a counterweight adds ``mR`` to each link's mass moment ``m c``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from ._validate import instance, nonnegative, positive
from .dynamics import _complex_scalar, _triple, link_properties
from .errors import InputError
from .fourbar import FourBar

__all__ = ["Counterweights", "fourbar_counterweights"]


@dataclass(frozen=True)
class Counterweights:
    """Mass–radius products that force-balance a four-bar.

    Attributes
    ----------
    mR2, mR4 : complex
        Counterweight ``m·R`` to add to link 2 (frame: origin O2, x toward A)
        and link 4 (origin O4, x toward B). Any mass ``m`` at ``R = mR / m``
        will do; a larger radius needs less mass.
    """

    mR2: complex
    mR4: complex

    def apply(
        self,
        mass: Sequence[float],
        inertia: Sequence[float],
        cg: Sequence[complex],
        counterweight_mass: tuple[float, float],
    ) -> tuple[tuple[float, ...], tuple[float, ...], tuple[complex, ...]]:
        """Mass properties of links 2–4 with point-mass counterweights attached.

        Each counterweight of mass ``mc`` sits at ``R = mR / mc``; the link's
        new centre of mass is the mass-weighted mean and its inertia about it
        follows from the parallel-axis theorem.

        Examples
        --------
        >>> cw = Counterweights(-4 + 0j, -1j)
        >>> mass, inertia, cg = cw.apply((1, 2, 1), (0.1, 0.5, 0.1), (2, 3, 1), (2.0, 1.0))
        >>> mass, cg[0], cg[2]
        ((3.0, 2.0, 2.0), (-0.6666666666666666+0j), (0.5-0.5j))
        """
        props = link_properties(mass, inertia, cg)
        try:
            mc2, mc4 = counterweight_mass
        except (TypeError, ValueError):
            raise InputError(
                "counterweight_mass", f"expected (mc2, mc4), got {counterweight_mass!r}"
            ) from None
        mc2 = positive("counterweight_mass mc2", mc2)
        mc4 = positive("counterweight_mass mc4", mc4)
        new_mass = list(props.mass)
        new_inertia = list(props.inertia)
        new_cg = list(props.cg)
        for index, mc, mR in ((0, mc2, self.mR2), (2, mc4, self.mR4)):
            m, i_g, c = props.mass[index], props.inertia[index], props.cg[index]
            R = mR / mc
            total = m + mc
            centre = (m * c + mR) / total
            new_inertia[index] = i_g + m * abs(c - centre) ** 2 + mc * abs(R - centre) ** 2
            new_mass[index] = total
            new_cg[index] = centre
        return tuple(new_mass), tuple(new_inertia), tuple(new_cg)


def fourbar_counterweights(fourbar: FourBar, mass: Any, cg: Any) -> Counterweights:
    """Counterweights on links 2 and 4 that make a four-bar's shaking force vanish.

    Parameters
    ----------
    fourbar : FourBar
        The linkage (lengths r1 … r4).
    mass : (m2, m3, m4)
        Masses of the moving links before balancing.
    cg : (c2, c3, c4)
        Their centres of mass in the link frames (complex).

    Returns
    -------
    Counterweights
        ``mR2``, ``mR4`` to add (complex, in the link frames). The coupler is
        not changed; the total centre of mass then stays fixed at
        ``(m4' r1 + m3 c3 r1 / r3) / M``, whatever the input angle.

    Examples
    --------
    A coupler of 2 kg with its centre of mass midway along AB, and uniform
    crank and rocker of 1 kg each (centres at their middles):

    >>> fb = FourBar(8, 4, 7, 6)
    >>> cw = fourbar_counterweights(fb, (1, 2, 1), (2, 3.5, 3))
    >>> cw.mR2, cw.mR4      # m2 c2 + mR2 = −2·4·(1 − 1/2) = −4;  m4 c4 + mR4 = −2·3.5·6/7 = −6
    ((-6+0j), (-9+0j))
    """
    instance("fourbar", fourbar, FourBar)
    m2, m3, m4 = (
        nonnegative(f"mass m{k}", v) for k, v in zip((2, 3, 4), _triple("mass", mass), strict=True)
    )
    c2, c3, c4 = (
        _complex_scalar(f"cg c{k}", v) for k, v in zip((2, 3, 4), _triple("cg", cg), strict=True)
    )
    _, r2, r3, r4 = fourbar.lengths
    mR2 = -m3 * r2 * (1.0 - c3 / r3) - m2 * c2
    mR4 = -m3 * c3 * r4 / r3 - m4 * c4
    return Counterweights(complex(mR2), complex(mR4))
