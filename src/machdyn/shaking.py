"""Shaking-force balance by counterweights: four-bar, slider-crank and any Linkage.

Four-bar (:func:`fourbar_counterweights`): complete force balance by
counterweights on links 2 and 4.

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

Slider-crank (:func:`slidercrank_counterweight`; Norton ch. 13, "Balancing the
single-cylinder engine"): with ``A = a e^{jθ2}``, ``B = d + jc`` and the rod's
centre ``G3 = A + c3 (B − A)/b``,

    Σ m rG = [m2 c2 + m3 a (1 − c3/b)] e^{jθ2} + (m4 + m3 c3/b) B,

a rotating part (Norton's ``m_A`` at the crank pin, here exact for any c2, c3)
and a reciprocating part ``m_B = m4 + m3 c3/b``. A crank counterweight
``mR = −[m2 c2 + m3 a (1 − c3/b)] − f·a·m_B`` (``f`` the overbalanced fraction
of the reciprocating mass) leaves ``Σ m rG = m_B (B − f A)``, so the shaking
force is exactly ``F_s = −m_B (B̈ − f Ä)``: along the slide and only the
piston's primary and secondary harmonics for ``f = 0``; a part ``f`` of the
primary turned into a rotating force across the slide for ``f > 0``. No
counterweight on the crank can remove the reciprocating part.

Any :class:`~machdyn.linkage.Linkage` (:func:`linkage_counterweights`): a
complete force balance where every link with mass is pinned to the ground or
floats on two pins of such links (a four-bar — the method above — a Watt
six-bar, ...), a rotating-mass balance of the crank where the links form a
slider-crank, otherwise a counterweight on every link pivoted on the ground
that puts that link's own centre of mass on its pivot (the floating links'
shaking remains).
"""

from __future__ import annotations

import copy
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ._validate import finite_scalar, instance, items, nonnegative, positive
from .dynamics import _complex_scalar, _triple, link_properties
from .errors import InputError
from .fourbar import FourBar

__all__ = [
    "Counterweights",
    "LinkageBalance",
    "LinkageCounterweight",
    "SliderCrankBalance",
    "fourbar_counterweights",
    "linkage_counterweights",
    "slidercrank_counterweight",
]


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
            new_mass[index], new_inertia[index], new_cg[index] = _attach(m, i_g, c, mc, mR / mc)
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


def _attach(
    m: float, i_g: float, c: complex, mc: float, R: complex
) -> tuple[float, float, complex]:
    """A body (m, I_G, c) with a point mass ``mc`` at ``R``: mass, I_G and centre of the whole."""
    total = m + mc
    centre = (m * c + mc * R) / total
    inertia = i_g + m * abs(c - centre) ** 2 + mc * abs(R - centre) ** 2
    return total, inertia, complex(centre)


