"""Round trips (hypothesis) and unit systems for cams, gears, flywheels, rotors, synthesis."""

from __future__ import annotations

import math
import tomllib

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from machdyn import cams, gears
from machdyn.errors import MachdynError
from machdyn.spec import SpecError, dumps, from_spec, read
from machdyn.spec._cam import Cam
from machdyn.spec._synthesis import FunctionTask, MotionTask, PathTask
from machdyn.spec._tasks import FlywheelSizing, RotorBalance
from machdyn.units import UnitSystem

RPM = 2 * math.pi / 60
SYSTEMS = st.sampled_from(
    [None, UnitSystem(length="mm"), UnitSystem(length="in", force="lbf", angle="rad")]
)


def back(model, name="x"):
    """The model read back from its spec written as TOML text."""
    return from_spec(tomllib.loads(dumps(model.to_spec(name))))


# ------------------------------------------------------------------ round trips
@given(
    np_=st.integers(12, 40),
    ng=st.integers(41, 90),
    size=st.sampled_from([("module", 2.5), ("diametral_pitch", 8.0), ("module", 0.7)]),
    phi=st.sampled_from([14.5, 20.0, 25.0]),
    shift=st.floats(-0.3, 0.3),
)
def test_gear_pairs_round_trip(np_, ng, size, phi, shift):
    try:
        pair = gears.GearPair(
            gears.Gear(
                np_, **{size[0]: size[1]}, pressure_angle=math.radians(phi), profile_shift=shift
            ),
            gears.Gear(ng, **{size[0]: size[1]}, pressure_angle=math.radians(phi)),
        )
    except MachdynError:
        return
    again = back(pair)
    assert again.pinion == pair.pinion and again.gear == pair.gear
    assert again.center_distance == pair.center_distance


@given(stages=st.lists(st.tuples(st.integers(10, 80), st.integers(10, 80)), min_size=1, max_size=4))
def test_gear_trains_round_trip(stages):
    train = gears.GearTrain(stages)
    assert back(train).stages == train.stages
    planet = gears.PlanetaryTrain.simple(40, 20, 80)
    assert back(planet).chain == planet.chain


LAWS = st.sampled_from(["cycloidal", "simple_harmonic", "poly345", "modified_sine", "scca"])


@given(
    law=LAWS,
    h=st.floats(0.1, 5.0),
    rise=st.floats(30.0, 120.0),
    fall=st.floats(30.0, 120.0),
    follower=st.sampled_from(["roller", "flat", "program"]),
    system=SYSTEMS,
)
def test_cams_round_trip(law, h, rise, fall, follower, system):
    params = {"b": 0.25, "c": 0.5, "d": 0.25} if law == "scca" else {}
    try:
        program = cams.CamProgram.double_dwell(
            h, math.radians(rise), math.radians(fall), cams.get_law(law, **params)
        )
    except MachdynError:
        return
    model = {
        "roller": Cam(program, cams.TranslatingRoller(4 * h + 3, 0.5, 0.2)),
        "flat": Cam(program, cams.TranslatingFlatFace(4 * h + 3)),
        "program": program,
    }[follower]
    object.__setattr__(model, "units", system)
    again = back(model)
    got = again.program if isinstance(again, Cam) else again
    assert [(s.motion, s.beta, s.h, s.law.name) for s in got.segments] == [
        (s.motion, s.beta, s.h, s.law.name) for s in program.segments
    ]
    if isinstance(model, Cam):
        assert again.follower == model.follower


def test_an_oscillating_cam_and_lone_followers_round_trip():
    program = cams.CamProgram.double_dwell(math.radians(20), math.radians(90), math.radians(90))
    arm = cams.OscillatingRoller(2.0, 0.3, pivot_distance=4.0, arm_length=3.5, pivot_side="left")
    cam = Cam(program, arm)
    again = back(cam)
    assert again.follower == arm and again.program.segments[0].h == program.segments[0].h
    assert back(arm) == arm and back(cams.TranslatingRoller(3.0, 0.5)) == cams.TranslatingRoller(
        3.0, 0.5
    )


