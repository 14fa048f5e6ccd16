"""The Linkage's check of a six-bar fit (sixbar_path.sixbar_result): apart, at a toggle.

A Watt I six-bar (dyad on the coupler and the rocker, the point on link 6) whose
coupler and rocker (2.5 + 1.5) just reach across the crank pin's farthest distance
from O4 (r1 + r2 = 3 + 1) at θ = π: there they lie in line, a toggle. The coupler
point is placed by circle intersections here (no machdyn solver); at the toggle B
lies on the line A–O4, r3 from A.
"""

from __future__ import annotations

import numpy as np
from tests.closed_forms import circle_meet

from machdyn.synthesis.sixbar_path import sixbar_result

FIXED = dict(s4=1, s6=1, topology=3, on=6)
X = np.array([0.0, 0.0, 0.0, 3.0, 1.0, 2.5, 1.5, 0.5, 0.6, 0.5, -0.5, 2.0, 2.0, 0.5, 0.4])
THETA = np.r_[np.linspace(0.3, 2.8, 6), np.pi, np.linspace(3.6, 6.0, 5)]  # target 7 at π


def _point(x, theta):
    """The coupler point at crank angle ``theta`` by circle intersections (None if apart)."""
    O4 = complex(x[3], 0.0)  # O2 at the origin, the ground along +x
    A = x[4] * np.exp(1j * theta)
    d = abs(O4 - A)
    r3, r4 = x[5], x[6]
    if d > r3 + r4 + 1e-12:
        return None
    # the assembly the six-bar is drawn in at THETA[0] (s4 = +1: B left of A -> O4)
    B = A + r3 * (O4 - A) / d if d >= r3 + r4 - 1e-12 else circle_meet(A, r3, O4, r4, 1.0)
    C = A + complex(x[7], x[8]) * (B - A)
    D = O4 + complex(x[9], x[10]) * (B - O4)
    E = circle_meet(C, x[11], D, x[12], 1.0)
    return D + complex(x[13], x[14]) * (E - D)


def _drawn_side_matches():
    # the sides circle_meet takes above are the kernel's s = +1 (checked away from the toggle)
    from machdyn.synthesis.sixbar_path import sixbar_coupler

    P = sixbar_coupler(X, THETA[:3], FIXED)[0]
    return np.allclose(P, [_point(X, t) for t in THETA[:3]], atol=1e-12)


def test_a_six_bar_at_a_toggle_is_placed_there_and_named_not_called_apart():
    assert _drawn_side_matches()
    targets = np.array([_point(X, t) for t in THETA])
    assert abs(abs(complex(X[3], 0) - X[4] * np.exp(1j * np.pi)) - (X[5] + X[6])) < 1e-15
    res = sixbar_result(X, THETA, FIXED, targets, THETA - THETA[0], True, None)
    size = np.max(np.abs(targets - targets.mean()))
    # every target met, the toggle one too: its distance is measured, not inf
    assert np.all(np.isfinite(res.distance))
    assert np.max(np.delete(res.distance, 6)) <= 1e-12 * size
    assert res.distance[6] <= 1e-7 * size  # at the toggle: the square root of rounding
    assert not res.ok
    assert not any("cannot be assembled" in d for d in res.defects)
    (toggle,) = [d for d in res.defects if "toggle" in d]
    assert "targets [7]" in toggle


def test_a_six_bar_apart_at_some_targets_says_which():
    x = X.copy()
    x[6] = 1.4  # coupler + rocker 3.9: short of the crank pin's reach near θ = π
    reach = [_point(x, t) is not None for t in THETA]
    apart = [i + 1 for i, ok in enumerate(reach) if not ok]
    assert apart and reach[0]  # drawn at the first target
    targets = np.array([_point(x, t) if ok else 0j for t, ok in zip(THETA, reach, strict=True)])
    res = sixbar_result(x, THETA, FIXED, targets, THETA - THETA[0], True, None)
    np.testing.assert_array_equal(np.isinf(res.distance), ~np.array(reach))
    assert np.max(res.distance[np.array(reach)]) <= 1e-9
    (msg,) = [d for d in res.defects if "cannot be assembled" in d]
    assert f"targets {apart}" in msg
    assert not any("toggle" in d for d in res.defects)
