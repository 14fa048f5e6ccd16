"""Shaking force before/after counterweights: slider-crank and any Linkage.

Independent references (none shares the balancing code's path):

* the slider-crank's piston position written here by hand,
  ``d = a cos θ + √(b² − a² sin² θ)`` (zero offset), differentiated by hand
  twice: after the crank counterweight the shaking force must be
  ``−m_B d̈`` along the slide with ``m_B = m4 + m3 c3/b`` (Norton ch. 13,
  "Balancing the single-cylinder engine"), solved by the Newton–Euler
  assembler (SliderCrank.dynamics) on the crank with the counterweight on;
* its harmonics (Norton's piston acceleration ``−aω²(cos θ + (a/b) cos 2θ)``):
  the primary is exactly ``m_B a ω²`` (the square root is even and of period π,
  so all of the first harmonic is ``a cos θ``), the secondary
  ``m_B a ω² λ (1 + λ²/4 + …)``, λ = a/b, from the binomial series written here;
* overbalancing a fraction f: the primary splits into ``(1 − f)`` along the
  slide and ``f`` across it;
* a Linkage drawn as a four-bar, and a Watt six-bar: the complete force balance
  makes the shaking force vanish at every pose (Linkage.forces on the rebuilt
  linkage) and the total centre of mass stand still; the four-bar's
  counterweights equal Norton's closed-form conditions (fourbar_counterweights,
  in the FourBar's own link frames);
* any other Linkage: the counterweights put each pivoted link's centre of mass
  on its pivot (read back from the rebuilt linkage), and the shaking force
  changes by exactly ``−Σ m_c a_C`` of the point masses added (momentum,
  written here).
"""

from __future__ import annotations

import numpy as np
import pytest

from closed_forms import circle_meet
from machdyn import FourBar, SliderCrank
from machdyn.errors import InputError
from machdyn.linkage import Linkage
from machdyn.shaking import (
    fourbar_counterweights,
    linkage_counterweights,
    slidercrank_counterweight,
)

W = 30.0  # rad/s


