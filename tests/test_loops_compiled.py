"""The compiled sweep of the general solver equals its NumPy continuation, field by field.

``machdyn.loops`` solves a sweep of a model whose groups are dyads and single
constraints with a numba kernel (``machdyn.loops._kernels``: each dyad in closed
form on the sweep's branch) when :mod:`machdyn.jit` lets the compiled kernels
serve; otherwise by its NumPy Newton–Raphson continuation. The two share no
solving code. Here the same calls go to both (``jit.set_mode("off")`` /
``"on"``) and every field of the two :class:`~machdyn.loops.Motion` results is
compared: flags and reasons exactly, positions, points and rates to rounding
(relative to the pose's conditioning near toggles). The mechanisms are the seeded
random drawings of ``test_loops_branches`` (pin and slider dyads, rigid points,
Watt six-bars, change-point four-bars) on even, uneven and reversing sweeps
through assembly gaps, and models for each closed-form kind (two angles, an
angle and a slide, the angle and length of one vector, two inputs).
Independent references (closed forms, finite differences, forward
constructions) for the same models run on both paths in test_loops*.py.
"""

from __future__ import annotations

import numpy as np
import pytest

from machdyn import jit
from machdyn.loops import LoopSystem, _jit_sweep
from test_loops import watt_six_bar_with_slider
from test_loops_branches import (
    change_point_fourbar,
    cross,
    random_chain,
    random_watt,
    sweeps,
)

pytest.importorskip("numba", reason="numba is not installed on this Python")


@pytest.fixture(autouse=True)
def _restore_mode():
    previous = jit.mode()
    assert jit.load(), jit.reason()
    yield
    jit.set_mode(previous)


@pytest.fixture
def served(monkeypatch):
    """A list that records, per compiled-sweep attempt, whether the kernel served it."""
    calls: list[bool] = []
    original = _jit_sweep.sweep

    def spy(*args, **kwargs):
        out = original(*args, **kwargs)
        if jit.mode() != "off":
            calls.append(out is not None)
        return out

    monkeypatch.setattr(_jit_sweep, "sweep", spy)
    return calls


def both(s: LoopSystem, values: dict, guess: dict, **kw):
    """The same solve on the NumPy path and on the compiled kernels."""
    jit.set_mode("off")
    numpy_path = s.solve(values, guess, **kw)
    jit.set_mode("on")
    compiled = s.solve(values, guess, **kw)
    return numpy_path, compiled


def assert_same_motion(ref, got, scale: float, label: str = "", margin=None) -> None:
    """Every field of two Motions: flags exactly, numbers to rounding.

    ``margin``: per sample, the smallest |sin| of the angle between a dyad's two
    links (0 at a toggle or change point). There a rounding error e in the loop
    moves the pose by ~e/margin, its k-th rate by ~e/margin^(k+1): the tolerances
    grow so (two solvers that share no code agree to rounding *of the pose*).
    """
    n = ref.ok.shape
    m = np.clip(np.ones(n) if margin is None else np.nan_to_num(margin, nan=1.0), 1e-6, 1.0)
    assert got.groups == ref.groups and got.inputs == ref.inputs and got.angles == ref.angles
    assert (got.ok == ref.ok).all(), (label, np.flatnonzero(got.ok != ref.ok)[:5])
    assert (got.reason == ref.reason).all(), (label, set(got.reason) ^ set(ref.reason))
    assert (got.branch == ref.branch).all(), label
    assert (got.group_branch == ref.group_branch).all(), label
    assert (np.isnan(ref.residual) == np.isnan(got.residual)).all(), label
    assert np.nanmax(got.residual, initial=0.0) < 1e-13, label
    atol = 1e-12 * scale / m
    for name in ref.positions:  # the same whole turn of every angle, too
        assert unwrap_equal(ref.positions[name], got.positions[name], atol), (label, name)
    for name in ref.points:
        assert unwrap_equal(ref.points[name], got.points[name], atol), (label, name)
    for k, kind in enumerate(("velocity", "acceleration", "jerk"), start=2):
        a_all, b_all = getattr(ref, kind), getattr(got, kind)
        assert (a_all is None) == (b_all is None), (label, kind)
        if a_all is None:
            continue
        for table_a, table_b in (
            (a_all, b_all),
            (getattr(ref, f"point_{kind}"), getattr(got, f"point_{kind}")),
        ):
            for name in table_a:
                a, b = table_a[name], table_b[name]
                big = np.nanmax(np.abs(a), initial=1.0)
                assert unwrap_equal(a, b, 1e-12 * big / m**k), (label, kind, name)


