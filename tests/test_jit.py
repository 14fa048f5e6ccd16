"""The compiled (numba) four-bar kernels and the rule that chooses them (machdyn.jit).

The kernels' own elementary functions are checked against NumPy's libm, and
their results sample by sample against the NumPy path. (test_fourbar.py and
test_closed_forms_vs_loops.py also run whole on the compiled kernels: loop
closure, finite differences, Kennedy's rule, the notes' worked examples and the
general vector-loop solver.)
"""

from __future__ import annotations

import os
import signal
import time
import warnings

import numpy as np
import pytest

from machdyn import FourBar, InputError, jit
from machdyn.classify import is_assemblable
from machdyn.fourbar import STATUS_REASONS, positions

kernels = pytest.importorskip("machdyn._kernels")

QUANTITIES = (
    "theta3",
    "theta4",
    "omega3",
    "omega4",
    "alpha3",
    "alpha4",
    "jerk3",
    "jerk4",
    "A",
    "B",
    "coupler",
    "coupler_velocity",
    "coupler_acceleration",
    "coupler_jerk",
)


@pytest.fixture(autouse=True)
def _restore_jit_state(monkeypatch):
    """Each test may switch modes or fake a failure; the rest of the suite runs 'off'."""
    assert jit.load(), jit.reason()
    monkeypatch.setattr(jit, "_spent", 0.0)
    yield
    jit.set_mode("off")


def both_paths(call):
    """``call()`` on the NumPy kernels and on the compiled ones."""
    jit.set_mode("off")
    reference = call()
    jit.set_mode("on")
    compiled = call()
    return reference, compiled


def ulp_error(value, reference):
    return np.abs(value - reference) / np.spacing(np.abs(reference))


# --------------------------------------------------------------------------------------
# Elementary functions


@pytest.mark.parametrize("limit", [1.0, 10.0, 1e3, kernels.SINCOS_LIMIT])
def test_sincos_is_within_two_ulp_of_libm(rng, limit):
    x = rng.uniform(-limit, limit, 200_000)
    sin, cos = np.empty_like(x), np.empty_like(x)
    kernels.sincos_into(x, sin, cos)
    assert ulp_error(sin, np.sin(x)).max() <= 2.0
    assert ulp_error(cos, np.cos(x)).max() <= 2.0


def test_sincos_near_its_zeros_and_quadrant_boundaries():
    # where sin or cos is tiny, the reduction x − qπ/2 must keep its relative accuracy
    q = np.arange(-20_000, 20_000, dtype=float)
    x = np.concatenate([q * np.pi / 2, q * np.pi / 2 + 1e-9, q * np.pi / 4, np.nextafter(q, 1e9)])
    sin, cos = np.empty_like(x), np.empty_like(x)
    kernels.sincos_into(x, sin, cos)
    assert ulp_error(sin, np.sin(x)).max() <= 2.0
    assert ulp_error(cos, np.cos(x)).max() <= 2.0


def test_angle_is_atan2_in_zero_to_two_pi(rng):
    theta = rng.uniform(-np.pi, np.pi, 400_000)
    radius = np.exp(rng.uniform(-30, 30, theta.size))
    y, x = radius * np.sin(theta), radius * np.cos(theta)
    out = np.empty_like(x)
    kernels.angle_into(y, x, out)
    reference = np.arctan2(y, x) % (2 * np.pi)
    error = np.abs(out - reference)
    error = np.minimum(error, 2 * np.pi - error)  # 0 and 2π are the same angle
    assert error.max() <= np.spacing(2 * np.pi)
    assert ((out >= 0.0) & (out < 2 * np.pi)).all()


def test_angle_of_the_axes_and_of_nan():
    y = np.array([0.0, 1.0, 0.0, -1.0, -1e-300, 1.0, np.nan])
    x = np.array([1.0, 0.0, -1.0, 0.0, 1.0, np.nan, 1.0])
    out = np.empty_like(x)
    kernels.angle_into(y, x, out)
    np.testing.assert_array_equal(out[:5], [0.0, np.pi / 2, np.pi, 3 * np.pi / 2, 0.0])
    assert np.isnan(out[5:]).all()


# --------------------------------------------------------------------------------------
# The kernels against the NumPy path


def random_linkages(rng, count):
    """Random lengths over three decades, assemblable somewhere, with a coupler point."""
    found = []
    while len(found) < count:
        lengths = np.exp(rng.uniform(-3.0, 3.0, 4))
        if is_assemblable(*lengths):
            found.append((tuple(lengths), (rng.uniform(0.1, 3.0) * lengths[2], rng.normal())))
    return found