def piston(a: float, b: float, th: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """d(θ) and d''(θ) of a zero-offset slider-crank, by hand."""
    s = np.sqrt(b**2 - a**2 * np.sin(th) ** 2)
    d = a * np.cos(th) + s
    d2 = -a * np.cos(th) - a**2 * np.cos(2 * th) / s - a**4 * (np.sin(th) * np.cos(th)) ** 2 / s**3
    return d, d2


def harmonic(y: np.ndarray, k: int) -> complex:
    """Complex amplitude of the k-th harmonic of samples over one uniform turn."""
    return 2 * np.fft.fft(y)[k] / y.size


@pytest.fixture(scope="module")
def engine():
    a, b = 2.0, 7.0
    sc = SliderCrank(a, b)
    mass, inertia, cg = (1.5, 2.0, 3.0), (0.2, 4.0), (0.6 + 0.1j, 2.5)
    th = np.linspace(0, 2 * np.pi, 720, endpoint=False)
    return sc, mass, inertia, cg, th


def test_crank_counterweight_leaves_the_reciprocating_force_along_the_slide(engine):
    sc, mass, inertia, cg, th = engine
    a, b = sc.a, sc.b
    bal = slidercrank_counterweight(sc, mass, cg)
    m_b = mass[2] + mass[1] * cg[1] / b
    assert bal.reciprocating == pytest.approx(m_b)
    before = sc.dynamics(th, W, mass=mass, inertia=inertia, cg=cg).shaking_force
    props = bal.apply(mass, inertia, cg, 1.0)
    after = sc.dynamics(th, W, mass=props[0], inertia=props[1], cg=props[2])
    Fs = after.shaking_force
    _, d2 = piston(a, b, th)
    scale = m_b * a * W**2
    assert np.max(np.abs(Fs - (-m_b * d2 * W**2))) < 1e-9 * scale
    assert np.max(np.abs(Fs.imag)) < 1e-9 * scale  # nothing across the slide
    assert np.max(np.abs(before.imag)) > 0.1 * scale  # ... which there was before
    # Norton's harmonics: the primary exactly m_B a ω², the secondary ≈ its λ times
    lam = a / b
    assert abs(harmonic(Fs.real, 1)) == pytest.approx(scale, rel=1e-9)
    assert abs(harmonic(Fs.real, 2)) == pytest.approx(scale * lam * (1 + lam**2 / 4), rel=1e-3)
    assert abs(harmonic(Fs.real, 2)) == pytest.approx(scale * lam, rel=0.03)


def test_overbalancing_turns_part_of_the_primary_across_the_slide(engine):
    sc, mass, inertia, cg, th = engine
    f = 0.5
    bal = slidercrank_counterweight(sc, mass, cg, fraction=f)
    props = bal.apply(mass, inertia, cg, radius=1.5)
    Fs = sc.dynamics(th, W, mass=props[0], inertia=props[1], cg=props[2]).shaking_force
    scale = bal.reciprocating.real * sc.a * W**2
    assert abs(harmonic(Fs.real, 1)) == pytest.approx((1 - f) * scale, rel=1e-9)
    assert abs(harmonic(Fs.imag, 1)) == pytest.approx(f * scale, rel=1e-9)
    m = sc.solve(th, W)
    assert np.allclose(Fs, bal.shaking_force(m), rtol=0, atol=1e-9 * scale)


def test_an_offset_engine_with_an_off_line_rod_centre():
    sc = SliderCrank(2.0, 6.5, 0.8)
    mass, inertia, cg = (1.0, 2.5, 2.0), (0.1, 3.0), (0.7 - 0.2j, 2.0 + 0.3j)
    th = np.linspace(0, 2 * np.pi, 360, endpoint=False)
    bal = slidercrank_counterweight(sc, mass, cg)
    props = bal.apply(mass, inertia, cg, radius=1.0)
    m = sc.solve(th, W)
    Fs = sc.dynamics(th, W, mass=props[0], inertia=props[1], cg=props[2]).shaking_force
    # the whole centre of mass, written here: Σ m rG = m_B·B + const → F_s = −m_B B̈
    m_b = mass[2] + mass[1] * cg[1] / sc.b
    assert np.allclose(Fs, -m_b * m.d_ddot, rtol=0, atol=1e-9 * abs(m_b) * sc.a * W**2)


def test_bad_fraction_and_properties_are_refused(engine):
    sc, mass, _, cg, _ = engine
    with pytest.raises(InputError, match="fraction"):
        slidercrank_counterweight(sc, mass, cg, fraction=1.5)
    with pytest.raises(InputError, match="cg"):
        slidercrank_counterweight(sc, mass, (1.0,))
    with pytest.raises(InputError):
        slidercrank_counterweight(object(), mass, cg)


# -- Linkage ---------------------------------------------------------------------------


def fourbar_linkage() -> Linkage:
    O2, O4 = 1.0 + 0.5j, 1.0 + 0.5j + 8 * np.exp(0.3j)  # a tilted ground line
    A = O2 + 4 * np.exp(1.1j)
    B = circle_meet(A, 7.0, O4, 6.0)
    return (
        Linkage({"O2": O2, "O4": O4, "A": A, "B": B, "P": A + 2 + 3j})
        .ground("O2", "O4")
        .link("crank", "O2", "A", mass=1.0, inertia=0.1, cg=2.0 + 0.3j)
        .link("coupler", "A", "B", "P", mass=2.0, inertia=0.5, cg="P")
        .link("rocker", "B", "O4", mass=1.5, inertia=0.3, cg=2.5 - 0.2j)
        .drive("crank")
    )


def sweep(lk: Linkage, n: int = 240):
    x = lk.drawn_inputs[lk.drivers[0]] + np.linspace(0, 2 * np.pi, n, endpoint=False)
    return x, lk.solve(x, velocity=W)


def fully_balanced(lk: Linkage) -> None:
    """The balanced linkage's shaking force vanishes and its centre of mass stands still."""
    bal = linkage_counterweights(lk)
    assert bal.method == "complete"
    _, m = sweep(lk)
    before = lk.forces(m).shaking_force
    balanced = bal.apply(lk)
    _, m2 = sweep(balanced)
    after = balanced.forces(m2).shaking_force
    peak = np.abs(before).max()
    assert peak > 1.0 and np.abs(after).max() < 1e-9 * peak
    # ... and the machine's centre of mass stays put (positions only, no forces)
    total = sum(link.mass * np.asarray(m2.cg[name]) for name, link in balanced.links.items())
    assert np.ptp(total.real) < 1e-9 and np.ptp(total.imag) < 1e-9
    return bal


def test_a_fourbar_linkage_is_fully_force_balanced():
    lk = fourbar_linkage()
    bal = fully_balanced(lk)
    assert {c.link for c in bal.counterweights} == {"crank", "rocker"}
    # Norton's conditions in the FourBar's frames (origin O2, x toward A; A → B; O4 → B)
    P = lk.points
    fb = FourBar(
        abs(P["O4"] - P["O2"]), abs(P["A"] - P["O2"]), abs(P["B"] - P["A"]), abs(P["B"] - P["O4"])
    )
    e2, e3, e4 = (
        (P["A"] - P["O2"]) / fb.r2,
        (P["B"] - P["A"]) / fb.r3,
        (P["B"] - P["O4"]) / fb.r4,
    )
    cg = (
        (2.0 + 0.3j) * ((P["A"] - P["O2"]) / fb.r2) / e2,
        (P["P"] - P["A"]) / e3,
        (P["B"] + (2.5 - 0.2j) * (P["O4"] - P["B"]) / abs(P["O4"] - P["B"]) - P["O4"]) / e4,
    )
    cw = fourbar_counterweights(fb, (1.0, 2.0, 1.5), cg)
    mR = {c.link: c.mR for c in bal.counterweights}
    assert mR["crank"] == pytest.approx(cw.mR2 * e2, abs=1e-12)
    assert mR["rocker"] == pytest.approx(cw.mR4 * e4, abs=1e-12)


def test_a_watt_sixbar_is_fully_force_balanced():
    from test_report import watt

    bal = fully_balanced(watt())
    assert {(c.link, c.pivot) for c in bal.counterweights} == {
        ("2", "O2"),
        ("4", "O4"),
        ("6", "O6"),
    }


def test_a_slidercrank_linkage_keeps_only_its_reciprocating_force():
    lk = (
        Linkage({"O2": (0, 0), "A": (1.2, 1.6), "B": (7.5, 0.0)})
        .ground("O2")
        .link("crank", "O2", "A", mass=1.0, inertia=0.1, cg=0.8 + 0.1j)
        .link("rod", "A", "B", mass=2.0, inertia=2.0, cg=2.0)
        .link("piston", "B", mass=1.5, inertia=0.01)
        .slider("piston", "ground", "B", 0.0, name="bore")
        .drive("crank")
    )
    bal = linkage_counterweights(lk)
    assert bal.method == "slider-crank"
    balanced = bal.apply(lk)
    _, m = sweep(balanced)
    Fs = balanced.forces(m).shaking_force
    b = abs(lk.points["B"] - lk.points["A"])
    m_b = 1.5 + 2.0 * 2.0 / b
    aB = np.asarray(m.point_acceleration["B"])
    assert np.allclose(Fs, -m_b * aB, rtol=0, atol=1e-9 * np.abs(Fs).max())


def test_any_linkage_gets_its_pivoted_links_centres_on_their_pivots():
    # a four-bar driving a slider through a rod from its coupler: the block moves
    # on a line and the rod hangs on a floating link, so no complete balance
    lk = fourbar_linkage()
    C = lk.points["P"] + 6.0
    lk = Linkage({**lk.points, "C": complex(C.real, C.imag)})
    lk.ground("O2", "O4")
    lk.link("crank", "O2", "A", mass=1.0, inertia=0.1, cg=2.0 + 0.3j)
    lk.link("coupler", "A", "B", "P", mass=2.0, inertia=0.5, cg="P")
    lk.link("rocker", "B", "O4", mass=1.5, inertia=0.3, cg=2.5 - 0.2j)
    lk.link("rod", "P", "C", mass=1.0, inertia=1.0, cg=3.0)
    lk.link("block", "C", mass=0.8, inertia=0.01)
    lk.slider("block", "ground", "C", 0.0, name="guide").drive("crank")
    bal = linkage_counterweights(lk)
    assert bal.method == "pivots"
    assert {(c.link, c.pivot) for c in bal.counterweights} == {
        ("crank", "O2"),
        ("rocker", "O4"),
    }
    radius = 1.7
    balanced = bal.apply(lk, radius=radius)
    _, m = sweep(lk)
    _, m2 = sweep(balanced)
    for c in bal.counterweights:  # the new centre of mass sits on the pivot at every pose
        assert np.allclose(m2.cg[c.link], balanced.points[c.pivot], atol=1e-12)
    # momentum: the shaking force changes by −Σ m_c a_C of the point masses added, each
    # at C = pivot + r, r = (mR/m_c) turned with its link from the drawn pose
    before, after = lk.forces(m).shaking_force, balanced.forces(m2).shaking_force
    change = 0
    for c in bal.counterweights:
        mc = abs(c.mR) / radius
        p, q = lk.links[c.link].points[:2]
        drawn = np.angle(lk.points[q] - lk.points[p])
        r = (c.mR / mc) * np.exp(1j * (np.asarray(m.theta[c.link]) - drawn))
        w, al = np.asarray(m.omega[c.link]), np.asarray(m.alpha[c.link])
        change = change - mc * (1j * al - w * w) * r
    ok = np.isfinite(before) & np.isfinite(after)
    assert ok.sum() > 100
    scale = np.abs(before[ok]).max()
    assert np.allclose((after - before)[ok], change[ok], rtol=0, atol=1e-9 * scale)
    assert np.abs(change[ok]).max() > 0.1 * np.median(np.abs(before[ok]))  # they change it


def test_a_linkage_without_a_pivoted_link_has_nothing_to_balance():
    lk = (
        Linkage({"A": (0, 0), "B": (5, 0)})
        .link("block", "A", mass=1.0, inertia=0.1)
        .slider("block", "ground", "A", 0.0, name="s")
        .drive("s")
    )
    bal = linkage_counterweights(lk)
    assert bal.counterweights == () and "no link" in bal.what