@given(k=st.floats(0.005, 0.4), w=st.floats(1.0, 500.0), n=st.integers(3, 40), system=SYSTEMS)
def test_tasks_round_trip(k, w, n, system):
    theta = np.linspace(0, 2 * np.pi, n)
    task = FlywheelSizing(
        theta, 5 + np.cos(theta), k, w, density=7850.0, thickness=0.04, units=system
    )
    again = back(task)
    assert np.array_equal(again.theta, task.theta) and np.array_equal(again.torque, task.torque)
    assert (again.k, again.omega_avg, again.density) == (k, w, 7850.0)
    rotor = RotorBalance(((1.0, 0.1, 0.3, 0.2), (2.0, 0.2, -1.0, 0.5)), (0.0, 1.0), (0.1,), w)
    assert back(rotor).masses == rotor.masses and back(rotor).planes == rotor.planes
    c = (0 + 5.086j, 2.019 + 3.181j, 3.933 + 4.051j)
    motion = MotionTask(c, (0.741 + 2.703j, 4.428 + 2.529j, 6.304 + 4.83j))
    assert back(motion).c == motion.c
    fn = FunctionTask("x**2", (0.0, 1.0), (0.5, 1.5), (1.0, 2.0), points=4)
    assert back(fn).theta4 == fn.theta4 and back(fn).points == 4
    path = PathTask((0j, 1 + 0j, 1 + 1j), timing=(0.0, 0.5, 1.0), tolerance=0.01)
    assert back(path).timing == path.timing and back(path).targets == path.targets


# ------------------------------------------------------------------ two unit systems
def _pair(units, spec):
    return read({"machdyn": 1, "units": units, **spec})


def test_cams_in_m_and_in_mm_agree():
    seg = [
        {"motion": "rise", "law": "poly345", "lift": None, "beta": 90},
        {"motion": "dwell", "beta": 90},
        {"motion": "fall", "law": "poly345", "lift": None, "beta": 90},
        {"motion": "dwell", "beta": "1.5707963267948966 rad"},
    ]

    def cam(lift, rp, rf, speed):
        segments = [dict(s, **({"lift": lift} if "lift" in s else {})) for s in seg]
        return {
            "cam": {
                "c": {
                    "segment": segments,
                    "speed": speed,
                    "step": 5,
                    "follower": {"type": "roller", "prime_radius": rp, "roller_radius": rf},
                }
            }
        }

    m = _pair({"length": "m"}, cam(0.02, 0.06, 0.01, "10.471975511965978 rad/s"))
    mm = _pair({"length": "mm", "angular_velocity": "rpm"}, cam(20, 60, "1 cm", 100))
    a, b = m.run()["c"], mm.run()["c"]
    ta, tb = a.table("motion").labelled(m.units), b.table("motion").labelled(mm.units)
    np.testing.assert_allclose(tb["A [mm/s^2]"] * 1e-3, ta["A [m/s^2]"], rtol=1e-10, atol=1e-12)
    sa = dict(i.shown(m.units) for i in a.summary)
    sb = dict(i.shown(mm.units) for i in b.summary)
    assert sb["least radius of curvature [mm]"] == pytest.approx(
        1000 * sa["least radius of curvature [m]"], rel=1e-10
    )
    assert sb["largest |pressure angle| [deg]"] == pytest.approx(
        sa["largest |pressure angle| [deg]"], rel=1e-12
    )