@pytest.mark.parametrize("form", [1, 2])
def test_solve_matches_the_numpy_path_sample_by_sample(rng, form):
    theta2 = np.linspace(-2 * np.pi, 2 * np.pi, 2_001)  # through toggles and dead zones
    for lengths, coupler in random_linkages(rng, 40):
        fb = FourBar(*lengths, coupler=coupler)
        reference, compiled = both_paths(
            lambda fb=fb: fb.solve(theta2, 3.0, -2.0, form=form, jerk2=5.0)
        )
        np.testing.assert_array_equal(compiled.status, reference.status)
        # The two paths round differently (the kernels' sin/cos are within 2 ulp of libm's).
        # How far that moves the answer is the problem's condition: θ3 = arg((d + c e4 − A)/b)
        # magnifies absolute errors by longest/shortest link and 1/|sin(θ3 − θ4)| (κ), and
        # the rates divide by sin(θ3 − θ4) once more (κ²). Compare to that, away from toggles.
        s34 = np.abs(np.sin(reference.theta3 - reference.theta4))
        kappa = max(lengths) / min(lengths) / s34
        good_pose = s34 > 1e-2
        for name in QUANTITIES:
            got, want = getattr(compiled, name), getattr(reference, name)
            np.testing.assert_array_equal(np.isnan(got), np.isnan(want), err_msg=name)
            good = ~np.isnan(want) & good_pose
            diff = np.abs(got[good] - want[good])
            if name.startswith("theta"):  # 0 and 2π are the same angle
                diff, bound = np.minimum(diff, 2 * np.pi - diff), kappa[good]
            elif name in "AB" or name == "coupler":
                bound = kappa[good] * np.max(np.abs(want[good]), initial=1.0)
            else:
                bound = kappa[good] ** 2 * np.max(np.abs(want[good]), initial=1.0)
            np.testing.assert_array_less(diff, 1e-14 * bound, err_msg=name)
        angles = ~np.isnan(reference.theta3)  # everywhere: within the conditioning
        diff = np.abs(compiled.theta3[angles] - reference.theta3[angles])
        np.testing.assert_array_less(np.minimum(diff, 2 * np.pi - diff), 1e-6)


@pytest.mark.parametrize("order", [0, 1, 2, 3])
@pytest.mark.parametrize("coupler", [None, (5.0, 0.5)])
def test_every_order_and_coupler_variant(order, coupler):
    fb = FourBar(8, 4, 7, 6, coupler=coupler)
    theta2 = np.linspace(0, 2 * np.pi, 721)
    reference, compiled = both_paths(lambda: fb.solve(theta2, 10.0, 1.0, order=order))
    for name in QUANTITIES:
        got, want = getattr(compiled, name), getattr(reference, name)
        assert (got is None) == (want is None), name
        if want is not None:
            np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12 * np.abs(want).max())


def test_grcr_forms_and_flags_match():
    # GRCR: the form is the side of the ground line; samples of the other side are flagged
    fb = FourBar(6, 9, 3, 8)
    theta2 = np.linspace(-np.pi, np.pi, 1_001)
    for form in (1, 2):
        reference, compiled = both_paths(lambda form=form: fb.solve(theta2, 1.0, form=form))
        np.testing.assert_array_equal(compiled.status, reference.status)
        assert set(np.unique(compiled.status)) >= {0, 3}
        assert compiled.reason[compiled.status == 3][0] == STATUS_REASONS[3]


def test_positions_match_on_threads_and_beyond_the_kernels_range():
    theta2 = np.linspace(-40.0, 40.0, 300_001)  # above MIN_PARALLEL: split across threads
    theta2[::1000] = kernels.SINCOS_LIMIT * 3.0  # beyond sincos's range: NumPy does it
    (t3, t4, ok), (c3, c4, cok) = both_paths(lambda: positions(8, 4, 7, 6, theta2, -1))
    np.testing.assert_array_equal(cok, ok)
    np.testing.assert_allclose(c3, t3, atol=1e-13)
    np.testing.assert_allclose(c4, t4, atol=1e-13)
    small = theta2[theta2 < 100.0]
    (t3, t4, ok), (c3, c4, cok) = both_paths(lambda: positions(8, 4, 7, 6, small))
    np.testing.assert_array_equal(cok, ok)
    np.testing.assert_allclose(c3, t3, atol=1e-13)


def test_positions_checks_its_arguments_on_both_paths():
    for mode in ("off", "on"):
        jit.set_mode(mode)
        with pytest.raises(InputError, match="branch: must be one of 1, -1; got 0"):
            positions(8, 4, 7, 6, [0.5, 1.0], branch=0)
        with pytest.raises(InputError, match="r1"):
            positions(0, 0, 0, 0, [0.5])
        with pytest.raises(InputError, match="r3"):
            positions(8, 4, np.array([7.0, 8.0]), 6, [0.5])


