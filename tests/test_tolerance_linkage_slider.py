"""Tolerance of a drawn Linkage with RRP dyads (a block on a straight ground guide).

Checked against what shares no code with the family solver's RRP closed form:

* every sample drawn here as its own ``Linkage`` (the block placed on the sample's
  guide line by a circle–line intersection written in this file) and solved by
  ``Linkage.solve``;
* the ``SliderCrank`` tolerance (its own closed forms and derivatives) on a plain
  slider-crank drawn as a Linkage: same linear prediction;
* Monte Carlo against the linearised std for small tolerances;
* the dual-number derivatives against central differences of the solved family.
"""

from __future__ import annotations

import cmath
import math

import numpy as np
import pytest

import machdyn
from machdyn import SliderCrank
from machdyn._linkage_family import Family
from machdyn.errors import InputError
from machdyn.linkage import Linkage

POSES = np.radians(np.arange(0.0, 360.0, 20.0))
PHI = 0.15  # the guide's drawn direction
A_DRAWN = 2.0 * cmath.exp(0.4j)
Q_DRAWN = 8.0 + 8.0 * math.tan(PHI) * 1j  # a point of the guide's drawn line


def _on_line(A, b, Q, u, ahead):
    """The point of the line ``Q + s u`` at distance ``b`` from ``A`` (ahead of A's foot)."""
    t0 = ((Q - A) * u.conjugate()).real
    c = ((Q - A) * u.conjugate()).imag
    s = -t0 + (1 if ahead else -1) * math.sqrt(b * b - c * c)
    return Q + s * u


def slider6(O2=0j, A=A_DRAWN, b=6.5, phi=PHI, e=0.0, c5=5.0, p=3.0, delta=0.5, Q=Q_DRAWN):
    """A six-bar of two sliders: crank, rod A-B-C on a block at B (guide ``guide``), link 5
    from C to a ram D on a second guide (``ram``), drawn here from its dimensions."""
    u = cmath.exp(1j * phi)
    B = _on_line(A, b, Q + 1j * u * e, u, True)
    C = A + p * (B - A) / abs(B - A) * cmath.exp(1j * delta)
    v = cmath.exp(1.45j)
    D = _on_line(C, c5, 2.4 + 6j, v, True)
    return (
        Linkage({"O2": O2, "A": A, "B": B, "C": C, "D": D}).ground("O2")
        .link("crank", "O2", "A").link("rod", "A", "B", "C").link("block", "B")
        .slider("block", "ground", "B", phi, name="guide").link("link5", "C", "D")
        .link("ram", "D").slider("ram", "ground", "D", 1.45, name="ram").drive("crank")
    )  # fmt: skip


NOMINAL = dict(O2=0j, A=A_DRAWN, b=6.5, phi=PHI, e=0.0, c5=5.0, p=3.0, delta=0.5)


def test_displacement_from_the_through_point():
    lk = (Linkage({"O2": 0j, "A": 2j, "B": 6 + 0.5j, "G": -3 + 0.5j}).ground("O2", "G")
          .link("crank", "O2", "A").link("rod", "A", "B").link("block", "B")
          .slider("block", "ground", "B", 0.0, through="G", name="guide")
          .drive("crank"))  # fmt: skip
    fam = Family(lk)
    st, _ = fam.solve(fam.geometry(fam.nominal[None]), [POSES], 0)
    np.testing.assert_allclose(fam.slide(st, "guide")[0], lk.solve(POSES).lengths["guide"])


def test_dimensions_named_as_the_builder_names_them():
    fam = Family(slider6())
    for name in ("guide.angle", "guide.offset", "ram.angle", "ram.offset", "A-B", "C.p"):
        assert name in fam.names
    assert "length.guide" in fam.output_names() and "length.ram" in fam.output_names()
    assert fam.nominal[fam.names.index("guide.angle")] == pytest.approx(PHI)


def test_every_sample_against_its_own_linkage():
    lk = slider6()
    fam = Family(lk)
    rng = np.random.default_rng(3)
    names = ("O2.x", "O2.y", "O2-A", "A-B", "guide.angle", "guide.offset", "C.p", "C.delta")
    for _ in range(6):
        dev = rng.uniform(-0.05, 0.05, len(names))
        row = fam.nominal.copy()
        for n, dv in zip(names, dev, strict=True):
            row[fam.names.index(n)] += dv
        st, closes = fam.solve(fam.geometry(row[None]), [POSES, 2.0, 0.5], 2)
        assert closes.all()
        s = dict(NOMINAL)
        # "O2-A" moves A along O2 → A (drawn at 0.4 rad); "A-B" moves B along A → B, then
        # the line through it; C.p and C.delta are polar from A relative to A → B.
        # "O2.x", "O2.y" move the pivot alone (the crank's length follows); "O2-A" then
        # moves A along O2 → A. The rod keeps its drawn B and C relative to A ("A-B" moves
        # B along A → B; "C.p", "C.delta" are C's polar coordinates from A, from A → B).
        O2 = complex(dev[0], dev[1])
        A0 = NOMINAL["A"] - O2
        A = O2 + A0 / abs(A0) * (abs(A0) + dev[2])
        B0, C0 = lk.points["B"] - NOMINAL["A"], lk.points["C"] - NOMINAL["A"]
        s.update(O2=O2, A=A, b=abs(B0) + dev[3], phi=PHI + dev[4], e=dev[5],
                 p=abs(C0) + dev[6], delta=cmath.phase(C0 / B0) + dev[7],
                 Q=lk.points["B"])  # fmt: skip
        # The sample's guide turns about the drawn B and shifts by e across it;
        # the ram's guide and link 5 as drawn.
        m = slider6(**s).solve(POSES, velocity=2.0, acceleration=0.5)
        for link in ("rod", "link5"):
            turn = np.angle(st.direction(link)[0] * np.exp(-1j * m.theta[link]))
            np.testing.assert_allclose(turn, 0.0, atol=1e-9)
            np.testing.assert_allclose(st.w[link][0], m.omega[link], atol=1e-9)
            np.testing.assert_allclose(st.al[link][0], m.alpha[link], atol=1e-9)
        for p in ("B", "C", "D"):
            owner = fam.owner(p)
            np.testing.assert_allclose(st.pos(owner, p)[0], m.points[p], atol=1e-9)
            np.testing.assert_allclose(st.acc(owner, p)[0], m.point_acceleration[p], atol=1e-8)
        for g in ("guide", "ram"):
            np.testing.assert_allclose(fam.slide(st, g)[0], m.lengths[g], atol=1e-9)