def test_gears_flywheel_rotor_synthesis_in_two_systems_agree():
    theta = [0, 90, 180, 270, 360]
    si = _pair(
        {"length": "m", "mass": "kg"},
        {
            "gear_pair": {
                "p": {
                    "pinion": {"teeth": 20},
                    "gear": {"teeth": 50},
                    "module": 0.003,
                    "input_speed": "100 rad/s",
                }
            },
            "planetary": {
                "e": {"sun": 30, "planet": 15, "ring": 60, "speeds": {"arm": "1 rad/s", "ring": 0}}
            },
            "flywheel": {
                "f": {
                    "theta": theta,
                    "torque": [10, 12, 10, 8, 10],
                    "k": 0.05,
                    "omega_avg": "50 rad/s",
                    "density": 7800,
                    "thickness": 0.02,
                }
            },
            "rotor": {
                "r": {
                    "mass": [
                        {"mass": 0.5, "radius": 0.1, "angle": 10, "z": 0.1},
                        {"mass": 0.2, "radius": 0.3, "angle": 200, "z": 0.4},
                    ],
                    "planes": [0, 0.5],
                    "radii": [0.1, 0.1],
                }
            },
            "motion_synthesis": {
                "s": {
                    "c": [[0, 5.086], [2.019, 3.181], [3.933, 4.051]],
                    "d": [[0.741, 2.703], [4.428, 2.529], [6.304, 4.83]],
                }
            },
        },
    )
    mm = _pair(
        {"length": "mm", "mass": "g", "torque": "N*mm", "angular_velocity": "rpm"},
        {
            "gear_pair": {
                "p": {
                    "pinion": {"teeth": 20},
                    "gear": {"teeth": 50},
                    "module": 3,
                    "input_speed": "100 rad/s",
                }
            },
            "planetary": {
                "e": {"sun": 30, "planet": 15, "ring": 60, "speeds": {"arm": "1 rad/s", "ring": 0}}
            },
            "flywheel": {
                "f": {
                    "theta": theta,
                    "torque": [1e4, 1.2e4, 1e4, 8e3, 1e4],
                    "k": 0.05,
                    "omega_avg": "50 rad/s",
                    "density": "7.8 g/cm^3",
                    "thickness": 20,
                }
            },
            "rotor": {
                "r": {
                    "mass": [
                        {"mass": 500, "radius": 100, "angle": 10, "z": 100},
                        {"mass": 200, "radius": 300, "angle": 200, "z": 400},
                    ],
                    "planes": [0, 500],
                    "radii": [100, 100],
                }
            },
            "motion_synthesis": {
                "s": {
                    "c": [[0, 5086], [2019, 3181], [3933, 4051]],
                    "d": [[741, 2703], [4428, 2529], [6304, 4830]],
                }
            },
        },
    )
    ra, rb = si.run(), mm.run()

    def s(results, machine, part):
        return dict(i.shown(machine.units) for i in results[part].summary)

    assert s(rb, mm, "p")["centre distance [mm]"] == pytest.approx(
        1000 * s(ra, si, "p")["centre distance [m]"], rel=1e-12
    )
    assert rb["p"].speed == pytest.approx(ra["p"].speed, rel=1e-12)  # both rad/s inside
    sa = ra["e"].table("speeds").labelled(si.units)["speed [rad/s]"]
    sb = rb["e"].table("speeds").labelled(mm.units)["speed [rpm]"]
    np.testing.assert_allclose(sb * RPM, sa, rtol=1e-12)
    fa, fb = s(ra, si, "f"), s(rb, mm, "f")
    assert fb["delta_E [N*mm]"] == pytest.approx(1000 * fa["delta_E [N*m]"], rel=1e-10)
    assert fb["I (flywheel inertia) [g*mm^2]"] == pytest.approx(
        1e9 * fa["I (flywheel inertia) [kg*m^2]"], rel=1e-10
    )
    assert fb["disc outer radius [mm]"] == pytest.approx(
        1000 * fa["disc outer radius [m]"], rel=1e-10
    )
    ca = ra["r"].table("corrections").labelled(si.units)
    cb = rb["r"].table("corrections").labelled(mm.units)
    np.testing.assert_allclose(cb["mass [g]"] * 1e-3, ca["mass [kg]"], rtol=1e-12)
    np.testing.assert_allclose(
        s(rb, mm, "s")["r1, r2, r3, r4 [mm]"], 1000 * np.array(s(ra, si, "s")["r1, r2, r3, r4 [m]"])
    )


@pytest.mark.parametrize(
    ("spec", "needle"),
    [
        ({"gear_pair": {"p": {"pinion": {"teeth": 20}, "gear": {"teeth": 50}}}}, "module or"),
        ({"gear_train": {"t": {"stages": [[18]]}}}, "expected [driver teeth"),
        ({"planetary": {"e": {"sun": 30, "planet": 15, "ring": 61}}}, "[planetary.e] ring"),
        ({"planetary": {"e": {"chain": [["sun", 30]], "sun": 30}}}, "chain"),
        ({"cam": {"c": {"segment": [{"motion": "rise", "beta": 360}]}}}, "missing: a rise needs"),
        ({"cam": {"c": {"segment": [{"motion": "dwell", "beta": 300}]}}}, "sum to 360"),
        ({"flywheel": {"f": {"torque": "nope", "k": 0.1}}}, "'nope' is not a part"),
        ({"flywheel": {"f": {"torque": [1, 2, 3], "k": 0.1}}}, "missing: the angles"),
        ({"flywheel": {"f": {"torque": "no.csv", "k": 0.1}}}, "cannot read it"),
        (
            {"rotor": {"r": {"mass": [{"mass": 1, "radius": 1, "angle": 0}], "planes": [0, 1]}}},
            "needs each z",
        ),
        (
            {
                "function_synthesis": {
                    "f": {"function": "import os", "x": [1, 2], "theta2": [0, 1], "theta4": [0, 1]}
                }
            },
            "function",
        ),
    ],
)
def test_bad_parts_of_every_kind_name_the_key(spec, needle):
    with pytest.raises(SpecError) as info:
        from_spec({"machdyn": 1, "units": {"length": "mm"}, **spec})
    assert needle in str(info.value) and "\n" not in str(info.value)