def unwrap_equal(a: np.ndarray, b: np.ndarray, atol: np.ndarray) -> bool:
    """Equal to ``atol`` (per sample) where both are numbers, NaN at the same samples."""
    a, b = np.asarray(a), np.asarray(b)
    if not (np.isnan(a) == np.isnan(b)).all():
        return False
    finite = ~np.isnan(a)
    return bool((np.abs(a - b)[finite] <= atol[finite]).all())


def dyad_margin(m, *pairs) -> np.ndarray:
    """Smallest |sin(a - b)| over the dyads' link angles ``(a, b)`` (a number: a fixed one)."""
    out = np.ones(m.ok.shape)
    for a, b in pairs:
        angle_b = m[b] if isinstance(b, str) else b
        out = np.minimum(out, np.abs(np.sin(m[a] - angle_b)))
    return out


# ----------------------------------------------------------------------------- drawings
@pytest.mark.parametrize("seed", [0, 1, pytest.param(2, marks=pytest.mark.slow)])
def test_random_drawings_same_motion_on_both_paths(seed, served):
    """Random dyad chains (pins, sliders), Watt six-bars and change-point four-bars, each on
    an even two-turn sweep, an uneven one and one that goes there and back: the compiled
    kernel serves every sweep that starts well assembled, with the NumPy path's answer."""
    rng = np.random.default_rng(1010 + seed)
    compared = 0
    for i in range(12):
        drawing = (random_watt, random_chain, change_point_fourbar)[i % 3](rng)
        s, guess = drawing.loop_system()
        name = s._inputs[0]
        start = float(np.angle(drawing.points["A"] - drawing.points["O2"]))
        scale = max(abs(v) for v in drawing.points.values())
        for theta2 in sweeps(rng, start):
            served.clear()
            ref, got = both(s, {name: theta2}, guess, velocity={name: 2.0}, order=2)
            margins = drawing.margin(theta2)
            if served != [True]:  # the NumPy path took it: the first pose gave no branch
                assert not (margins[0] > 1e-2), (drawing, served)
                continue
            gap = np.zeros(theta2.shape, dtype=bool)  # where the drawing cannot be assembled
            for joint in drawing.forward(theta2).values():
                gap |= np.isnan(joint)
            near = ~gap & ~(margins > 1e-6)  # flags at a toggle to rounding may differ
            ref_ok, got_ok = ref.ok & ~near, got.ok & ~near
            assert (ref_ok == got_ok).all(), (seed, i, np.flatnonzero(ref_ok != got_ok)[:5])
            if near.any():
                continue
            assert_same_motion(ref, got, scale, f"seed {seed} mechanism {i}", margins)
            compared += 1
    assert compared >= 20


def test_issue_watt_six_bar_through_its_gaps(served):
    """Issue #17's Watt six-bar over two turns (gaps where it cannot be assembled)."""
    from test_loops_branches import Drawing

    p = {
        "O2": 0j,
        "O4": 1.556 - 0.241j,
        "A": 1.207 + 1.096j,
        "B": -0.472 - 1.807j,
        "C": -0.149 + 0.064j,
        "O6": 5.587 - 2.252j,
        "D": 3.466 - 0.775j,
    }
    steps = [("crank", "O2", "A"), ("rrr", "A", "O4", "B"), ("rigid", "O4", "B", "C")]
    drawing = Drawing(p, [*steps, ("rrr", "C", "O6", "D")])
    s, guess = drawing.loop_system()
    theta2 = float(np.angle(p["A"])) + np.linspace(0.0, 4 * np.pi, 843)
    ref, got = both(s, {"tO2A": theta2}, guess, velocity={"tO2A": 1.0})
    assert served == [True]
    assert_same_motion(ref, got, 6.0, "issue", drawing.margin(theta2))
    # and, independently: D on the drawn side of C–O6 at every ok sample, and NaN
    # (positions, points, every rate) at every sample that cannot be assembled
    side = np.sign(cross(p["O6"] - got.points["C"], got.points["D"] - got.points["C"]))
    assert (side[got.ok] == drawing.side("C", "O6", "D")).all()
    gap = ~got.ok
    assert gap.sum() > 100
    # the whole-turn rule past a gap (docs/loops.md): each angle's first value after the
    # gap lies within π of its last value before it
    there = np.flatnonzero(got.ok)
    after = there[1:][np.diff(there) > 1]
    before = there[:-1][np.diff(there) > 1]
    assert after.size >= 2
    for name in ("tAB", "tO4B", "tO4C", "tCD", "tO6D"):
        assert (np.abs(got[name][after] - got[name][before]) <= np.pi).all(), name
    for table in (got.positions, got.points, got.velocity, got.point_velocity):
        for key, arr in table.items():
            if key != "tO2A":
                assert np.isnan(arr[gap]).all(), key