def test_unusual_input_arrays_give_the_same_answer_on_both_paths():
    theta2 = np.linspace(0, 2 * np.pi, 64)
    read_only = theta2.copy()
    read_only.flags.writeable = False
    for given in (read_only, theta2[::2], theta2.astype(">f8"), theta2.astype(np.float32)):
        (t3, t4, ok), (c3, c4, cok) = both_paths(lambda g=given: positions(8, 4, 7, 6, g))
        np.testing.assert_array_equal(cok, ok)
        np.testing.assert_allclose(c3, t3, atol=1e-13)
        np.testing.assert_allclose(c4, t4, atol=1e-13)


def test_zero_angle_is_plus_zero_on_both_paths():
    # FourBar(2, 1, 2, 1), form 2, at θ2 = 0: the links fold onto the ground line
    (t3, t4, _), (c3, c4, _) = both_paths(lambda: positions(2, 1, 2, 1, [0.0], -1))
    for value in (t3[0], t4[0], c3[0], c4[0]):
        assert value == 0.0 and np.copysign(1.0, value) == 1.0


def test_a_failing_kernel_switches_to_numpy_with_one_warning(monkeypatch):
    monkeypatch.setattr(jit, "_failure", "")

    def broken(*args):
        raise ZeroDivisionError("simulated")

    monkeypatch.setattr(kernels, "SOLVERS", (broken,) * 4)
    jit.set_mode("on")
    theta2 = np.linspace(0, 6, 100)
    with pytest.warns(RuntimeWarning, match="kernel failed .ZeroDivisionError: simulated") as seen:
        m = FourBar(8, 4, 7, 6).solve(theta2, 2.0)
    assert seen[0].filename == __file__  # attributed to the caller, not to machdyn
    assert not jit.active() and "simulated" in jit.reason()
    jit.set_mode("off")
    np.testing.assert_array_equal(FourBar(8, 4, 7, 6).solve(theta2, 2.0).omega4, m.omega4)
    monkeypatch.setattr(jit, "_kernels", kernels)  # for the other tests


@pytest.mark.skipif(not hasattr(os, "fork"), reason="needs os.fork")
def test_a_forked_child_can_solve_after_the_parent_used_threads():
    jit.set_mode("on")
    theta2 = np.linspace(0, 6, 200_000)  # above MIN_PARALLEL: the parent's thread pool
    expected = FourBar(8, 4, 7, 6).solve(theta2, 1.0).omega4
    pid = os.fork()
    if pid == 0:  # child: must not wait forever on the parent's (absent) threads
        try:
            got = FourBar(8, 4, 7, 6).solve(theta2, 1.0).omega4
            os._exit(0 if np.array_equal(got, expected, equal_nan=True) else 1)
        finally:
            os._exit(2)
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        done, status = os.waitpid(pid, os.WNOHANG)
        if done:
            assert os.waitstatus_to_exitcode(status) == 0
            return
        time.sleep(0.05)
    os.kill(pid, signal.SIGKILL)
    os.waitpid(pid, 0)
    pytest.fail("the forked child hung")


def test_solve_beyond_the_kernels_range_falls_back_to_numpy():
    theta2 = np.array([0.3, 2e7 + 0.3])  # radians on purpose: the degrees hint is expected
    with pytest.warns(UserWarning, match="did you pass degrees"):
        reference, compiled = both_paths(lambda: FourBar(8, 4, 7, 6).solve(theta2, 2.0))
    np.testing.assert_allclose(compiled.theta3, reference.theta3, atol=1e-9)
    np.testing.assert_allclose(compiled.omega4, reference.omega4, atol=1e-9)


def test_coupler_points_of_many_candidates_match_the_numpy_path(rng):
    from machdyn.synthesis.atlas import coupler_points

    n = 2_000
    lengths = np.exp(rng.uniform(-1.5, 1.5, (4, n)))  # many cannot assemble everywhere
    p, delta = rng.uniform(0.1, 3.0, n), rng.normal(size=n)
    branch = np.where(rng.random(n) < 0.5, 1, -1)
    theta2 = np.linspace(0, 2 * np.pi, 90, endpoint=False)
    (ref, ref_ok), (got, got_ok) = both_paths(
        lambda: coupler_points(*lengths, p, delta, theta2, branch)
    )
    np.testing.assert_array_equal(got_ok, ref_ok)
    assert 0.05 < ref_ok.mean() < 0.95  # both kinds of sample are exercised
    np.testing.assert_array_equal(np.isnan(got), np.isnan(ref))
    scale = lengths.max(axis=0)[:, None] + p[:, None]
    np.testing.assert_array_less(
        np.abs(got - ref)[ref_ok], 1e-13 * np.broadcast_to(scale, ref.shape)[ref_ok]
    )