def slider_crank(a=2.0, b=6.0, c=0.5):
    """SliderCrank(a, b, c) drawn as a Linkage at θ2 = 30°: block at y = c, guide along +x."""
    A = a * cmath.exp(1j * math.radians(30.0))
    B = complex(A.real + math.sqrt(b * b - (c - A.imag) ** 2), c)
    return (
        Linkage({"O2": 0j, "A": A, "B": B}).ground("O2").link("crank", "O2", "A")
        .link("rod", "A", "B").link("block", "B").slider("block", "ground", "B", 0.0, name="guide")
        .drive("crank")
    )  # fmt: skip


def test_slider_crank_drawn_as_a_linkage_matches_the_slider_crank_tolerance():
    theta = np.radians(np.arange(0.0, 360.0, 10.0))
    sc = machdyn.tolerance(SliderCrank(2.0, 6.0, 0.5), {"crank": 0.02, "coupler": 0.03,
                           "offset": 0.04}, theta, samples=2000, outputs=["d"])  # fmt: skip
    lk = machdyn.tolerance(slider_crank(), {"O2-A": 0.02, "A-B": 0.03, "guide.offset": 0.04},
                           theta, samples=2000, outputs=["length.guide"])  # fmt: skip
    d, g = sc.outputs["d"], lk.outputs["length.guide"]
    np.testing.assert_allclose(g.nominal, d.nominal, atol=1e-9)
    np.testing.assert_allclose(g.linear_std, d.linear_std, rtol=1e-7, atol=1e-12)
    np.testing.assert_allclose(g.worst_case, d.worst_case, rtol=1e-7, atol=1e-12)


def test_linear_std_against_monte_carlo_for_small_tolerances():
    tol = {"O2-A": 0.002, "A-B": 0.003, "guide.angle": 0.001, "guide.offset": 0.003,
           "C.p": 0.002, "ram.offset": 0.002, "C-D": 0.002}  # fmt: skip
    t = machdyn.tolerance(slider6(), tol, POSES, samples=40000, seed=2)
    assert t.failed == 0
    for name in ("length.guide", "length.ram", "theta.link5", "point.D"):
        s = t.outputs[name]
        np.testing.assert_allclose(s.std, s.linear_std, rtol=0.03)


def test_dual_derivatives_against_central_differences():
    fam = Family(slider6())
    h = 1e-6
    index = np.arange(len(fam.names))
    st, _ = fam.solve(fam.seeded(index), [POSES, 2.0, 0.5], 2)
    for out in ("length.guide", "length.ram", "point.D", "theta.link5"):
        value = fam.value(st, out)
        d = (value.d / value.v[..., None]).imag if out.startswith("theta.") else value.d
        for i in index:
            rows = np.repeat(fam.nominal[None], 2, axis=0)
            rows[0, i] += h
            rows[1, i] -= h
            s2, _ = fam.solve(fam.geometry(rows), [POSES, 2.0, 0.5], 2)
            v = fam.value(s2, out)
            fd = (np.angle(v[0] / v[1]) if out.startswith("theta.") else v[0] - v[1]) / (2 * h)
            np.testing.assert_allclose(d[0, :, i], fd, atol=1e-6, err_msg=f"{out}/{fam.names[i]}")


def test_refusals_name_the_group_and_the_dimension():
    moving = (Linkage({"O2": 0j, "A": 2j, "O4": 5 + 0j, "B": 5 + 3j, "C": 4 + 5j})
              .ground("O2", "O4").link("crank", "O2", "A").link("rocker", "O4", "B")
              .link("rod", "A", "C").link("block", "C")
              .slider("block", "rocker", "C", "B", name="rail")
              .link("tie", "B", "C").drive("crank"))  # fmt: skip
    with pytest.raises(InputError, match=r"not solved in closed form"):
        Family(moving)
    with pytest.raises(InputError, match=r"tolerances\[guide.angle\]"):
        machdyn.tolerance(slider6(), {"guide.angle": 4.0})