# ----------------------------------------------------------------------------- each kind
def inverted_slider_crank() -> tuple[LoopSystem, dict]:
    """The angle and length of one vector (the slot O4→A): a e^{jθ2} − b e^{jθ4} − d = 0.

    (With an offset the slot's two vectors and their constraint make one general
    group, which the NumPy path solves.)
    """
    s = (
        LoopSystem()
        .vector("R1", 4.5, 0.0)
        .vector("R2", 2.0, "theta2")
        .vector("Rb", "b", "theta4")
        .loop("R2 - Rb - R1")
        .point("A", "R2")
        .inputs("theta2")
    )
    return s, {"theta4": 2.9, "b": 2.6}


def five_bar() -> tuple[LoopSystem, dict]:
    s = (
        LoopSystem()
        .vector("R1", 4.0, 0.0)
        .vector("R2", 2.0, "theta2")
        .vector("R3", 5.0, "theta3")
        .vector("R4", 5.0, "theta4")
        .vector("R5", 2.0, "theta5")
        .loop("R2 + R3 - R4 - R5 - R1")
        .point("P", "R2 + R3")
        .inputs("theta2", "theta5")
    )
    return s, {"theta3": 1.4, "theta4": 1.9}


def triple_rocker() -> tuple[LoopSystem, dict]:
    """4-3-3-2.5: assembles only for θ2 ≤ 102.6° (mod a turn): gaps in every turn."""
    s = (
        LoopSystem()
        .vector("R1", 4.0, 0.0)
        .vector("R2", 3.0, "theta2")
        .vector("R3", 3.0, "theta3")
        .vector("R4", 2.5, "theta4")
        .loop("R2 + R3 - R4 - R1")
        .point("B", "R2 + R3")
        .inputs("theta2")
    )
    return s, {"theta3": 0.2, "theta4": 1.5}


def slider_watt() -> tuple[LoopSystem, dict]:
    guess = {"theta3": 1.2, "theta4": 1.9, "theta4c": 2.2, "theta5": 0.4, "d6": 10.0}
    return watt_six_bar_with_slider(), guess


#: The dyads' two link angles (a number: a fixed direction), for their conditioning.
PAIRS = {
    "inverted_slider_crank": (),  # the slot never shrinks to zero (|O4A| >= 2.5)
    "triple_rocker": (("theta3", "theta4"),),
    "slider_watt": (("theta3", "theta4"), ("theta5", 0.0)),
}


@pytest.mark.parametrize("build", [inverted_slider_crank, triple_rocker, slider_watt])
@pytest.mark.parametrize("sweep", ["even", "uneven", "reversing", "jerk"])
def test_each_closed_form_kind_same_motion(build, sweep, served):
    s, guess = build()
    rng = np.random.default_rng(7)
    t = np.linspace(0.3, 0.3 + 4 * np.pi, 500)
    if sweep == "uneven":
        t = 0.3 + np.cumsum(rng.uniform(0.0, 1.0, 500) ** 3) * 4 * np.pi / 125
    elif sweep == "reversing":
        t = np.concatenate([t[:300], t[299::-1]])
    kw = {"velocity": {"theta2": 3.0}, "acceleration": {"theta2": -2.0}}
    if sweep == "jerk":
        kw["jerk"] = {"theta2": 5.0}
    else:
        kw["order"] = 2
    ref, got = both(s, {"theta2": t}, guess, **kw)
    assert served == [True]
    margin = dyad_margin(ref, *PAIRS[build.__name__])
    assert_same_motion(ref, got, 8.0, f"{build.__name__} {sweep}", margin)
    assert got.ok.any()


def test_two_inputs_same_motion(served):
    s, guess = five_bar()
    t = np.linspace(0, 2 * np.pi, 400)
    values = {"theta2": t, "theta5": np.pi / 2 + 0.6 * np.sin(t)}
    rates = {"theta2": 1.0, "theta5": 0.6 * np.cos(t)}
    ref, got = both(s, values, guess, velocity=rates)
    assert served == [True]
    assert got.ok.all()
    assert_same_motion(ref, got, 5.0, "five-bar", dyad_margin(ref, ("theta3", "theta4")))