@dataclass(frozen=True)
class SliderCrankBalance:
    """Crank counterweight of a slider-crank (single-cylinder engine).

    Attributes
    ----------
    mR : complex
        Counterweight ``m·R`` to add to the crank (frame: origin O2, x toward
        the crank pin A).
    rotating : complex
        The rotating mass moment ``m2 c2 + m3 a (1 − c3/b)`` it cancels (Norton's
        ``m_A·r``, crank frame).
    reciprocating : complex
        ``m_B = m4 + m3 c3/b``, the mass that moves with the piston (real when the
        rod's centre of mass lies on AB).
    fraction : float
        The fraction ``f`` of ``m_B`` overbalanced (0: rotating masses only).

    After balancing, the shaking force without external loads is
    ``F_s = −m_B (B̈ − f Ä)`` (see the module notes and :meth:`shaking_force`).
    """

    mR: complex
    rotating: complex
    reciprocating: complex
    fraction: float

    @property
    def angle_deg(self) -> float:
        """Angle of the counterweight from the crank line O2→A, degrees in [0, 360)."""
        return float(np.mod(np.degrees(np.angle(self.mR)), 360.0))

    def mass(self, radius: float) -> float:
        """Counterweight mass ``|mR| / R`` at the given radius from O2."""
        return abs(self.mR) / positive("radius", radius)

    def apply(
        self, mass: Sequence[float], inertia: Sequence[float], cg: Sequence[complex], radius: float
    ) -> tuple[tuple[float, ...], tuple[float, ...], tuple[complex, ...]]:
        """``(mass, inertia, cg)`` for :meth:`SliderCrank.dynamics` with the counterweight on.

        The counterweight is a point mass ``|mR| / radius`` at ``radius`` from
        O2; the crank's centre and ``I_G`` follow (parallel-axis theorem), the
        rod and the slider are unchanged.

        Examples
        --------
        >>> from machdyn.slidercrank import SliderCrank
        >>> bal = slidercrank_counterweight(SliderCrank(2.0, 6.0), (1, 2, 1), (1.0, 3.0))
        >>> mass, inertia, cg = bal.apply((1, 2, 1), (0.1, 0.5), (1.0, 3.0), radius=1.0)
        >>> mass, cg[0]
        ((4.0, 2.0, 1.0), (-0.5+0j))
        """
        m2, m3, m4 = (
            nonnegative(f"mass m{k}", v)
            for k, v in zip((2, 3, 4), _triple("mass", mass), strict=True)
        )
        i2, i3 = (
            nonnegative(f"inertia IG{k}", v)
            for k, v in zip((2, 3), _pair("inertia", inertia), strict=True)
        )
        c2, c3 = (
            _complex_scalar(f"cg c{k}", v) for k, v in zip((2, 3), _pair("cg", cg), strict=True)
        )
        radius = positive("radius", radius)
        if abs(self.mR) == 0:
            return (m2, m3, m4), (i2, i3), (c2, c3)
        mc = abs(self.mR) / radius
        m2n, i2n, c2n = _attach(m2, i2, c2, mc, self.mR / mc)
        return (m2n, m3, m4), (i2n, i3), (c2n, c3)

    def shaking_force(self, motion: Any) -> Any:
        """``−m_B (B̈ − f Ä)``: the balanced shaking force without external loads.

        ``motion`` is a :class:`~machdyn.slidercrank.SliderCrankMotion`; ``Ä`` is
        written from the crank (``(jα2 − ω2²) A``), ``B̈ = d̈``.
        """
        from .slidercrank import SliderCrankMotion

        instance("motion", motion, SliderCrankMotion, "a SliderCrankMotion (SliderCrank.solve)")
        A = np.asarray(motion.A)
        aA = (1j * np.asarray(motion.alpha2) - np.asarray(motion.omega2) ** 2) * A
        return -self.reciprocating * (np.asarray(motion.d_ddot) - self.fraction * aA)


def slidercrank_counterweight(
    slidercrank: Any, mass: Any, cg: Any, fraction: float = 0.0
) -> SliderCrankBalance:
    """The crank counterweight that balances a slider-crank's rotating masses.

    Parameters
    ----------
    slidercrank : SliderCrank
        Crank ``a``, rod ``b`` (any offset).
    mass : (m2, m3, m4)
        Crank, rod and slider masses.
    cg : (c2, c3)
        Centres of mass of the crank (frame O2, x toward A) and of the rod
        (frame A, x toward B), complex.
    fraction : float
        Part ``f`` of the reciprocating mass ``m_B`` to overbalance, 0 ≤ f ≤ 1
        (Norton: "overbalancing"; 0 balances the rotating masses exactly).

    Returns
    -------
    SliderCrankBalance
        ``.mR`` (crank frame), ``.reciprocating`` (``m_B``), ``.apply(...)``.

    Examples
    --------
    A 2-6 slider-crank, crank 1 kg with its centre at the pin's middle, rod
    2 kg at its middle, piston 1 kg: ``m2 c2 + m3 a/2 = 1 + 2 = 3``, so
    ``mR = −3`` (opposite the crank pin) and ``m_B = 1 + 2·½ = 2``:

    >>> from machdyn.slidercrank import SliderCrank
    >>> bal = slidercrank_counterweight(SliderCrank(2.0, 6.0), (1, 2, 1), (1.0, 3.0))
    >>> bal.mR, bal.reciprocating, bal.angle_deg
    ((-3+0j), (2+0j), 180.0)
    """
    from .slidercrank import SliderCrank

    instance("slidercrank", slidercrank, SliderCrank)
    m2, m3, m4 = (
        nonnegative(f"mass m{k}", v) for k, v in zip((2, 3, 4), _triple("mass", mass), strict=True)
    )
    c2, c3 = (_complex_scalar(f"cg c{k}", v) for k, v in zip((2, 3), _pair("cg", cg), strict=True))
    f = finite_scalar("fraction", fraction)
    if not 0.0 <= f <= 1.0:
        raise InputError("fraction", f"is a part of the reciprocating mass, 0 ≤ f ≤ 1; got {f}")
    a, b = slidercrank.a, slidercrank.b
    rotating = m2 * c2 + m3 * a * (1.0 - c3 / b)
    reciprocating = m4 + m3 * c3 / b
    mR = -rotating - f * a * reciprocating
    return SliderCrankBalance(
        complex(mR) + 0j, complex(rotating) + 0j, complex(reciprocating) + 0j, f
    )


