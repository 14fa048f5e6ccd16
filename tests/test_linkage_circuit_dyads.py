"""Several drivers, two RRR dyads: each dyad's dip between scanned points is followed on its own.

Where an RRR dyad's margin dips between two scanned points of a path, the dip is
scanned again around *that dyad's* least margin (``paths._Scan.dips``), not the
least over all dyads: a second dyad whose margin stays small but positive
elsewhere (a four-bar a little off the change-point condition) must not draw the
search away from the first one's change point. The references are written here:
the parallelogram's change points where its crank lies along the ground line
(``sin θ = 0``, ``reached_without_a_change_point``), the second dyad's margin
from the distance of its pivots.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from closed_forms import circle_meet
from machdyn.linkage import Linkage
from test_linkage_circuit_narrow import reached_without_a_change_point

pytestmark = pytest.mark.usefixtures("backend")  # NumPy, then the compiled kernel


def parallelogram_and_near_miss(margin):
    """``parallelogram_and_arm``'s parallelogram (driven at c1) and a second four-bar
    O6-F-G-O8 (crank 2, coupler 5, rocker 2 + ε, ground 5; driven at c2) a little off
    the change-point condition: at c2 = 180° its pivots F, O8 are 7 apart, and its dyad's
    relative margin ``(5 + 2 + ε − 7) / (7 + ε)`` is ``margin`` (> CHANGE_POINT_RTOL)."""
    eps = 7 * margin / (1 - margin)
    A = 2 * np.exp(1j * math.radians(60.0))
    F = 20 + 2j  # c2 drawn at 90°
    G = circle_meet(F, 5.0, 25 + 0j, 2.0 + eps, 1.0)
    pts = {"O2": 0j, "O4": 5 + 0j, "A": A, "B": A + 5, "O6": 20 + 0j, "O8": 25 + 0j, "F": F, "G": G}
    lk = Linkage(pts).ground("O2", "O4", "O6", "O8").link("c1", "O2", "A").link("cp", "A", "B")
    lk.link("r", "O4", "B").link("c2", "O6", "F").link("cq", "F", "G").link("q", "O8", "G")
    return lk.drive("c1", "c2"), eps


@pytest.mark.parametrize("k", range(0, 16, 2))
def test_a_change_point_is_found_while_another_dyad_has_the_least_margin(k):
    # c2 held at 180°: the second dyad's margin stays at 3e-9 all along the sweep, below
    # the parallelogram's near its change point (0.102 δ², δ rad from it: its D written
    # below) at most of the points of a scan; the parallelogram's dip is followed on its
    # own margin. (The sweep shifted by k/16 of a 64th of two scan steps: before, with
    # the least margin over both dyads followed, k = 7, 8 and 10 of 0 … 15 showed the
    # 120 samples past the change point ok, on the crossed form.)
    lk, eps = parallelogram_and_near_miss(3e-9)
    th = np.radians(np.arange(60.0 + k / 16 * 0.5 / 16, 300.0, 1.0))
    c2 = np.full(th.size, math.pi)
    D = np.abs(20 + 2 * np.exp(1j * c2) - 25)  # the second dyad: closes, never touches
    assert np.allclose((5 + 2 + eps - D) / (7 + eps), 3e-9, rtol=1e-6, atol=0)
    m = lk.solve({"c1": th, "c2": c2})
    expected = reached_without_a_change_point(th, math.radians(60.0), True)
    assert expected.sum() == 120 and (m.ok == expected).all(), np.flatnonzero(m.ok != expected)
    assert np.allclose(m.theta["cp"][m.ok], 0.0, atol=1e-9)  # the drawn form
    first = int(np.argmax(~expected))
    assert f"(before sample {first}) passes a change point of RRR dyad (cp, r)" in m.reason[first]