def test_gear_trains_function_and_path_synthesis_in_two_systems_agree():
    """The remaining kinds: SI (m, rad/s) against mm, deg and rpm; factors written here."""
    mm_per_m, rpm_per_rad_s = 1000.0, 60 / (2 * math.pi)
    targets = [[0, 0], [0.1, 0.05], [0.2, 0], [0.1, -0.05]]
    search = {"maxiter": 20, "popsize": 6, "seed": 3, "polish": False}
    si = _pair(
        {"length": "m", "angle": "rad"},
        {
            "gear_train": {"b": {"stages": [[18, 54], [20, 60]], "input_speed": 100.0}},
            "function_synthesis": {
                "f": {
                    "function": "log10(x)",
                    "x": [1, 2],
                    "theta2": [math.radians(45), math.radians(105)],
                    "theta4": [math.radians(135), math.radians(225)],
                    "r1": 0.2,
                }
            },
            "path_synthesis": {"p": {"targets": targets, "tolerance": 0.001, **search}},
        },
    )
    mm = _pair(
        {"length": "mm", "angle": "deg", "angular_velocity": "rpm"},
        {
            "gear_train": {"b": {"stages": [[18, 54], [20, 60]], "input_speed": "100 rad/s"}},
            "function_synthesis": {
                "f": {
                    "function": "log10(x)",
                    "x": [1, 2],
                    "theta2": [45, 105],
                    "theta4": [135, 225],
                    "r1": 200,
                }
            },
            "path_synthesis": {
                "p": {
                    "targets": [[mm_per_m * x, mm_per_m * y] for x, y in targets],
                    "tolerance": 1,
                    **search,
                }
            },
        },
    )
    ra, rb = si.run(), mm.run()

    def s(results, machine, part):
        return dict(i.shown(machine.units) for i in results[part].summary)

    # the train: 18/54 * 20/60 = 1/9 of the input speed, shown in rad/s and in rpm
    assert s(ra, si, "b")["output speed [rad/s]"] == pytest.approx(100 / 9, rel=1e-12)
    assert s(rb, mm, "b")["output speed [rpm]"] == pytest.approx(100 / 9 * rpm_per_rad_s)
    sa = ra["b"].table("stages").labelled(si.units)["driven_speed [rad/s]"]
    sb = rb["b"].table("stages").labelled(mm.units)["driven_speed [rpm]"]
    np.testing.assert_allclose(sb, sa * rpm_per_rad_s, rtol=1e-12)
    # Freudenstein: the same linkage, lengths scaled by 1000
    np.testing.assert_allclose(
        s(rb, mm, "f")["r1, r2, r3, r4 [mm]"],
        mm_per_m * np.array(s(ra, si, "f")["r1, r2, r3, r4 [m]"]),
        rtol=1e-10,
    )
    # the path search (same seed): the same design at 1000 times the size
    np.testing.assert_allclose(
        s(rb, mm, "p")["r1, r2, r3, r4 [mm]"],
        mm_per_m * np.array(s(ra, si, "p")["r1, r2, r3, r4 [m]"]),
        rtol=1e-6,
    )
    assert s(rb, mm, "p")["mu_min [deg]"] == pytest.approx(
        math.degrees(s(ra, si, "p")["mu_min [rad]"]), rel=1e-6
    )
    da = ra["p"].table("targets").labelled(si.units)["distance [m]"]
    db = rb["p"].table("targets").labelled(mm.units)["distance [mm]"]
    np.testing.assert_allclose(db, mm_per_m * da, rtol=1e-5, atol=1e-9)