def _pair(field: str, value: Any) -> tuple[Any, Any]:
    return items(field, value, 2, "values (links 2, 3)")  # type: ignore[return-value]


# -- any Linkage ------------------------------------------------------------------------


@dataclass(frozen=True)
class LinkageCounterweight:
    """One counterweight of a :class:`LinkageBalance`.

    Attributes
    ----------
    link : str
        The link it is fixed to (a link pinned to the ground).
    pivot : str
        That link's ground pivot (a point name).
    mR : complex
        Its mass moment about the pivot, ``m_c (C − O)``, in the drawing's
        frame at the drawn pose (it turns with the link).
    """

    link: str
    pivot: str
    mR: complex

    @property
    def angle_deg(self) -> float:
        """Direction of the counterweight from its pivot in the drawing, degrees in [0, 360)."""
        return float(np.mod(np.degrees(np.angle(self.mR)), 360.0))


@dataclass(frozen=True)
class LinkageBalance:
    """Counterweights for a :class:`~machdyn.linkage.Linkage` and what they do.

    Attributes
    ----------
    method : str
        ``"complete"`` (complete force balance, Berkof–Lowen: the total centre
        of mass stays put and the shaking force vanishes), ``"slider-crank"``
        (the crank balances the rotating masses; the reciprocating force of the
        slider's mass ``m_B`` stays) or ``"pivots"`` (each pivoted link's centre
        of mass on its pivot; the floating links still shake the frame).
    counterweights : tuple of LinkageCounterweight
    what : str
        One sentence saying exactly what the balance does.
    """

    method: str
    counterweights: tuple[LinkageCounterweight, ...]
    what: str

    def apply(self, linkage: Any, radius: Any = None) -> Any:
        """The same linkage with point-mass counterweights on (a new Linkage).

        Parameters
        ----------
        linkage : Linkage
            The linkage the balance was computed for.
        radius : float or mapping of link name to float, optional
            Distance of each counterweight from its pivot (its mass is then
            ``|mR| / radius``); default: the link's own reach (the farthest of
            its points from the pivot).

        Returns
        -------
        Linkage
            Each balanced link's mass, centre of mass and ``I_G`` include its
            counterweight (parallel-axis theorem); all else is unchanged.
        """
        from . import from_spec
        from .linkage import Linkage

        instance("linkage", linkage, Linkage)
        missing = [c.link for c in self.counterweights if c.link not in linkage.links]
        if missing:
            raise InputError(
                "linkage", f"has no link {missing[0]!r}: give the linkage the balance was made for"
            )
        lk = copy.copy(linkage)
        lk.units = None  # the spec in the numbers the linkage computes in
        spec = lk.to_spec("balanced")
        part = spec["linkage"]["balanced"]
        for cw in self.counterweights:
            link = linkage.links[cw.link]
            pivot = linkage.points[cw.pivot]
            r = _radius(radius, cw.link, max(abs(linkage.points[p] - pivot) for p in link.points))
            if abs(cw.mR) == 0:
                continue
            mc = abs(cw.mR) / r
            G = _drawn_cg(linkage, cw.link)
            m, i_g, G2 = _attach(link.mass, link.inertia, G, mc, pivot + cw.mR / mc)
            p0, e = _frame(linkage, cw.link)
            c = (G2 - p0) / e
            part["links"][cw.link].update(mass=m, inertia=i_g, cg=[c.real, c.imag])
        out = from_spec(spec)
        out.units = linkage.units
        return out