def test_sweeps_the_kernel_leaves_to_numpy(served):
    """A sweep that starts where it cannot be assembled or at a toggle has no branch to keep
    at its first sample: the NumPy path takes it (and anchors it elsewhere)."""
    s, guess = triple_rocker()
    t = np.linspace(2.5, 2.5 + 2 * np.pi, 200)  # starts in the gap
    ref, got = both(s, {"theta2": t}, guess)
    assert served == [False]
    assert_same_motion(ref, got, 4.0, "gap first", dyad_margin(ref, ("theta3", "theta4")))
    # one sample: no sweep at all
    served.clear()
    both(s, {"theta2": [0.5]}, guess)
    assert served == []


def test_non_dyad_models_stay_on_numpy(served):
    """Groups the closed forms do not cover — three unknowns tied by two loop equations and a
    constraint (a general group), or a loop linear in two lengths — are solved by the
    NumPy continuation even with the kernels on."""
    geared = (
        LoopSystem()
        .vector("R1", 4.0, 0.0)
        .vector("R2", 1.0, "theta2")
        .vector("R3", 3.0, "theta3")
        .vector("R4", 3.0, "theta4")
        .vector("R5", 1.5, "theta5")
        .loop("R2 + R3 - R4 - R5 - R1")
        .constraint("theta3 - theta5 = c", c=-0.6)
        .inputs("theta2")
    )
    guess = {"theta3": 1.0, "theta4": 2.0, "theta5": 1.6}
    ref, got = both(geared, {"theta2": np.linspace(0, 1, 50)}, guess)
    assert served == [False] and got.ok.all()
    assert_same_motion(ref, got, 4.0, "general group")
    yoke = (
        LoopSystem()
        .vector("R2", 1.0, "theta2")
        .vector("X", "x", 0.0)
        .vector("Y", "y", np.pi / 2)
        .loop("R2 - X - Y")
        .inputs("theta2")
    )
    served.clear()
    ref, got = both(yoke, {"theta2": np.linspace(0, 1, 50)}, {"x": 1.0, "y": 0.0})
    assert served == [False] and got.ok.all()
    assert_same_motion(ref, got, 1.0, "linear group")


def test_gear_on_an_unknown_angle_stays_on_numpy_and_keeps_its_ratio(served):
    """A gear on the rocker (2 θ4 + θ6 = 0) of a triple rocker with gaps: θ6's pose depends
    on θ4's whole turns, which the kernel's closed forms do not carry, so NumPy solves it;
    past every gap the ratio still holds exactly (no whole turn added to θ4 alone)."""
    s, guess = triple_rocker()
    s.vector("R6", 1.0, "theta6").constraint("2*theta4 + theta6 = c", c=0.0)
    s.point("P", "R1 + R6")
    t = np.linspace(0.3, 0.3 + 4 * np.pi, 500)
    ref, got = both(s, {"theta2": t}, guess | {"theta6": -3.0})
    assert served == [False]
    assert (~got.ok).sum() > 100 and got.ok.sum() > 100
    assert_same_motion(ref, got, 4.0, "gear", dyad_margin(ref, ("theta3", "theta4")))
    ratio = 2 * got["theta4"] + got["theta6"]
    assert np.nanmax(np.abs(ratio)) < 1e-12
    # P = O4 + e^{jθ6} with θ6 = -2 θ4, from the solved θ4 (an independent evaluation)
    p_ref = 4.0 + np.exp(-2j * got["theta4"])
    np.testing.assert_allclose(got.points["P"][got.ok], p_ref[got.ok], atol=1e-12)


@pytest.mark.parametrize("build", [triple_rocker, slider_watt])
def test_sweeps_longer_than_a_chunk(build, served):
    """The kernel works in chunks of samples: a sweep over three of them (the last one
    partial), through gaps and whole turns, equals the NumPy path everywhere."""
    from machdyn.loops import _kernels

    s, guess = build()
    n = 2 * _kernels.CHUNK + 77
    t = np.linspace(0.3, 0.3 + 6 * np.pi, n)
    ref, got = both(s, {"theta2": t}, guess, velocity={"theta2": 3.0}, jerk={"theta2": 1.0})
    assert served == [True]
    margin = dyad_margin(ref, *PAIRS[build.__name__])
    assert_same_motion(ref, got, 8.0, f"{build.__name__} long", margin)
    assert got.ok[_kernels.CHUNK :].any()
