"""Cam programs: closing the turn, svaj sampling, time units, continuity check."""

import numpy as np
import pytest

from machdyn import InputError
from machdyn.cams import CamProgram, Segment, polynomial_law

deg = np.radians


def double_dwell(law, h=1.0):
    return CamProgram(
        [
            Segment("rise", deg(60), h, law),
            Segment("dwell", deg(120)),
            Segment("fall", deg(60), h, law),
            Segment("dwell", deg(120)),
        ]
    )


@pytest.mark.parametrize("law", ["cycloidal", "modified_sine", "4-5-6-7", "modified_trapezoid"])
def test_continuity_passes_finite_jerk_double_dwells(law):
    report = double_dwell(law).continuity()
    assert report.ok
    assert report.finite_jerk
    assert report.discontinuities == ()


def test_continuity_flags_constant_velocity_double_dwell():
    report = double_dwell("constant_velocity").continuity()
    assert not report.ok
    # v jumps by ±h/β at the four boundaries 0°, 60°, 180°, 240°.
    v_jumps = [d for d in report.discontinuities if d.quantity == "v"]
    assert sorted(round(np.degrees(d.theta)) for d in v_jumps) == [0, 60, 180, 240]
    h_over_beta = 1.0 / deg(60)
    assert sorted(abs(d.jump) for d in v_jumps) == pytest.approx([h_over_beta] * 4)
    assert any("constant velocity" in note for note in report.notes)


def test_continuity_flags_simple_harmonic_double_dwell():
    report = double_dwell("simple_harmonic").continuity()
    assert not report.ok
    a_jumps = [d for d in report.discontinuities if d.quantity == "a"]
    assert len(a_jumps) == 4
    assert {d.quantity for d in report.discontinuities} == {"a"}
    # SHM starts with a = π²h/(2β²) (Norton eq. 8.5), so each jump has that size.
    expected = np.pi**2 / (2 * deg(60) ** 2)
    assert [abs(d.jump) for d in a_jumps] == pytest.approx([expected] * 4)
    assert "FAILS" in report.lines()[0]


def test_continuity_flags_jump_inside_constant_acceleration():
    report = double_dwell("constant_acceleration").continuity()
    inside = [d for d in report.discontinuities if "inside" in d.where]
    assert sorted(round(np.degrees(d.theta)) for d in inside) == [30, 210]
    assert all(abs(d.jump) == pytest.approx(8 / deg(60) ** 2, rel=1e-6) for d in inside)


def test_program_that_does_not_return_is_rejected():
    # Review finding 4: rises 1.0, falls 0.6 leave the follower 0.4 above its
    # start at 360°, a step in the cam outline. A cam is periodic, so refuse it.
    segments = [
        Segment("rise", deg(90), 1.0, "cycloidal"),
        Segment("dwell", deg(90)),
        Segment("fall", deg(90), 0.6, "cycloidal"),
        Segment("dwell", deg(90)),
    ]
    with pytest.raises(InputError) as info:
        CamProgram(segments)
    assert info.value.field == "segments"
    message = str(info.value)
    assert "rises total 1" in message
    assert "falls total 0.6" in message
    assert "net rise +0.4" in message
    assert "return to its start" in message


def test_program_falling_below_its_start_is_rejected():
    # The reviewer's case: rise 1 then fall 2 dips the follower 1 below the prime circle.
    with pytest.raises(InputError, match=r"net rise -1\b"):
        CamProgram(
            [
                Segment("rise", deg(60), 1.0, "cycloidal"),
                Segment("fall", deg(60), 2.0, "cycloidal"),
                Segment("dwell", deg(240)),
            ]
        )


def test_program_that_starts_above_its_lowest_point_is_rejected():
    # s is measured from the prime circle: a fall first would put the pitch curve
    # inside the prime circle the cam reports. Listing the same motion from its
    # low dwell (segment 3) is accepted.
    segments = [
        Segment("fall", deg(90), 1.0, "cycloidal"),
        Segment("dwell", deg(90)),
        Segment("rise", deg(90), 1.0, "cycloidal"),
        Segment("dwell", deg(90)),
    ]
    with pytest.raises(InputError, match="starting with segment 2") as info:
        CamProgram(segments)
    assert info.value.field == "segments"
    assert "θ = 90°" in str(info.value)
    program = CamProgram(segments[1:] + segments[:1])
    assert program.sample(360).s.min() >= 0.0


def test_program_closing_within_rounding_is_accepted():
    # 0.1 + 0.2 != 0.3 in binary floating point; that is not a step in the cam.
    program = CamProgram(
        [
            Segment("rise", deg(60), 0.1, "cycloidal"),
            Segment("rise", deg(60), 0.2, "cycloidal"),
            Segment("fall", deg(60), 0.3, "cycloidal"),
            Segment("dwell", deg(180)),
        ]
    )
    assert abs(program.levels[-1]) < 1e-12
    assert program.continuity().ok


def test_single_dwell_rise_fall_with_cycloids_is_continuous():
    program = CamProgram(
        [
            Segment("rise", deg(90), 1.0, "cycloidal"),
            Segment("fall", deg(90), 1.0, "cycloidal"),
            Segment("dwell", deg(180)),
        ]
    )
    assert program.continuity().ok


