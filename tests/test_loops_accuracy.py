"""Accuracy of the general solver whatever the sweep's order, and its ``tol`` (issue #10 item 5).

Reference: ``machdyn.FourBar``'s closed form (law of cosines; no Newton, no
continuation), on the NumPy and the compiled kernels (``backend``). Before the
fix a uniform sweep agreed with it to 6e-15 but one out-of-order sample dropped
every sample to about 1e-12 (Newton stopped at its tolerance); now every pose is
polished to the rounding floor.
"""

from __future__ import annotations

import numpy as np
import pytest

from machdyn import FourBar
from machdyn.errors import InputError
from machdyn.loops import LoopSystem

pytestmark = pytest.mark.usefixtures("backend")

R1, R2, R3, R4 = 8.0, 2.0, 7.0, 6.0  # GCRR crank-rocker


def fourbar() -> LoopSystem:
    return (
        LoopSystem()
        .vector("R1", R1, 0.0)
        .vector("R2", R2, "theta2")
        .vector("R3", R3, "theta3")
        .vector("R4", R4, "theta4")
        .loop("R2 + R3 - R4 - R1")
        .point("B", "R2 + R3")
        .inputs("theta2")
    )


def wrap(angle):
    return np.angle(np.exp(1j * np.asarray(angle)))


def sweeps() -> dict[str, np.ndarray]:
    base = np.linspace(0.0, 2 * np.pi, 721)
    rng = np.random.default_rng(105)
    return {
        "uniform": base,
        "one sample out of order": np.concatenate([base[:300], [base[100]], base[300:]]),
        "reversed": base[::-1].copy(),
        "there and back to the start": np.concatenate([base, base[-2::-1]]),
        "shuffled": rng.permutation(base),
        "uneven": np.sort(rng.uniform(0.0, 2 * np.pi, 721)),
    }


@pytest.mark.parametrize("order", list(sweeps()))
@pytest.mark.parametrize("form", [1, 2])
def test_every_sweep_order_agrees_with_the_closed_form_to_rounding(order, form):
    theta2 = sweeps()[order]
    closed = FourBar(R1, R2, R3, R4).solve(theta2, omega2=3.0, alpha2=-2.0, form=form)
    assert closed.ok.all()
    guess = {"theta3": float(closed.theta3[0]), "theta4": float(closed.theta4[0])}
    m = fourbar().solve(
        {"theta2": theta2}, guess, velocity={"theta2": 3.0}, acceleration={"theta2": -2.0}
    )
    assert m.ok.all()
    for k in (3, 4):  # angles of magnitude ~1: relative = absolute
        assert np.abs(wrap(m[f"theta{k}"] - getattr(closed, f"theta{k}"))).max() < 1e-14
        for ours, theirs in (
            (m.velocity[f"theta{k}"], getattr(closed, f"omega{k}")),
            (m.acceleration[f"theta{k}"], getattr(closed, f"alpha{k}")),
        ):
            assert np.abs(ours - theirs).max() < 1e-13 * np.abs(theirs).max()
    # the residual reported is the closure of the poses returned, recomputed here
    closure = (
        R2 * np.exp(1j * theta2)
        + R3 * np.exp(1j * m["theta3"])
        - R4 * np.exp(1j * m["theta4"])
        - R1
    )
    scale = np.mean([R1, R2, R3, R4])
    assert np.abs(closure).max() / scale < 4e-15
    assert m.residual.max() < 4e-15


def test_the_order_changes_nothing_beyond_rounding():
    """The same inputs in any order give the same poses (to a few ulps)."""
    s = fourbar()
    all_sweeps = sweeps()
    base = all_sweeps["uniform"]
    ref = s.solve({"theta2": base}, {"theta3": 0.5, "theta4": 1.5})
    lookup = {float(t): i for i, t in enumerate(base)}
    for name, theta2 in all_sweeps.items():
        if name == "uneven":  # (other inputs)
            continue
        g = int(lookup[float(theta2[0])])
        guess = {"theta3": float(ref["theta3"][g]), "theta4": float(ref["theta4"][g])}
        m = s.solve({"theta2": theta2}, guess)
        idx = [lookup[float(t)] for t in theta2]
        for k in ("theta3", "theta4"):
            assert np.abs(wrap(m[k] - ref[k][idx])).max() < 4e-15, name


@pytest.mark.parametrize(
    "bad",
    [np.inf, -np.inf, np.nan, 0.0, -1e-12, 1e-3, 1.0, 1e-20, "tight", None, True, 1e-12 + 1e-13j],
)
def test_tol_is_checked(bad):
    with pytest.raises(InputError, match="tol"):
        fourbar().solve({"theta2": [0.1, 0.2]}, {"theta3": 0.5, "theta4": 1.5}, tol=bad)


@pytest.mark.parametrize("tol", [1e-6, 1e-12, 1e-15])
def test_any_allowed_tol_returns_poses_at_the_rounding_floor(tol):
    theta2 = np.linspace(0.0, 2 * np.pi, 400) ** 1.02  # uneven: the careful path
    closed = FourBar(R1, R2, R3, R4).solve(theta2, form=1)
    guess = {"theta3": float(closed.theta3[0]), "theta4": float(closed.theta4[0])}
    m = fourbar().solve({"theta2": theta2}, guess, tol=tol)
    assert m.ok.all()
    assert np.abs(wrap(m["theta4"] - closed.theta4)).max() < 1e-14