def linkage_counterweights(linkage: Any) -> LinkageBalance:
    """Counterweights that reduce a linkage's shaking force, by the best method that applies.

    * **complete** — every link with mass is either pinned to the ground or a
      floating link with two pins on two such links (a four-bar, a Watt
      six-bar, a pantograph on two cranks...): Berkof–Lowen's linearly
      independent vectors. A floating link's centre ``G = P + w (Q − P)``
      (``w`` fixed in it) puts ``m (1 − w)(P − O_p)`` on the link carrying P
      and ``m w (Q − O_q)`` on the one carrying Q, each a vector turning with
      that link; a counterweight on every pivoted link cancels its total, so
      the total centre of mass stays put and the shaking force is zero (for
      the four-bar this is :func:`fourbar_counterweights`).
    * **slider-crank** — a crank, a rod and a block sliding on the ground: the
      crank's counterweight balances the rotating masses
      (:func:`slidercrank_counterweight`); ``−m_B B̈`` along the slide stays.
    * **pivots** — otherwise: every link pinned to the ground gets a
      counterweight putting its own centre of mass on its pivot, so it adds
      no shaking force of its own; the floating links' shaking remains.

    Parameters
    ----------
    linkage : Linkage

    Returns
    -------
    LinkageBalance
        ``.apply(linkage, radius=...)`` gives the balanced linkage.

    Examples
    --------
    >>> from machdyn.linkage import Linkage
    >>> lk = (Linkage({"O2": (0, 0), "A": (2, 0), "B": (3, 1)}).ground("O2")
    ...       .link("arm", "O2", "A", "B", mass=2.0, inertia=0.5, cg=(1.0, 0.5))
    ...       .drive("arm"))
    >>> bal = linkage_counterweights(lk)
    >>> bal.method, bal.counterweights[0].mR
    ('complete', (-2-1j))
    """
    from .linkage import Linkage

    instance("linkage", linkage, Linkage)
    pivots = _pivots(linkage)
    complete = _complete_balance(linkage, pivots)
    if complete is not None:
        return complete
    shape = _slidercrank_shape(linkage, pivots)
    if shape is not None:
        return _slidercrank_balance(linkage, *shape)
    cws = []
    for link, pivot in pivots.items():
        mR = -linkage.links[link].mass * (_drawn_cg(linkage, link) - linkage.points[pivot])
        cws.append(LinkageCounterweight(link, pivot, complex(mR) + 0j))
    what = (
        "each link pinned to the ground ("
        + ", ".join(pivots)
        + ") gets a counterweight that puts its own centre of mass on its pivot, so it adds "
        "no shaking force; the floating links' shaking force remains"
        if pivots
        else "no link is pinned to the ground: a counterweight cannot balance anything here"
    )
    return LinkageBalance("pivots", tuple(cws), what)


def _radius(radius: Any, link: str, default: float) -> float:
    if radius is None:
        return default
    if isinstance(radius, Mapping):
        return positive(f"radius[{link!r}]", radius[link]) if link in radius else default
    return positive("radius", radius)


def _frame(lk: Any, link: str) -> tuple[complex, complex]:
    """Origin and unit x of a link's frame in the drawing (first point, toward its second)."""
    pts = lk.links[link].points
    p0 = complex(lk.points[pts[0]])
    if len(pts) < 2:
        return p0, 1.0 + 0j
    d = complex(lk.points[pts[1]]) - p0
    return p0, d / abs(d)


def _drawn_cg(lk: Any, link: str) -> complex:
    ln = lk.links[link]
    if isinstance(ln.cg, str):
        return complex(lk.points[ln.cg])
    p0, e = _frame(lk, link)
    return p0 + (0j if ln.cg is None else complex(ln.cg)) * e


def _pivots(lk: Any) -> dict[str, str]:
    """Each moving link pinned to the ground → its (first) ground pivot."""
    out: dict[str, str] = {}
    for j in lk.joints:
        if j.kind == "pin" and "ground" in j.links:
            for link in j.links:
                if link != "ground":
                    out.setdefault(link, j.points[0])
    return out