def test_polynomial_single_dwell_segments_join_smoothly():
    # Norton §8.4 style single dwell: rise and fall meet at the top with v = 0 and
    # the same negative acceleration, so a is continuous there.
    beta = deg(90)
    up = polynomial_law(start={"v": 0, "a": 0}, end={"v": 0, "a": -3.0})
    down = polynomial_law(start={"v": 0, "a": -3.0}, end={"v": 0, "a": 0})
    program = CamProgram(
        [
            Segment("rise", beta, 1.0, up),
            Segment("fall", beta, 1.0, down),
            Segment("dwell", deg(180)),
        ]
    )
    assert program.continuity().ok
    top = program.svaj(np.array([beta - 1e-9, beta]))
    np.testing.assert_allclose(top.a, [-3.0, -3.0], atol=1e-6)
    # The same rise with a = 0 at the top would not meet this fall.
    flat = polynomial_law(start={"v": 0, "a": 0}, end={"v": 0, "a": 0})
    broken = CamProgram(
        [
            Segment("rise", beta, 1.0, flat),
            Segment("fall", beta, 1.0, down),
            Segment("dwell", deg(180)),
        ]
    )
    [jump] = broken.continuity().discontinuities
    assert (jump.quantity, jump.jump) == ("a", pytest.approx(-3.0))


def test_svaj_values_at_known_angles():
    program = double_dwell("cycloidal", h=2.0)
    m = program.svaj(deg(np.array([0.0, 30.0, 60.0, 120.0, 210.0, 300.0, 390.0, -60.0])))
    # Cycloidal mid-rise: s = h/2, v = 2h/β; high dwell s = h; low dwell s = 0.
    np.testing.assert_allclose(m.s, [0, 1, 2, 2, 1, 0, 1, 0], atol=1e-12)
    assert m.v[1] == pytest.approx(2 * 2.0 / deg(60))
    assert m.v[4] == pytest.approx(-2 * 2.0 / deg(60))
    assert m.theta[6] == pytest.approx(deg(30))


def test_motion_in_time_units_matches_time_derivative():
    program = double_dwell("modified_sine", h=0.05)
    omega = 2 * np.pi * 100 / 60  # 100 rpm
    dt = 1e-6
    t = np.linspace(0.01, 0.59, 50)
    timed = program.svaj(omega * t).in_time(omega)
    s_plus = program.svaj(omega * (t + dt)).s
    s_minus = program.svaj(omega * (t - dt)).s
    np.testing.assert_allclose((s_plus - s_minus) / (2 * dt), timed.V, atol=1e-6)
    plain = program.svaj(omega * t)
    np.testing.assert_allclose(timed.A, omega**2 * plain.a)
    np.testing.assert_allclose(timed.J, omega**3 * plain.j)
    np.testing.assert_allclose(timed.t, t)


def test_sample_and_pandas():
    m = double_dwell("cycloidal").sample(360)
    assert m.theta.size == 360
    assert m.theta[1] == pytest.approx(deg(1))
    frame = m.to_pandas()
    assert list(frame.columns) == ["theta", "theta_deg", "s", "v", "a", "j"]
    assert frame.theta_deg.iloc[90] == pytest.approx(90.0)
    timed = m.in_time(10.0).to_pandas()
    # Review finding 12: theta in radians as well as degrees, as Motion has.
    assert list(timed.columns) == ["t", "theta", "theta_deg", "s", "V", "A", "J"]
    np.testing.assert_allclose(np.radians(timed["theta_deg"]), timed["theta"])


def test_double_dwell_constructor():
    program = CamProgram.double_dwell(1.0, deg(60), deg(90), law="4-5-6-7", dwell_high=deg(30))
    assert [np.degrees(s.beta) for s in program.segments] == pytest.approx([60, 30, 90, 180])
    assert "rise:poly4567" in repr(program)
    with pytest.raises(InputError, match="no room"):
        CamProgram.double_dwell(1.0, deg(200), deg(160))


@pytest.mark.parametrize(
    ("segments", "field", "match"),
    [
        (lambda: [Segment("rise", deg(60), 1.0, "cycloidal")], "segments", "sum to 360"),
        (lambda: [], "segments", "at least one"),
        (lambda: ["rise"], "segments[0]", "Segment"),
        (lambda: [Segment("rise", -1.0, 1.0, "cycloidal")], "beta", "positive"),
        (lambda: [Segment("rise", 1.0, -1.0, "cycloidal")], "h", "zero or positive"),
        (lambda: [Segment("rise", 1.0, 0.0, "cycloidal")], "h", "positive lift"),
        (lambda: [Segment("lift", 1.0, 1.0, "cycloidal")], "motion", "rise, fall, dwell"),
        (lambda: [Segment("rise", 1.0, 1.0, "dwell")], "law", "moving law"),
        (lambda: [Segment("rise", 1.0, 1.0, "bogus")], "law", "valid: dwell"),
    ],
)
def test_bad_programs(segments, field, match):
    with pytest.raises(InputError, match=match) as info:
        CamProgram(segments())
    assert info.value.field == field


def test_degrees_typed_by_hand_close_the_turn():
    # 3 × 120° in radians rounded to 9 digits is accepted and closed exactly.
    beta = round(2 * np.pi / 3, 9)
    program = CamProgram(
        [
            Segment("rise", beta, 1.0, "cycloidal"),
            Segment("fall", beta, 1.0, "cycloidal"),
            Segment("dwell", beta),
        ]
    )
    assert program.starts[-1] == pytest.approx(4 * np.pi / 3, abs=1e-12)


def test_pint_angles_and_speed_are_converted_at_the_boundary():
    pint = pytest.importorskip("pint")
    ureg = pint.UnitRegistry()
    seg = Segment("rise", 60 * ureg.degree, 1.0, "cycloidal")
    assert seg.beta == pytest.approx(np.pi / 3)
    timed = double_dwell("cycloidal").sample(36).in_time(100 * ureg.rpm)
    assert timed.omega == pytest.approx(2 * np.pi * 100 / 60)
    with pytest.raises(InputError, match="cannot be expressed in radian"):
        Segment("rise", 60 * ureg.meter, 1.0, "cycloidal")