# --------------------------------------------------------------------------------------
# The rule that chooses the path


def test_mode_comes_from_the_environment(monkeypatch):
    jit.set_mode(None)
    for value, expected in [("on", "on"), ("1", "on"), ("OFF", "off"), ("", "auto")]:
        monkeypatch.setenv("MACHDYN_JIT", value)
        assert jit.mode() == expected
    monkeypatch.setenv("MACHDYN_JIT", "of")
    with pytest.warns(RuntimeWarning, match="MACHDYN_JIT='of' is not one of auto, on, off"):
        assert jit.mode() == "auto"


def test_set_mode_names_the_choices():
    with pytest.raises(InputError, match="mode: must be one of auto, on, off; got 'fast'"):
        jit.set_mode("fast")


def test_auto_switches_after_the_numpy_kernels_spent_the_budget(monkeypatch):
    monkeypatch.setattr(jit, "_kernels", None)  # as in a new process
    monkeypatch.setattr(jit, "BUDGET", 1e-3)
    jit.set_mode("auto")
    assert jit.kernels(10) is None  # nothing spent yet: NumPy
    FourBar(8, 4, 7, 6).solve(np.linspace(0, 6, 50_000))  # well over a millisecond
    assert jit.kernels(10) is kernels
    jit.set_mode("off")
    assert jit.kernels(10) is None and not jit.active()


def test_auto_counts_the_call_about_to_be_made(monkeypatch):
    # one call big enough to cost the budget in NumPy loads the kernels before it runs
    monkeypatch.setattr(jit, "_kernels", None)
    jit.set_mode("auto")
    big = int(jit.BUDGET / jit.NUMPY_SECONDS_PER_POSE)
    assert jit.kernels(big // 2) is None
    assert jit.kernels(big) is kernels


def test_a_failed_load_leaves_numpy_in_charge_and_says_why(monkeypatch):
    monkeypatch.setattr(jit, "_kernels", None)
    monkeypatch.setattr(jit, "_failure", "")

    def broken():
        raise ImportError("no numba here")

    monkeypatch.setattr(kernels, "warm_up", broken)
    jit.set_mode("on")
    with pytest.warns(RuntimeWarning, match=r"unavailable \(ImportError: no numba here\)"):
        first = FourBar(8, 4, 7, 6).solve(0.5, 1.0)
    assert jit.reason() == "ImportError: no numba here"
    assert not jit.active()
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # said once, not at every call
        second = FourBar(8, 4, 7, 6).solve(0.5, 1.0)
        assert jit.load() is False  # and not retried
    for m in (first, second):  # NumPy served both: the loop closes
        loop = 4 * np.exp(0.5j) + 7 * np.exp(1j * m.theta3) - 6 * np.exp(1j * m.theta4) - 8
        assert abs(loop) < 1e-13


def test_auto_keeps_to_the_documented_bound_across_its_switch_and_on_off_repeat_bits(
    monkeypatch,
):
    """The same call in one process: NumPy before the switch, compiled after it.

    The bits may change at the switch (documented in machdyn.jit); they stay within
    the conditioning bound, and a fixed path (on or off) repeats them exactly.
    """
    fb = FourBar(8, 4, 7, 6, coupler=(3.0, 0.5))
    theta2 = np.linspace(0, 2 * np.pi, 3_601)

    def call():
        return fb.solve(theta2, 10.0, -3.0, jerk2=2.0)

    monkeypatch.setattr(jit, "_kernels", None)  # as in a new process
    monkeypatch.setattr(jit, "_spent", 0.0)
    monkeypatch.setattr(jit, "BUDGET", 1e-4)
    jit.set_mode("auto")
    before = call()  # NumPy: nothing spent yet
    assert jit.kernels(1) is not None  # that call spent the budget
    after = call()  # compiled
    s34 = np.abs(np.sin(before.theta3 - before.theta4))
    kappa = 8 / 4 / s34
    for name in ("theta3", "theta4", "A", "B", "coupler"):
        diff = np.abs(getattr(after, name) - getattr(before, name))
        if name.startswith("theta"):
            diff = np.minimum(diff, 2 * np.pi - diff)
            scale = 1.0
        else:
            scale = np.abs(getattr(before, name)).max()
        assert np.all(diff <= 1e-14 * kappa * scale), name
    for name in ("omega3", "omega4", "alpha3", "alpha4", "jerk3", "jerk4"):
        diff = np.abs(getattr(after, name) - getattr(before, name))
        assert np.all(diff <= 1e-14 * kappa**2 * np.abs(getattr(before, name)).max()), name
    for mode in ("off", "on"):
        jit.set_mode(mode)
        first, second = call(), call()
        for name in QUANTITIES:
            np.testing.assert_array_equal(getattr(first, name), getattr(second, name))