def _slidercrank_shape(lk: Any, pivots: dict[str, str]) -> tuple[str, ...] | None:
    """(crank, rod, block, A, B) when the moving links are a crank, a rod and a block on a slide."""
    joints = lk.joints
    pins = [j for j in joints if j.kind == "pin"]
    if len(lk.links) != 3 or len(pivots) != 1 or any(len(j.links) != 2 for j in pins):
        return None
    moving_pins = {frozenset(j.links): j.points[0] for j in pins if "ground" not in j.links}
    others = [j for j in joints if j.kind != "pin"]
    if len(moving_pins) != 2 or len(others) != 1 or others[0].kind != "slider":
        return None
    if others[0].links[1] != "ground":
        return None
    (crank,) = pivots
    block = others[0].links[0]
    rods = set(lk.links) - {crank, block}
    if len(rods) != 1:
        return None
    (rod,) = rods
    A = moving_pins.get(frozenset((crank, rod)))
    B = moving_pins.get(frozenset((rod, block)))
    if A and B and others[0].points[0] == B:
        return (crank, rod, block, A, B)
    return None


def _complete_balance(lk: Any, pivots: dict[str, str]) -> LinkageBalance | None:
    """Berkof–Lowen on every pivoted link, or None where a massive link is neither kind."""
    U = {k: lk.links[k].mass * (_drawn_cg(lk, k) - lk.points[o]) for k, o in pivots.items()}
    on_pivoted: dict[str, list[tuple[str, str]]] = {}  # floating link → [(point, pivoted link)]
    for j in lk.joints:
        if j.kind == "pin" and "ground" not in j.links:
            for c in j.links:
                on_pivoted.setdefault(c, []).extend(
                    (j.points[0], p) for p in j.links if p in pivots and p != c
                )
    for name, link in lk.links.items():
        if name in pivots or link.mass == 0:
            continue
        pair = next(
            (
                (P, p, Q, q)
                for i, (P, p) in enumerate(on_pivoted.get(name, []))
                for Q, q in on_pivoted[name][i + 1 :]
                if q != p and abs(lk.points[Q] - lk.points[P]) > 0
            ),
            None,
        )
        if pair is None:
            return None
        P, p, Q, q = pair
        zP, zQ = complex(lk.points[P]), complex(lk.points[Q])
        w = (_drawn_cg(lk, name) - zP) / (zQ - zP)  # fixed in the link: G = P + w (Q − P)
        U[p] += link.mass * (1.0 - w) * (zP - lk.points[pivots[p]])
        U[q] += link.mass * w * (zQ - lk.points[pivots[q]])
    if not pivots:
        return None
    cws = tuple(LinkageCounterweight(k, pivots[k], complex(-U[k]) + 0j) for k in pivots)
    what = (
        "complete force balance (Berkof–Lowen): counterweights on the links pinned to the ground "
        f"({', '.join(pivots)}) keep the total centre of mass fixed, so the shaking force "
        "vanishes (but for the machine's constant weight under gravity; the shaking moment "
        "does not, and usually grows)"
    )
    return LinkageBalance("complete", cws, what)


def _slidercrank_balance(lk: Any, crank: str, rod: str, block: str, A: str, B: str) -> Any:
    O2 = lk.points[_pivots(lk)[crank]]
    pA, pB = lk.points[A], lk.points[B]
    b = abs(pB - pA)
    c3 = (_drawn_cg(lk, rod) - pA) / ((pB - pA) / b)
    m2, m3, m4 = (lk.links[n].mass for n in (crank, rod, block))
    rotating = m2 * (_drawn_cg(lk, crank) - O2) + m3 * (1.0 - c3 / b) * (pA - O2)
    m_b = m4 + m3 * c3 / b
    cws = (LinkageCounterweight(crank, _pivots(lk)[crank], complex(-rotating) + 0j),)
    what = (
        f"the counterweight on {crank} balances the rotating masses ({crank} and the part of "
        f"{rod} at its crank pin); the reciprocating force −m_B·a_B of the slider and the rest of "
        f"the rod (m_B = {abs(m_b):.4g}) stays, along the slide"
    )
    return LinkageBalance("slider-crank", cws, what)
