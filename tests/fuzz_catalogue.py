"""A valid call of every public callable, for the bad-input fuzzers (tests/test_fuzz_api.py).

Each entry names one public function, class or method (``"module:Qualname"``) and a
valid call of it: the callable (a factory, so that methods get a fresh instance) and
keyword arguments. The fuzzer replaces one argument at a time with each value of a
catalogue of bad values and asserts a machdyn error or a result that passes the
checks (:mod:`tests.test_fuzz_api`).

Adding a public name anywhere (a module's ``__all__`` or a public method) without an
entry here fails ``test_every_public_callable_is_catalogued``: new functions are fuzzed
from the day they are written.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

#: Front-end packages: they parse, draw and present, and are fuzzed through the CLI
#: (tests/test_fuzz_cli.py) and their own browser tests, not here.
FRONT_ENDS = (
    "machdyn.cli",
    "machdyn.draw",
    "machdyn.plot",
    "machdyn.report",
    "machdyn.studio",
    "machdyn.viewer",
)


#: Modules of a package that serve its public functions and are not called by users
#: (their names would better start with "_"); the package's __all__ is fuzzed instead.
INTERNAL_MODULES = {
    "machdyn.linkage.newton_euler": "Newton-Euler blocks of Linkage.forces and dynamics",
    "machdyn.synthesis.atlas_dask": "Dask plumbing of build_atlas",
    "machdyn.synthesis.atlas_store": "the atlas folder's chunks and manifest (build_atlas)",
    "machdyn.synthesis.circuits": "circuit sampling inside the atlas builder",
    "machdyn.synthesis.descriptor": "curve descriptors inside path_from_atlas",
    "machdyn.synthesis.geometry": "points and lines inside the synthesis functions",
    "machdyn.synthesis.refine": "least-squares refinement inside path_from_atlas",
    "machdyn.synthesis.valley": "the final polish of a refinement inside path_from_atlas",
}


def public_modules() -> list[str]:
    """Every public module of machdyn with an ``__all__`` (packages before their modules)."""
    import importlib
    import pkgutil

    import machdyn

    names = ["machdyn"]
    for info in pkgutil.walk_packages(machdyn.__path__, "machdyn."):
        if any(part.startswith("_") for part in info.name.split(".")):
            continue
        if info.name.startswith(FRONT_ENDS) or info.name in INTERNAL_MODULES:
            continue
        if info.name == "machdyn.errors":
            continue
        if getattr(importlib.import_module(info.name), "__all__", None):
            names.append(info.name)
    return sorted(names, key=lambda n: (n == "machdyn", n.count("."), n))


#: Public names that are not called by users with arguments of their own: result
#: records built by machdyn (their methods are catalogued), exceptions and constants.
NOT_CALLED = {
    # results and records, constructed by machdyn and handed to the user
    "machdyn.cams:CamProfile",
    "machdyn.cams:ContinuityReport",
    "machdyn.cams:DesignCheck",
    "machdyn.cams:Discontinuity",
    "machdyn.cams:LawValues",
    "machdyn.cams:Motion",
    "machdyn.cams:MotionLaw",
    "machdyn.cams:PolynomialLaw",
    "machdyn.cams:Sizing",
    "machdyn.cams:SurfaceSelfIntersection",
    "machdyn.cams:TimeMotion",
    "machdyn.centres:InstantCentre",
    "machdyn.centres:InstantCentres",
    "machdyn.centrodes:Centrodes",
    "machdyn.centrodes:PitchCurves",
    "machdyn.centrodes:RolledMotion",
    "machdyn.classify:Classification",
    "machdyn.classify:FourBarLoop",
    "machdyn.dynamics:FourBarForces",
    "machdyn.dynamics:LinkEquations",
    "machdyn.dynamics:LinkProperties",
    "machdyn.dynamics:SliderCrankForces",
    "machdyn.dynamics_inverted:InvertedSliderCrankForces",
    "machdyn.flywheel:DiscFlywheel",
    "machdyn.flywheel:FlywheelResult",
    "machdyn.flywheel:LobeTable",
    "machdyn.fourbar:FourBarMotion",
    "machdyn.gears:GearOutline",
    "machdyn.gears:MeshForces",
    "machdyn.gears:PlanetaryPower",
    "machdyn.gears:PlanetaryTable",
    "machdyn.gears:RevertedTrain",
    "machdyn.gears:TrainPower",
    "machdyn.linkage:LinkageForces",
    "machdyn.linkage:LinkageMotion",
    "machdyn.loops:Motion",
    "machdyn.loops:SystemReport",
    "machdyn.shaking:Counterweights",
    "machdyn.shaking:LinkageBalance",
    "machdyn.shaking:LinkageCounterweight",
    "machdyn.shaking:SliderCrankBalance",
    "machdyn.slidercrank:InvertedSliderCrankMotion",
    "machdyn.slidercrank:SliderCrankMotion",
    "machdyn.synthesis:Atlas",  # opened by open_atlas
    "machdyn.synthesis:AtlasError",
    "machdyn.synthesis:PathCandidates",
    "machdyn.synthesis:SixBarPath",
    "machdyn.synthesis:CouplerAtlas",
    "machdyn.synthesis:DrivingDyad",
    "machdyn.synthesis:FunctionGenerator",
    "machdyn.synthesis:MotionSynthesis",
    "machdyn.synthesis:PathSynthesis",
    "machdyn.synthesis:QuickReturn",
    "machdyn.synthesis:RotopoleLink",
    "machdyn.synthesis:StructuralError",
    "machdyn.virtual_work:InputTorque",
    "machdyn.balancing:StaticBalance",
    "machdyn.balancing:TwoPlaneBalance",
    "machdyn.inversions:Inversion",
    "machdyn.inversions:InversionTable",
    "machdyn.linkage:Joint",
    "machdyn.linkage:Link",
    "machdyn.linkage:Spring",
    "machdyn.linkage:TorsionSpring",
    "machdyn.linkage:Group",
    "machdyn.linkage.dyads:Pair",
    "machdyn.linkage.dyads:PinOnLine",
    "machdyn.linkage.dyads:Slotted",
    "machdyn.linkage.dyads:TwoLines",
    "machdyn.rotor:BearingReactions",
    "machdyn.spec:Machine",  # built by machdyn.spec.load; its methods are catalogued
    "machdyn.spec:Part",
    "machdyn.units:Kind",
    # machdyn.simulate: results, loads built by torque()/force()/step(), the motors' base
    "machdyn.simulate:Energy",
    "machdyn.simulate:Event",
    "machdyn.simulate:Load",
    "machdyn.simulate:Motor",
    "machdyn.simulate:PeriodicMotion",
    "machdyn.simulate:MultiSimulation",
    "machdyn.simulate:Simulation",
    "machdyn.simulate:SteadyState",
    "machdyn.simulate:Step",
    "machdyn.sensitivity:Sensitivity",
    "machdyn.tolerance:Spread",
    "machdyn.tolerance:Tolerance",
}

#: Public callables not fuzzed here, with the reason.
NOT_FUZZED = {
    "machdyn.cams:plot_profile": "drawing (matplotlib); tested by the plotting tests and the CLI",
    "machdyn.cams:plot_svaj": "drawing (matplotlib); tested by the plotting tests and the CLI",
    "machdyn.gears:plot_mesh": "drawing (matplotlib); tested by the plotting tests and the CLI",
    "machdyn.cams:write_csv": "writes files; fuzzed through the CLI",
    "machdyn.cams:write_dxf": "writes files; fuzzed through the CLI",
}

#: Methods not fuzzed, with the reason.
METHODS_NOT_FUZZED = {
    # drawing: hands off to matplotlib; each call costs ~50 ms (fuzzed by the CLI and
    # the plotting tests instead)
    "plot",
    "draw",
    "animate",
    "plot_coupler_curve",
    "to_html",
    "report",  # the design report: machdyn.report (tests/test_report.py and its browser test)
    # writing files: fuzzed through the CLI (tests/test_fuzz_cli.py)
    "to_csv",
    "to_dxf",
    "to_svg",
}


@dataclass
class Call:
    """A valid call: ``target()(*args, **kwargs)``."""

    target: Callable[[], Callable[..., Any]]
    kwargs: dict[str, Any] = field(default_factory=dict)
    args: tuple[Any, ...] = ()
    #: bad-value names (see test_fuzz_api.BAD) that are valid for a parameter here
    accepts: dict[str, set[str]] = field(default_factory=dict)
    #: parameters not fuzzed, with the reason
    skip: dict[str, str] = field(default_factory=dict)
    #: an independent check of an accepted result: check(result, kwargs) raises if wrong
    check: Callable[[Any, dict[str, Any]], None] | None = None
    #: results may hold non-finite numbers unflagged (say why)
    nonfinite: str = ""


def _fb():
    from machdyn import FourBar

    return FourBar(8.0, 4.0, 7.0, 6.0, coupler=(3.0, 0.5))


def _sc():
    from machdyn import SliderCrank

    return SliderCrank(2.0, 6.0, 0.5, point=(2.0, 0.3))


def _program():
    from machdyn.cams import CamProgram

    return CamProgram.double_dwell(1.0, math.radians(60), math.radians(60))


def _motion():
    return _program().sample(90)


def _profile():
    from machdyn.cams import TranslatingRoller

    return TranslatingRoller(4.0, 0.5).profile(_program(), n=90)


def _gear(teeth=24):
    from machdyn.gears import Gear

    return Gear(teeth, diametral_pitch=8)


def _pair():
    from machdyn.gears import GearPair

    return GearPair(_gear(24), _gear(60))


def _linkage():
    from machdyn.linkage import Linkage

    lk = Linkage({"O2": (0, 0), "O4": (8, 0), "A": (4, 0), "B": (7.625, math.sqrt(49 - 3.625**2))})
    lk = lk.ground("O2", "O4").link("crank", "O2", "A", mass=1.0, inertia=0.1)
    lk = lk.link("coupler", "A", "B", mass=2.0, inertia=0.5)
    return lk.link("rocker", "O4", "B", mass=1.5, inertia=0.3).drive("crank")


def _loops():
    from machdyn.loops import LoopSystem

    s = LoopSystem().vector("R1", 8.0, 0.0).vector("R2", 4.0, "theta2")
    s = s.vector("R3", 7.0, "theta3").vector("R4", 6.0, "theta4")
    return s.loop("R2 + R3 - R4 - R1").point("B", "R2 + R3").inputs("theta2")


THETA = np.radians([0.0, 40.0, 95.0, 200.0, 310.0])
MASS = dict(mass=(1.0, 2.0, 1.5), inertia=(0.1, 0.5, 0.3), cg=(2.0, 3.0 + 0.5j, 3.0))
SC_MASS = dict(mass=(1.0, 2.0, 1.5), inertia=(0.1, 0.5), cg=(1.0, 3.0 + 0.2j))


def _attr(factory, name):
    return lambda: getattr(factory(), name)


def _mod(module, name):
    def target():
        import importlib

        obj = importlib.import_module(module)
        for part in name.split("."):
            obj = getattr(obj, part)
        return obj

    return target


def catalogue() -> dict[str, Call]:
    """Every catalogued call, by ``"module:Qualname"``."""
    c: dict[str, Call] = {}

    def fn(key: str, call: Call | None = None, /, **kwargs: Any) -> None:
        module, qual = key.split(":")
        if call is None:
            call = Call(_mod(module, qual), kwargs)
        c[key] = call

    def meth(key: str, factory, /, **kwargs: Any) -> Call:
        name = key.split(".")[-1]
        c[key] = Call(_attr(factory, name), kwargs)
        return c[key]

    # --- the top level and the closed-form models -----------------------------------
    fn("machdyn.fourbar:FourBar", r1=8.0, r2=4.0, r3=7.0, r4=6.0, coupler=(3.0, 0.5))
    c["machdyn.fourbar:FourBar"].accepts["coupler"] = {"none"}
    meth("machdyn.fourbar:FourBar.solve", _fb, theta2=THETA, omega2=10.0, alpha2=1.0)
    meth("machdyn.fourbar:FourBar.dynamics", _fb, theta2=THETA, omega2=10.0, **MASS)
    meth("machdyn.fourbar:FourBar.input_range", _fb, form=1)
    meth("machdyn.fourbar:FourBar.toggles", _fb)
    meth(
        "machdyn.fourbar:FourBar.extrema", _fb, form=1, n=101
    ).nonfinite = (
        "an angle that turns fully has no extremum location (full_turn=True, theta2_at NaN)"
    )
    meth("machdyn.fourbar:FourBar.transmission_angle", _fb, form=1, n=101)
    meth("machdyn.fourbar:FourBar.coupler_curve", _fb, form=1, n=101)
    meth("machdyn.fourbar:FourBar.instant_centres", _fb, theta2=THETA)
    meth("machdyn.fourbar:FourBar.mechanical_advantage", _fb, theta2=THETA)
    fn("machdyn.fourbar:positions", r1=8.0, r2=4.0, r3=7.0, r4=6.0, theta2=THETA)
    t3, t4 = _fb_angles()
    fn(
        "machdyn.fourbar:velocities",
        r2=4.0,
        r3=7.0,
        r4=6.0,
        theta2=THETA,
        theta3=t3,
        theta4=t4,
        omega2=10.0,
    )
    fn(
        "machdyn.fourbar:accelerations",
        r2=4.0,
        r3=7.0,
        r4=6.0,
        theta2=THETA,
        theta3=t3,
        theta4=t4,
        omega2=10.0,
        omega3=1.0,
        omega4=2.0,
        alpha2=0.0,
    )
    fn(
        "machdyn.fourbar:jerks",
        r2=4.0,
        r3=7.0,
        r4=6.0,
        theta2=THETA,
        theta3=t3,
        theta4=t4,
        omega2=10.0,
        omega3=1.0,
        omega4=2.0,
        alpha2=0.0,
        alpha3=1.0,
        alpha4=1.0,
        jerk2=0.0,
    )
    fn("machdyn.fourbar:named_angle", name="phi12", theta2=THETA, theta3=t3, theta4=t4)
    fn("machdyn.slidercrank:SliderCrank", crank=2.0, coupler=6.0, offset=0.5, point=(2.0, 0.3))
    c["machdyn.slidercrank:SliderCrank"].accepts["point"] = {"none"}
    meth("machdyn.slidercrank:SliderCrank.input_range", _sc)
    meth("machdyn.slidercrank:SliderCrank.stroke", _sc, form=1)
    meth("machdyn.slidercrank:SliderCrank.solve", _sc, theta2=THETA, omega2=10.0, alpha2=1.0)
    meth("machdyn.slidercrank:SliderCrank.dynamics", _sc, theta2=THETA, omega2=10.0, **SC_MASS)
    meth("machdyn.slidercrank:SliderCrank.instant_centres", _sc, theta2=THETA)
    meth("machdyn.slidercrank:SliderCrank.mechanical_advantage", _sc, theta2=THETA)
    fn("machdyn.slidercrank:InvertedSliderCrank", crank=2.0, ground=4.0, offset=0.3)
    meth(
        "machdyn.slidercrank:InvertedSliderCrank.solve",
        lambda: __import__("machdyn").InvertedSliderCrank(2.0, 4.0),
        theta2=THETA,
        omega2=10.0,
    )
    for name in ("barker_class", "classify", "is_grashof", "is_assemblable"):
        fn(f"machdyn.classify:{name}", r1=8.0, r2=4.0, r3=7.0, r4=6.0)
    fn("machdyn.classify:fourbar_loops", lk=_linkage())
    fn("machdyn.mobility:mobility", links=4, full_joints=4, half_joints=0)

    def gruebler(result, kw) -> None:  # exact integer arithmetic: any size is answered
        L, J1, J2 = (int(kw[k]) for k in ("links", "full_joints", "half_joints"))
        assert result == 3 * (L - 1) - 2 * J1 - J2

    c["machdyn.mobility:mobility"].check = gruebler
    for name in ("links", "full_joints", "half_joints"):
        c["machdyn.mobility:mobility"].accepts[name] = {"bigint"}
    fn("machdyn.mobility:mobility_of", joints=[("R", (1, 2)), ("R", (2, 3)), ("R", (3, 1))])
    c["machdyn.mobility:mobility_of"].accepts["links"] = {"none", "bigint"}
    c["machdyn.mobility:mobility_of"].check = _mobility_of_check
    fn("machdyn.mobility:Joint", kind="R", links=(1, 2))
    fn("machdyn.loops:Vector", name="R1", length=8.0, angle=0.0)
    c["machdyn.dynamics:PointLoad"] = Call(  # a record: checked where it is used
        lambda: _used_point_load, dict(link=3, point=1 + 1j, force=10j)
    )
    fn("machdyn.massprops:MassProperties", mass=2.0, cg=1 + 1j, inertia=0.5)
    fn("machdyn.mobility:count_joints", joints=[("R", (1, 2)), ("P", (2, 3))])
    from machdyn.centres import finite

    p, q, r = (
        finite(np.array([0j, 1 + 1j])),
        finite(np.array([1 + 0j, 2j])),
        finite(np.array([2 + 0j, 3j])),
    )
    fn("machdyn.centres:at_infinity", direction=1 + 1j)
    fn("machdyn.centres:finite", z=1 + 2j)
    fn("machdyn.centres:collinearity", p=p, q=q, r=r)
    fn("machdyn.centres:line_through", p=p, q=q)
    fn(
        "machdyn.centres:intersect",
        Call(
            _mod("machdyn.centres", "intersect"),
            {"l1": _line(0j, 1 + 0j), "l2": _line(0j, 1j)},
        ),
    )
    meth("machdyn.centres:InstantCentres.omega_ratio", _ics, i=3, j=2, ground=1)
    meth("machdyn.centres:InstantCentres.method", _ics, i=1, j=3)
    fn("machdyn.centrodes:centrodes", model=_fb(), values=THETA, moving=3, fixed=1, form=1)
    fn("machdyn.centrodes:gear_pitch_curves", model=_fb(), values=THETA, link_a=2, link_b=4)
    cent = lambda: __import__("machdyn.centrodes").centrodes.centrodes(_fb(), THETA, 3)  # noqa: E731
    meth("machdyn.centrodes:Centrodes.placed", cent, k=2)
    meth("machdyn.centrodes:Centrodes.roll", cent)
    meth("machdyn.centrodes:Centrodes.to_pandas", cent)
    meth(
        "machdyn.centres:InstantCentres.mechanical_advantage",
        _ics,
        input=2,
        output=4,
        r_in=1.0,
        r_out=2.0,
        ground=1,
    )
    fn("machdyn.centres:instant_centres_of", lk=_linkage(), values=THETA, velocity=1.0)
    fn("machdyn.centres:linkage_centres", lk=_linkage(), motion=_linkage().solve(THETA, 1.0))
    meth("machdyn.linkage:Linkage.instant_centres", _linkage, values=THETA, velocity=2.0)
    meth(
        "machdyn.slidercrank:InvertedSliderCrank.instant_centres",
        lambda: __import__("machdyn").InvertedSliderCrank(2.0, 4.0),
        theta2=THETA,
        form=1,
    )
    meth("machdyn.fourbar:FourBar.inversions", _fb, n=101)
    fn("machdyn.inversions:inversions", r1=6.0, r2=9.0, r3=3.0, r4=8.0, n=101)
    arc = (math.radians(30.0), math.radians(90.0))
    fn("machdyn.inversions:AngleRange", arcs=(arc,), full_turn=False)
    fn("machdyn.inversions:AngleRange.every_direction")
    rng = lambda: __import__("machdyn.inversions").inversions.AngleRange((arc,))  # noqa: E731
    meth("machdyn.inversions:AngleRange.contains", rng, angle=np.array([0.6, 2.0]), tol=1e-9)
    meth("machdyn.inversions:AngleRange.text", rng, digits=2)
    meth("machdyn.inversions:AngleRange.degrees", rng)
    meth("machdyn.inversions:AngleRange.intersection", rng, other=rng())
    table = lambda: __import__("machdyn.inversions").inversions.inversions(6, 9, 3, 8, n=101)  # noqa: E731
    meth("machdyn.inversions:InversionTable.rows", table)
    meth("machdyn.inversions:InversionTable.to_pandas", table)
    meth("machdyn.inversions:Inversion.fourbar", lambda: table()[1])
    for name in ("active", "load", "mode", "reason"):
        fn(f"machdyn.jit:{name}")
    fn("machdyn.jit:set_mode", value="off")
    c["machdyn.jit:set_mode"].accepts["value"] = {"none"}

    _add_analyses(c, fn, meth)
    _add_elements(c, fn, meth)
    _add_design(c, fn, meth)
    _add_general(c, fn, meth)
    __import__("fuzz_catalogue_spec").add_spec(c, fn, meth)  # machdyn.spec, machdyn.units
    __import__("fuzz_catalogue_simulate").add_simulate(c, fn, meth)  # machdyn.simulate
    for (key, name), values in ACCEPTS.items():
        c[key].accepts.setdefault(name, set()).update(values)
    for key, why in NONFINITE.items():
        c[key].nonfinite = why
    return c


def _used_point_load(**kwargs: Any) -> Any:
    """A PointLoad as four-bar dynamics use it (the record is checked there)."""
    from machdyn.dynamics import PointLoad

    return _fb().dynamics(THETA, 10.0, **MASS, external_forces=[PointLoad(**kwargs)])


def _mobility_of_check(result, kw) -> None:
    links = kw.get("links")
    if links is not None and not isinstance(links, bool):
        assert result == 3 * (int(links) - 1) - 2 * len(kw["joints"]), "Gruebler"


#: (entry, parameter) -> bad values that are valid there (complex points, NaN passed
#: through as "not assembled", ...), applied once the catalogue is built.
ACCEPTS = {
    **{
        (f"machdyn.fourbar:{f}", t): {"nan"}
        for f in ("velocities", "accelerations", "jerks", "named_angle")
        for t in ("theta3", "theta4")
    },
    ("machdyn.fourbar:positions", "theta2"): {"nan"},  # the sample comes out not ok
    ("machdyn.centres:finite", "z"): {"nan", "complex"},
    ("machdyn.centres:at_infinity", "direction"): {"nan", "complex"},
    ("machdyn.balancing:static_balance", "unbalance"): {"complex"},
    ("machdyn.balancing:two_plane", "unbalance"): {"complex"},
    ("machdyn.balancing:shaking_force", "unbalance"): {"complex"},
    ("machdyn.balancing:shaking_moment", "unbalance"): {"complex"},
    ("machdyn.balancing:bearing_balance", "bearing_forces"): {"complex"},
    ("machdyn.virtual_work:power", "effort"): {"complex"},
    ("machdyn.virtual_work:power", "rate"): {"complex"},
    ("machdyn.virtual_work:virtual_work", "input_rate"): {"complex"},
    ("machdyn.virtual_work:virtual_work", "direction"): {"complex"},
    ("machdyn.massprops:cg_motion", "origin"): {"complex"},
    ("machdyn.massprops:cg_motion", "origin_velocity"): {"complex"},
    ("machdyn.massprops:cg_motion", "origin_acceleration"): {"complex"},
    ("machdyn.massprops:parallel_axis", "d"): {"complex"},
    ("machdyn.rotor:Rotor.from_masses", "R"): {"complex"},
    ("machdyn.gears:gear_outline", "center"): {"complex"},  # a point x + jy or (x, y)
    **{
        (f"machdyn.synthesis:{f}", p): {"complex"}
        for f, ps in {
            "circumcentre": ("p1", "p2", "p3"),
            "driving_dyad": ("pivot", "b1", "b2"),
            "intersect_lines": ("p1", "u1", "p2", "u2"),
            "perpendicular_bisector": ("p", "q"),
            "rigid_motion": ("c_from", "d_from", "c_to", "d_to"),
            "rotopole": ("c1", "d1", "c2", "d2"),
            "three_position": ("A", "B"),
            "three_position_fixed_pivots": ("O2", "O4"),
            "two_position": ("A", "B"),
            "path_objective": ("centre",),
            "PlacedFourBar.theta2_of": ("A",),
            "PlacedFourBar.to_global": ("z",),
            "PlacedFourBar.to_local": ("z",),
        }.items()
        for p in ps
    },
    ("machdyn.gears:GearPair.with_center_distance", "center_distance"): {"none"},  # tight mesh
    # a tooth count of inf is a rack (documented)
    ("machdyn.gears:min_pinion_teeth", "gear_teeth"): {"inf"},
    ("machdyn.gears:onset_gear_teeth", "pinion_teeth"): {"inf"},
    ("machdyn.gears:max_gear_teeth", "pinion_teeth"): {"inf"},
    ("machdyn.gears:min_profile_shift", "teeth"): {"inf"},
    ("machdyn.gears:undercut", "teeth"): {"inf"},
    ("machdyn.rotor:Rotor.with_masses", "R"): {"complex"},
}

#: Entries whose results may hold ±inf unflagged, with the documented reason.
NONFINITE = {
    "machdyn.virtual_work:mechanical_advantage": "±inf where the output stops (a toggle)",
    "machdyn.gears:onset_gear_teeth": "inf: the pinion meshes even with a rack (documented)",
    "machdyn.gears:max_gear_teeth": "inf: any gear, even a rack (documented)",
}


def _fb_angles():
    from machdyn.fourbar import positions

    t3, t4, _ = positions(8.0, 4.0, 7.0, 6.0, THETA)
    return t3, t4


def _line(a, b):
    from machdyn.centres import finite, line_through

    return line_through(finite(a), finite(b))


def _ics():
    return _fb().instant_centres(THETA)


def _add_analyses(c, fn, meth) -> None:
    fb, sc = _fb, _sc
    motion = lambda: _fb().solve(THETA, 10.0, 1.0)  # noqa: E731
    sc_motion = lambda: _sc().solve(THETA, 10.0, 1.0)  # noqa: E731
    fn("machdyn.dynamics:fourbar_dynamics", fourbar=fb(), theta2=THETA, omega2=10.0, **MASS)
    fn("machdyn.dynamics:fourbar_forces", fourbar=fb(), motion=motion(), **MASS)
    fn(
        "machdyn.dynamics:slidercrank_dynamics",
        slidercrank=sc(),
        theta2=THETA,
        omega2=10.0,
        **SC_MASS,
    )
    fn("machdyn.dynamics:slidercrank_forces", slidercrank=sc(), motion=sc_motion(), **SC_MASS)
    isc = lambda: __import__("machdyn").InvertedSliderCrank(2.0, 4.0, 0.3)  # noqa: E731
    fn(
        "machdyn.dynamics_inverted:inverted_slidercrank_dynamics",
        isc=isc(),
        theta2=THETA,
        omega2=10.0,
        **MASS,
    )
    fn(
        "machdyn.dynamics_inverted:inverted_slidercrank_forces",
        isc=isc(),
        motion=isc().solve(THETA, 10.0, 1.0),
        **MASS,
    )
    meth("machdyn.slidercrank:InvertedSliderCrank.dynamics", isc, theta2=THETA, omega2=10.0, **MASS)
    fn(
        "machdyn.dynamics:link_equations",
        mass=8.0,
        inertia=6.0,
        a_g=-4 - 5j,
        alpha=-5.0,
        joints={"F32": (-4 + 1j, -1), "F43": (1 - 6j, 1)},
        forces=[(-1 + 1.5j, 3 - 5j)],
        torque=12.0,
    )
    fn(
        "machdyn.dynamics:link_properties",
        mass=(1.0, 2.0, 3.0),
        inertia=(1.0, 1.0, 1.0),
        cg=(1, 2, 3),
    )
    c["machdyn.dynamics:link_properties"].accepts["length_unit"] = {"none"}
    fn("machdyn.dynamics:unit_system", length_unit="mm")
    c["machdyn.dynamics:unit_system"].accepts["length_unit"] = {"none"}
    from machdyn.massprops import rod

    fn(
        "machdyn.dynamics:from_bodies",
        Call(_mod("machdyn.dynamics", "from_bodies"), args=(rod(1, 4), rod(2, 7), rod(1.5, 6))),
    )
    meth(
        "machdyn.dynamics:LinkEquations.residual",
        lambda: __import__("machdyn.dynamics").dynamics.link_equations(
            8, 6, -4 - 5j, -5, {"F32": (-4 + 1j, -1), "F43": (1 - 6j, 1)}
        ),
        values=[1.0, 2.0, 3.0, 4.0],
    )
    meth(
        "machdyn.dynamics:SliderCrankForces.normal_reversals",
        lambda: _sc().dynamics(THETA, 10.0, **SC_MASS),
    )
    for result, factory in (
        ("machdyn.dynamics:FourBarForces", lambda: _fb().dynamics(THETA, 10.0, **MASS)),
        ("machdyn.dynamics:SliderCrankForces", lambda: _sc().dynamics(THETA, 10.0, **SC_MASS)),
        (
            "machdyn.dynamics_inverted:InvertedSliderCrankForces",
            lambda: isc().dynamics(THETA, 10.0, **MASS),
        ),
        ("machdyn.fourbar:FourBarMotion", motion),
        ("machdyn.slidercrank:SliderCrankMotion", sc_motion),
    ):
        meth(f"{result}.to_pandas", factory)
    c["machdyn.fourbar:FourBarMotion.to_pandas"].kwargs["degrees"] = True
    fn(
        "machdyn.virtual_work:fourbar_input_torque",
        fourbar=fb(),
        theta2=THETA,
        omega2=10.0,
        alpha2=1.0,
        **MASS,
    )
    fn("machdyn.virtual_work:fourbar_mechanical_advantage", fourbar=fb(), theta2=THETA)
    fn(
        "machdyn.virtual_work:mechanical_advantage",
        input_rate=np.array([1.0, 2.0]),
        output_rate=0.5,
    )
    fn("machdyn.virtual_work:power", effort=2.0 + 1j, rate=1.0 - 1j)
    fn(
        "machdyn.virtual_work:virtual_work",
        input_rate=0.5,
        loads=[(-1000 * 9.81j, 0.08896 + 1.086j)],
    )
    c["machdyn.virtual_work:virtual_work"].accepts["direction"] = {"none"}
    meth(
        "machdyn.virtual_work:InputTorque.to_pandas",
        lambda: __import__("machdyn.virtual_work").virtual_work.fourbar_input_torque(
            _fb(), THETA, 10.0, **MASS
        ),
    )
    fn("machdyn.shaking:fourbar_counterweights", fourbar=fb(), mass=(1, 2, 1), cg=(2, 3.5, 3))
    meth(
        "machdyn.shaking:Counterweights.apply",
        lambda: __import__("machdyn.shaking").shaking.fourbar_counterweights(
            _fb(), (1, 2, 1), (2, 3.5, 3)
        ),
        **MASS,
        counterweight_mass=(0.5, 0.5),
    )
    sc_bal = lambda: __import__("machdyn.shaking").shaking.slidercrank_counterweight(  # noqa: E731
        _sc(), (1, 2, 1), (1.0, 3.0)
    )
    fn("machdyn.shaking:slidercrank_counterweight", slidercrank=_sc(), mass=(1, 2, 1), cg=(1, 3))
    meth(
        "machdyn.shaking:SliderCrankBalance.apply",
        sc_bal,
        mass=(1, 2, 1),
        inertia=(0.1, 0.5),
        cg=(1.0, 3.0),
        radius=1.0,
    )
    meth("machdyn.shaking:SliderCrankBalance.mass", sc_bal, radius=1.0)
    meth(
        "machdyn.shaking:SliderCrankBalance.shaking_force",
        sc_bal,
        motion=_sc().solve(THETA, 10.0),
    )
    fn("machdyn.shaking:linkage_counterweights", linkage=_linkage())
    meth(
        "machdyn.shaking:LinkageBalance.apply",
        lambda: __import__("machdyn.shaking").shaking.linkage_counterweights(_linkage()),
        linkage=_linkage(),
        radius=1.0,
    )
    c["machdyn.shaking:LinkageBalance.apply"].accepts["radius"] = {"none"}
    theta = np.radians(np.arange(0.0, 360.0, 10.0))
    fn(
        "machdyn.flywheel:size_flywheel",
        theta=theta,
        torque=20.0 + 5.0 * np.sin(2 * theta),
        omega_avg=50.0,
        k=0.05,
    )
    fn("machdyn.flywheel:disc_flywheel", inertia=2.0, density=7800.0, thickness=0.05)
    fw = lambda: __import__("machdyn.flywheel").flywheel.size_flywheel(  # noqa: E731
        theta, 20.0 + 5.0 * np.sin(2 * theta), 50.0, 0.05
    )
    meth("machdyn.flywheel:FlywheelResult.to_pandas", fw)
    meth("machdyn.flywheel:LobeTable.to_pandas", lambda: fw().lobes)
    unbalance = np.array([2.0j, 1.0 + 0.5j])
    fn("machdyn.balancing:static_balance", unbalance=unbalance)
    fn("machdyn.balancing:two_plane", unbalance=unbalance, z=[5.0, 8.0], plane_a=0.0, plane_b=10.0)
    fn("machdyn.balancing:shaking_force", unbalance=unbalance, omega=10.0)
    fn("machdyn.balancing:shaking_moment", unbalance=unbalance, z=[5.0, 8.0], omega=10.0)
    fn(
        "machdyn.balancing:bearing_balance",
        bearing_forces=[5 * np.exp(0.7j), 2 * np.exp(-2.1j)],
        z_bearings=[-14.0, -4.0],
        omega=10.0,
        plane_a=0.0,
        plane_b=7.0,
    )
    bal = __import__("machdyn.balancing").balancing
    meth("machdyn.balancing:StaticBalance.mass", lambda: bal.static_balance(unbalance), radius=2.0)
    two = lambda: bal.two_plane(unbalance, [5.0, 8.0], 0.0, 10.0)  # noqa: E731
    meth("machdyn.balancing:TwoPlaneBalance.masses", two, radius_a=2.0, radius_b=3.0)
    meth("machdyn.balancing:TwoPlaneBalance.to_pandas", two, radius_a=2.0, radius_b=3.0)
    for key in ("masses", "to_pandas"):
        c[f"machdyn.balancing:TwoPlaneBalance.{key}"].accepts["radius_b"] = {"none"}
    c["machdyn.balancing:TwoPlaneBalance.to_pandas"].accepts["radius_a"] = {"none"}
    mp = __import__("machdyn.massprops").massprops
    rotor = __import__("machdyn.rotor").rotor
    tensor = [[0.5, 0, -0.05], [0, 0.5, 0], [-0.05, 0, 0.9]]
    fn("machdyn.rotor:Rotor", mass=10.0, cg=(0.0, 0.0, 0.2), inertia=tensor, about="cg")
    c["machdyn.rotor:Rotor"].accepts["inertia"] = {"none"}
    masses = dict(masses=[1.0, 1.0], R=[0.1, -0.1j], z=[0.25, 0.75])
    fn("machdyn.rotor:Rotor.from_masses", **masses)
    rot = lambda: rotor.Rotor.from_masses(**masses)  # noqa: E731
    meth("machdyn.rotor:Rotor.with_masses", rot, masses=[0.5], R=[0.1j], z=[0.5])
    meth("machdyn.rotor:Rotor.is_balanced", rot, rtol=1e-12)
    meth("machdyn.rotor:Rotor.angular_momentum", rot, omega=100.0)
    meth("machdyn.rotor:Rotor.gyroscopic_moment", rot, omega=100.0)
    meth("machdyn.rotor:Rotor.bearing_reactions", rot, omega=10.0, z_a=0.0, z_b=1.0, alpha=1.0)
    meth("machdyn.rotor:Rotor.static_correction", rot)
    meth("machdyn.rotor:Rotor.two_plane_correction", rot, plane_a=0.0, plane_b=1.0)
    meth(
        "machdyn.rotor:BearingReactions.to_pandas",
        lambda: rot().bearing_reactions(10.0, 0.0, 1.0),
    )
    fn("machdyn.massprops:annulus", mass=2.0, outer_radius=2.0, inner_radius=1.0, centre=1 + 1j)
    fn("machdyn.massprops:disc", mass=2.0, radius=2.0, centre=1 + 1j)
    fn("machdyn.massprops:ring", mass=2.0, radius=2.0, centre=1 + 1j)
    fn("machdyn.massprops:plate", mass=2.0, width=2.0, height=1.0, centre=1 + 1j)
    fn("machdyn.massprops:point_mass", mass=2.0, at=1 + 1j)
    fn("machdyn.massprops:rod", mass=2.0, length=4.0, start=1j, angle=0.3)
    fn("machdyn.massprops:parallel_axis", inertia_g=2.0, mass=3.0, d=1.5)
    fn("machdyn.massprops:radius_of_gyration", inertia=2.0, mass=3.0)
    fn(
        "machdyn.massprops:cg_motion",
        theta=THETA,
        omega=2.0,
        alpha=1.0,
        cg=1 + 1j,
        origin=0j,
        origin_velocity=0j,
        origin_acceleration=0j,
    )
    fn(
        "machdyn.massprops:composite",
        Call(_mod("machdyn.massprops", "composite"), args=(mp.rod(1, 4), mp.disc(2, 1))),
    )
    meth("machdyn.massprops:MassProperties.inertia_about", lambda: mp.rod(1, 4), point=1 + 1j)
    meth(
        "machdyn.massprops:MassProperties.radius_of_gyration_about", lambda: mp.rod(1, 4), point=1j
    )
    meth("machdyn.massprops:MassProperties.moved", lambda: mp.rod(1, 4), offset=1j, angle=0.5)


def _add_elements(c, fn, meth) -> None:
    cams = __import__("machdyn.cams").cams
    x = np.linspace(0.0, 1.0, 7)
    for law in (
        "constant_velocity",
        "cycloidal",
        "dwell",
        "modified_sine",
        "modified_trapezoid",
        "poly345",
        "poly4567",
        "simple_harmonic",
    ):
        fn(f"machdyn.cams:{law}", x=x, h=1.5, beta=2.0)
    fn("machdyn.cams:fall", law="cycloidal", x=x, h=1.5, beta=2.0)
    fn("machdyn.cams:scca", x=x, h=1.0, beta=1.0, b=0.25, c=0.5, d=0.25)
    fn("machdyn.cams:scca_peak_factor", b=0.25, c=0.5, d=0.25)
    fn("machdyn.cams:get_law", name="cycloidal")
    fn("machdyn.cams:polynomial_law", start={"v": 0, "a": 0}, end={"v": 0, "a": 0})
    c["machdyn.cams:polynomial_law"].accepts.update(start={"none"}, end={"none"})
    law = lambda: cams.polynomial_law(start={"v": 0}, end={"v": 0})  # noqa: E731
    meth("machdyn.cams:PolynomialLaw.coefficients", law, h=1.0, beta=1.0)
    m = _motion()
    fn("machdyn.cams:pressure_angle", s=m.s, v=m.v, prime_radius=4.0, eccentricity=0.2)
    fn("machdyn.cams:radius_of_curvature", s=m.s, v=m.v, a=m.a, prime_radius=4.0)
    fn("machdyn.cams:pitch_curve", theta=m.theta, s=m.s, prime_radius=4.0)
    fn(
        "machdyn.cams:roller_surface",
        theta=m.theta,
        s=m.s,
        v=m.v,
        prime_radius=4.0,
        roller_radius=0.5,
    )
    fn("machdyn.cams:flat_face_radius_of_curvature", s=m.s, a=m.a, base_radius=4.0)
    fn("machdyn.cams:surface_self_intersection", theta=m.theta, surface=_profile().surface)
    fn(
        "machdyn.cams:cam_profile",
        program=_program(),
        follower=cams.TranslatingRoller(4.0, 0.5),
        n=90,
    )
    fn("machdyn.cams:size_roller", motion=_program(), roller_radius=0.5, n=90)
    fn("machdyn.cams:size_flat_face", motion=_program(), min_radius_of_curvature=0.5, n=90)
    fn(
        "machdyn.cams:size_oscillating_roller",
        motion=cams.CamProgram.double_dwell(math.radians(20), math.radians(90), math.radians(90)),
        roller_radius=0.3,
        pivot_distance=8.0,
        arm_length=5.0,
        n=90,
    )
    theta = np.radians([0, 60, 120, 180, 240, 300])
    lift = [0, 0.4, 1.0, 1.0, 0.5, 0.1]
    fn("machdyn.cams:CriticalPathMotion", theta=theta, s=lift, degree=5, smoothing=0.0)
    fn("machdyn.cams:CriticalPathMotion.from_degrees", theta_deg=np.degrees(theta), s=lift)
    cpm = lambda: cams.CriticalPathMotion(theta, lift)  # noqa: E731
    meth("machdyn.cams:CriticalPathMotion.svaj", cpm, theta=np.array([1.0, 2.0]))
    meth("machdyn.cams:CriticalPathMotion.sample", cpm, n=90)
    meth("machdyn.cams:CriticalPathMotion.continuity", cpm, rtol=1e-9)
    fn("machdyn.cams:CamProgram", segments=list(_program().segments))
    fn("machdyn.cams:CamProgram.double_dwell", h=1.0, beta_rise=1.0, beta_fall=1.0, law="cycloidal")
    c["machdyn.cams:CamProgram.double_dwell"].accepts.update(dwell_high={"none"}, fall_law={"none"})
    meth("machdyn.cams:CamProgram.svaj", _program, theta=np.linspace(0, 6, 7))
    meth("machdyn.cams:CamProgram.sample", _program, n=90)
    meth("machdyn.cams:CamProgram.continuity", _program, rtol=1e-9)
    meth("machdyn.cams:ContinuityReport.lines", lambda: _program().continuity())
    meth("machdyn.cams:Motion.in_time", _motion, omega=10.0)
    meth("machdyn.cams:Motion.peaks", _motion)
    meth("machdyn.cams:Motion.to_pandas", _motion)
    meth("machdyn.cams:TimeMotion.peaks", lambda: _motion().in_time(10.0))
    meth("machdyn.cams:TimeMotion.to_pandas", lambda: _motion().in_time(10.0))
    fn("machdyn.cams:Segment", motion="rise", beta=1.0, h=1.0, law="cycloidal")
    meth("machdyn.cams:Segment.evaluate", lambda: cams.Segment("rise", 1.0, 1.0, "cycloidal"), x=x)
    for name, kw in (
        ("TranslatingRoller", dict(prime_radius=4.0, roller_radius=0.5, eccentricity=0.2)),
        ("TranslatingFlatFace", dict(base_radius=4.0, eccentricity=0.2)),
        (
            "OscillatingRoller",
            dict(prime_radius=2.0, roller_radius=0.3, pivot_distance=4.0, arm_length=3.5),
        ),
    ):
        fn(f"machdyn.cams:{name}", **kw)
        program = (
            _program()
            if name != "OscillatingRoller"
            else c["machdyn.cams:size_oscillating_roller"].kwargs["motion"]
        )
        meth(
            f"machdyn.cams:{name}.profile",
            lambda n=name, k=kw: getattr(cams, n)(**k),
            motion=program,
            n=90,
        )
    for method in ("undercut_ranges", "surface_loop_ranges", "checks", "to_pandas"):
        meth(f"machdyn.cams:CamProfile.{method}", _profile)
    c["machdyn.cams:CamProfile.checks"].accepts["face_width"] = {"none"}
    meth(
        "machdyn.cams:SurfaceSelfIntersection.ranges",
        lambda: cams.surface_self_intersection(m.theta, _profile().surface),
    )
    meth(
        "machdyn.cams:SurfaceSelfIntersection.to_pandas",
        lambda: cams.surface_self_intersection(m.theta, _profile().surface),
    )
    meth(
        "machdyn.cams:Discontinuity.describe",
        lambda: (
            cams.CamProgram.double_dwell(1.0, 1.0, 1.0, law="shm").continuity().discontinuities[0]
        ),
    )
    meth("machdyn.cams:DesignCheck.line", lambda: _profile().checks()[0])
    _add_gears(c, fn, meth)


def _add_gears(c, fn, meth) -> None:
    gears = __import__("machdyn.gears").gears
    phi = math.radians(20)
    fn("machdyn.gears:Gear", teeth=24, diametral_pitch=8.0)
    c["machdyn.gears:Gear"].accepts.update(module={"none"}, diametral_pitch={"none"})
    meth("machdyn.gears:Gear.thickness_at", _gear, radius=1.55)
    meth("machdyn.gears:Gear.outline", _gear, points=20)
    meth("machdyn.gears:Gear.summary", _gear)
    fn("machdyn.gears:GearPair", pinion=_gear(24), gear=_gear(60))
    c["machdyn.gears:GearPair"].accepts["center_distance"] = {"none"}
    meth("machdyn.gears:GearPair.with_center_distance", _pair, center_distance=5.3)
    meth("machdyn.gears:GearPair.with_driver", _pair, driver="gear")
    meth("machdyn.gears:GearPair.to_pandas", _pair)
    meth("machdyn.gears:GearPair.summary", _pair)
    fn(
        "machdyn.gears:backlash_from_center_distance",
        center_distance_increase=0.1,
        pressure_angle=phi,
    )
    fn("machdyn.gears:base_pitch", pitch_radius=1.5, teeth=24, pressure_angle=phi)
    fn("machdyn.gears:belt_ratio", driver_diameter=2.0, driven_diameter=5.0)
    fn("machdyn.gears:chain_ratio", driver_teeth=12, driven_teeth=30)
    fn("machdyn.gears:contact_ratio", length_of_action=0.6, base_pitch=0.37)
    fn("machdyn.gears:contact_ratio_rating", contact_ratio=1.6)
    ring = gears.Gear(60, module=2.0, internal=True, profile_shift=0.25)
    fn("machdyn.gears:cutter_teeth_range", gear=ring)
    fn("machdyn.gears:default_cutter_teeth", gear=ring)
    fn("machdyn.gears:default_tip_radius", gear=_gear())
    fn("machdyn.gears:gear_outline", gear=_gear(), points=20, rotation=0.3, center=(1.0, 2.0))
    c["machdyn.gears:gear_outline"].accepts.update(tip_radius={"none"}, cutter_teeth={"none"})
    fn("machdyn.gears:inverse_involute", value=0.0149)
    fn("machdyn.gears:involute", phi=phi)
    fn(
        "machdyn.gears:length_of_action",
        r_gear=3.75,
        a_gear=0.125,
        r_pinion=1.5,
        a_pinion=0.125,
        pressure_angle=phi,
    )
    c["machdyn.gears:length_of_action"].accepts["center_distance"] = {"none"}
    fn("machdyn.gears:max_gear_teeth", pinion_teeth=15, pressure_angle=phi)
    fn("machdyn.gears:mesh_outlines", pair=_pair(), pinion_angle=0.1, points=20)
    c["machdyn.gears:mesh_outlines"].accepts["cutter_teeth"] = {"none"}
    fn("machdyn.gears:min_pinion_teeth", gear_teeth=60, pressure_angle=phi)
    fn("machdyn.gears:min_profile_shift", teeth=12, pressure_angle=phi)
    fn("machdyn.gears:min_teeth_equal_gears", pressure_angle=phi)
    fn("machdyn.gears:min_teeth_rack", pressure_angle=phi)
    fn("machdyn.gears:onset_gear_teeth", pinion_teeth=15, pressure_angle=phi)
    fn(
        "machdyn.gears:operating_pressure_angle",
        standard_center_distance=5.25,
        center_distance=5.3,
        pressure_angle=phi,
    )
    fn("machdyn.gears:reverted_compound", ratio=18.0)
    fn("machdyn.gears:simple_train_value", teeth=[20, 40, 30])
    fn("machdyn.gears:sprocket_pitch_diameter", pitch=0.5, teeth=20)
    fn("machdyn.gears:stage_ratio", driver=20, driven=40, kind="external")
    fn(
        "machdyn.gears:tooth_thickness_at",
        radius=1.55,
        pitch_radius=1.5,
        thickness=0.19,
        pressure_angle=phi,
    )
    fn("machdyn.gears:train_value", stages=[(14, 54), (14, 56)])
    fn("machdyn.gears:undercut", teeth=12, pressure_angle=phi)
    fn("machdyn.gears:willis", train_value=-0.5, first=100.0, arm=-200.0)
    c["machdyn.gears:willis"].accepts.update(first={"none"}, last={"none"}, arm={"none"})
    train = lambda: gears.PlanetaryTrain.simple(sun=40, planet=20, ring=80)  # noqa: E731
    fn("machdyn.gears:PlanetaryTrain", chain=[(40, 20), (20, 80, "internal")])
    fn("machdyn.gears:PlanetaryTrain.simple", sun=40, planet=20, ring=80)
    meth("machdyn.gears:PlanetaryTrain.table", train, arm=-200.0, sun=100.0)
    meth("machdyn.gears:PlanetaryTrain.speeds", train, arm=-200.0, sun=100.0)
    meth("machdyn.gears:PlanetaryTrain.ratio", train, driver="sun", driven="arm", fixed="ring")
    meth("machdyn.gears:PlanetaryTable.to_pandas", lambda: train().table(arm=1.0, sun=2.0))
    fn("machdyn.gears:mesh_forces", pair=_pair(), torque=300.0, member="pinion")
    fn(
        "machdyn.gears:train_power",
        train=gears.GearTrain([(18, 54), (20, 60)]),
        omega_in=10.0,
        torque_in=2.0,
    )
    fn(
        "machdyn.gears:planetary_power",
        train=train(),
        speeds={"arm": -200.0, "sun": 100.0},
        torque={"sun": 10.0},
    )
    rev = lambda: gears.reverted_compound(18.0)  # noqa: E731
    meth("machdyn.gears:RevertedTrain.to_pandas", rev)
    meth("machdyn.gears:RevertedTrain.center_distance", rev, module=2.0)
    meth("machdyn.gears:GearOutline.to_pandas", lambda: _gear().outline(points=10))


def _add_design(c, fn, meth) -> None:
    syn = __import__("machdyn.synthesis").synthesis
    fb = __import__("machdyn").FourBar
    placed = lambda: syn.PlacedFourBar(fb(5, 2, 5, 4, coupler=(3.0, 0.6)), 1 + 2j, 0.3, 1)  # noqa: E731
    cc = [0 + 5.086j, 2.019 + 3.181j, 3.933 + 4.051j]
    dd = [0.741 + 2.703j, 4.428 + 2.529j, 6.304 + 4.83j]
    fn("machdyn.synthesis:atlas", r1=[2.0, 3.0], r3=2.5, r4=2.0, p=1.0, delta=0.3, n=36)
    fn("machdyn.synthesis:chebyshev_spacing", x0=1.0, xf=2.0, n=3)
    fn("machdyn.synthesis:circumcentre", p1=0j, p2=1 + 0j, p3=1j)
    fn(
        "machdyn.synthesis:coupler_points",
        r1=5.0,
        r2=2.0,
        r3=5.0,
        r4=4.0,
        p=3.0,
        delta=0.6,
        theta2=THETA,
    )
    fn("machdyn.synthesis:driving_dyad", pivot=0j, b1=1 + 0j, b2=1j, distance=2.0)
    k = syn.freudenstein_coefficients(
        np.radians([45.0, 75.0, 105.0]), np.radians([135.0, 180.0, 225.0])
    )
    fn(
        "machdyn.synthesis:freudenstein_coefficients",
        theta2=np.radians([45.0, 75.0, 105.0]),
        theta4=np.radians([135.0, 180.0, 225.0]),
    )
    fn(
        "machdyn.synthesis:function_generator",
        func=np.log10,
        x_range=(1.0, 2.0),
        theta2_range=np.radians((45, 105)),
        theta4_range=np.radians((135, 225)),
    )
    c["machdyn.synthesis:function_generator"].accepts["x_precision"] = {"none"}
    fn("machdyn.synthesis:intersect_lines", p1=0j, u1=1 + 0j, p2=1j, u2=1 + 1j)
    fn("machdyn.synthesis:lengths_from_freudenstein", k=k, r1=1.0)
    targets = placed().pose(np.radians([0, 60, 120, 180, 240, 300]))[2]
    fn(
        "machdyn.synthesis:path_objective",
        x=np.array([1.0, 0.4, 1.0, 0.8, 0.6, 0.12, 0.2, 0.4, 0.06, 1.0]),
        targets=targets,
        n=24,
    )
    c["machdyn.synthesis:path_objective"].accepts.update(
        timing={"none"}, scale={"none"}, centre={"none"}
    )
    fn("machdyn.synthesis:perpendicular_bisector", p=0j, q=1 + 1j)
    fn("machdyn.synthesis:quick_return", swing=math.radians(60), time_ratio=1.25, n=201)
    fn("machdyn.synthesis:rigid_motion", c_from=0j, d_from=1 + 0j, c_to=1j, d_to=1 + 1j)
    fn("machdyn.synthesis:rotopole", c1=0j, d1=1 + 0j, c2=1j, d2=2j)
    fn("machdyn.synthesis:rotopole_link", c=[0j, 1j], d=[1 + 0j, 2j])
    fn(
        "machdyn.synthesis:synthesize_path",
        targets=targets,
        popsize=5,
        maxiter=3,
        n=24,
        polish=False,
    )
    c["machdyn.synthesis:synthesize_path"].accepts.update(
        timing={"none"}, tolerance={"none"}, seed={"none"}
    )
    c["machdyn.synthesis:synthesize_path"].skip["polish"] = (
        "True is valid and runs a full local search (seconds); other values are refused"
    )
    fn("machdyn.synthesis:three_position", c=cc, d=dd)
    c["machdyn.synthesis:three_position"].accepts.update(A={"none"}, B={"none"})
    fn("machdyn.synthesis:three_position_fixed_pivots", c=cc, d=dd, O2=-1 + 0.5j, O4=7 + 0.5j)
    fn("machdyn.synthesis:time_ratio_angle", time_ratio=1.25)
    fn("machdyn.synthesis:two_position", c=[0j, 2 + 0j], d=[1j, 2 + 1j], s2=3.0, s4=3.0)
    c["machdyn.synthesis:two_position"].accepts.update(A={"none"}, B={"none"})
    fn("machdyn.synthesis:PlacedFourBar", fourbar=fb(5, 2, 5, 4), O2=1 + 2j, theta1=0.3, branch=1)
    fn("machdyn.synthesis:PlacedFourBar.from_pivots", O2=1j, O4=1j + 8, A=1j + 4, B=1j + 8 + 6j)
    c["machdyn.synthesis:PlacedFourBar.from_pivots"].accepts["P"] = {"none"}
    meth("machdyn.synthesis:PlacedFourBar.to_global", placed, z=np.array([1 + 1j, 2j]))
    meth("machdyn.synthesis:PlacedFourBar.to_local", placed, z=np.array([1 + 1j, 2j]))
    meth("machdyn.synthesis:PlacedFourBar.theta2_of", placed, A=np.array([1 + 3j]))
    meth("machdyn.synthesis:PlacedFourBar.pose", placed, theta2=THETA)
    at = lambda: syn.atlas([2.0, 3.0], 2.5, 2.0, 1.0, 0.3, n=36)  # noqa: E731
    meth("machdyn.synthesis:CouplerAtlas.to_pandas", at)

    def gen():
        return syn.function_generator(
            np.log10, (1.0, 2.0), np.radians((45, 105)), np.radians((135, 225))
        )

    meth("machdyn.synthesis:FunctionGenerator.theta2_of", gen, x=np.array([1.2, 1.5]))
    meth("machdyn.synthesis:FunctionGenerator.theta4_of", gen, y=np.array([0.1, 0.2]))
    meth("machdyn.synthesis:FunctionGenerator.structural_error", gen, n=21)
    c["machdyn.synthesis:FunctionGenerator.structural_error"].accepts["x"] = {"none"}
    meth("machdyn.synthesis:StructuralError.to_pandas", lambda: gen().structural_error(n=11))
    three = lambda: syn.three_position(cc, dd)  # noqa: E731
    meth("machdyn.synthesis:MotionSynthesis.require_ok", three)
    meth("machdyn.synthesis:MotionSynthesis.driving_dyad", three, distance=2.0)
    meth("machdyn.synthesis:MotionSynthesis.to_pandas", three, degrees=True)
    path = lambda: syn.synthesize_path(targets, popsize=5, maxiter=3, n=24, polish=False)  # noqa: E731
    meth("machdyn.synthesis:PathSynthesis.curve", path, n=36)
    _add_atlas(c, fn, meth, targets)


_ATLAS: list = []


def _tiny_atlas():
    """A 400-entry four-bar atlas in a temporary folder, built once per session."""
    import tempfile

    syn = __import__("machdyn.synthesis").synthesis
    if not _ATLAS:
        folder = tempfile.mkdtemp(prefix="machdyn_fuzz_atlas_")
        syn.build_atlas(folder, 400, chunk_size=200, progress=False)
        _ATLAS.append(syn.open_atlas(folder))
    return _ATLAS[0]


def _in_temporary_folder(func):
    """``func`` run with a fresh temporary working directory (a build writes where told)."""
    import functools
    import os
    import tempfile

    @functools.wraps(func)
    def call(*args, **kwargs):
        here = os.getcwd()
        with tempfile.TemporaryDirectory(prefix="machdyn_fuzz_") as tmp:
            os.chdir(tmp)
            try:
                return func(*args, **kwargs)
            finally:
                os.chdir(here)

    return call


def _add_atlas(c, fn, meth, targets) -> None:
    syn = __import__("machdyn.synthesis").synthesis
    build = lambda: _in_temporary_folder(syn.build_atlas)  # noqa: E731
    fn(
        "machdyn.synthesis:build_atlas",
        Call(build, dict(path="a", count=20, chunk_size=20, progress=False)),
    )
    c["machdyn.synthesis:build_atlas"].accepts.update(
        path={"text"}, scheduler={"none"}, workers={"none"}
    )
    fn("machdyn.synthesis:open_atlas", path=str(_tiny_atlas().path))
    c["machdyn.synthesis:open_atlas"].accepts["path"] = {"text"}
    fn("machdyn.synthesis:curve_descriptor", z=np.exp(1j * np.linspace(0, 6, 40)) + 0.2)
    coupled = __import__("machdyn.fourbar").fourbar.FourBar(5.0, 2.0, 5.0, 4.0, coupler=(3.0, 0.6))
    fn("machdyn.synthesis:cognates", linkage=syn.PlacedFourBar(coupled, 1 + 2j, 0.3, 1))
    fn(
        "machdyn.synthesis:path_from_atlas",
        targets=targets,
        atlas=_tiny_atlas(),
        n=1,
        retrieve=5,
        refine_count=1,
    )
    c["machdyn.synthesis:path_from_atlas"].accepts.update(
        atlas={"text"}, timing={"none"}, tolerance={"none"}, client={"none"}, O2={"complex"},
        time_limit={"seconds"},
    )  # fmt: skip
    meth("machdyn.synthesis:Atlas.entries", _tiny_atlas, index=[0, 5, 399])
    meth("machdyn.synthesis:Atlas.nearest", _tiny_atlas, descriptor=_tiny_atlas().desc[0][3], k=3)
    c["machdyn.synthesis:Atlas.nearest"].accepts["client"] = {"none"}
    meth("machdyn.synthesis:Atlas.pool", _tiny_atlas, size=10, draw=1)


def _add_general(c, fn, meth) -> None:
    lk = _linkage
    fn("machdyn.linkage:Linkage", points={"O2": (0, 0), "A": (1, 0)})
    c["machdyn.linkage:Linkage"].accepts["points"] = {"none"}
    meth("machdyn.linkage:Linkage.point", lk, name="P", xy=(1.0, 2.0))
    c["machdyn.linkage:Linkage.point"].accepts["xy"] = {"complex"}  # x + yj is a point
    meth("machdyn.linkage:Linkage.position", lk, name="A")
    meth("machdyn.linkage:Linkage.mobility", lk)
    meth("machdyn.linkage:Linkage.loop_system", lk)
    meth("machdyn.linkage:Linkage.solve", lk, values=THETA, velocity=10.0, acceleration=1.0)
    c["machdyn.linkage:Linkage.solve"].accepts.update(velocity={"none"}, continuation={"none"})
    lm = lambda: _linkage().solve(THETA, 10.0, 1.0)  # noqa: E731
    meth("machdyn.linkage:Linkage.forces", lk, motion=lm(), gravity=9.81)
    meth("machdyn.linkage:LinkageMotion.angle", lm, link="coupler")
    meth("machdyn.linkage:LinkageMotion.to_pandas", lm)
    lf = lambda: _linkage().forces(lm())  # noqa: E731
    meth("machdyn.linkage:LinkageForces.F", lf, a="crank", p="coupler")
    meth("machdyn.linkage:LinkageForces.to_pandas", lf)
    meth("machdyn.linkage:Linkage.transmission_angles", lk, motion=lm())
    meth("machdyn.linkage:Linkage.flipped", lk, group="RRR dyad (coupler, rocker)")

    def base():
        return (
            __import__("machdyn.linkage")
            .linkage.Linkage(
                {"O2": (0, 0), "O4": (8, 0), "A": (4, 0), "B": (7.0, 3.0), "C": (3.0, 3.0)}
            )
            .ground("O2", "O4")
        )

    c["machdyn.linkage:Linkage.ground"] = Call(_attr(base, "ground"), args=("O2",))
    c["machdyn.linkage:Linkage.link"] = Call(
        _attr(base, "link"),
        {"mass": 1.0, "inertia": 0.2, "cg": 1 + 0.5j},
        args=("crank", "O2", "A"),
    )
    for opt in ("mass", "inertia", "cg", "body"):
        c["machdyn.linkage:Linkage.link"].accepts[opt] = {"none"}
    c["machdyn.linkage:Linkage.drive"] = Call(_attr(lk, "drive"), args=("crank",))
    with_links = lambda: base().link("crank", "O2", "A").link("arm", "O4", "B")  # noqa: E731
    meth(
        "machdyn.linkage:Linkage.slider",
        with_links,
        block="arm",
        on="ground",
        at="B",
        direction=0.3,
    )
    meth("machdyn.linkage:Linkage.slot", with_links, pin="A", link="crank", on="arm", direction=0.3)
    meth("machdyn.linkage:Linkage.actuator", base, name="cyl", start="O2", end="A")
    meth(
        "machdyn.linkage:Linkage.roll",
        with_links,
        link_a="crank",
        centre_a="O2",
        radius_a=3.0,
        link_b="arm",
        centre_b="O4",
        radius_b=5.0,
    )
    meth("machdyn.linkage:Linkage.motor", base, name="m", at="O2")
    meth(
        "machdyn.linkage:Linkage.spring",
        base,
        name="k",
        start="O2",
        end="B",
        stiffness=10.0,
        free_length=5.0,
    )
    meth(
        "machdyn.linkage:Linkage.torsion_spring",
        base,
        name="k",
        at="O2",
        stiffness=10.0,
        free_angle=0.3,
    )
    for key in ("slider", "slot", "roll", "motor"):
        for opt in ("through", "name", "links"):
            c[f"machdyn.linkage:Linkage.{key}"].accepts[opt] = {"none"}
    c["machdyn.linkage:Linkage.torsion_spring"].accepts["links"] = {"none"}
    c["machdyn.linkage:Linkage.solve"].accepts["jerk"] = {"none"}
    _add_dyads(c, fn)
    s = _loops
    fn("machdyn.loops:LoopSystem")
    meth(
        "machdyn.loops:LoopSystem.vector",
        lambda: __import__("machdyn.loops").loops.LoopSystem(),
        name="R1",
        length=8.0,
        angle=0.0,
    )
    meth("machdyn.loops:LoopSystem.loop", lambda: _loops_vectors(), text="R2 + R3 - R4 - R1")
    meth(
        "machdyn.loops:LoopSystem.constraint",
        lambda: _loops_vectors(),
        text="theta4 = theta3 + 0.2",
    )
    meth("machdyn.loops:LoopSystem.point", s, name="P", chain="R2")
    meth("machdyn.loops:LoopSystem.check", s)
    c["machdyn.loops:LoopSystem.check"].accepts["inputs"] = {"none"}
    c["machdyn.loops:LoopSystem.inputs"] = Call(
        _attr(lambda: _loops_vectors().loop("R2 + R3 - R4 - R1"), "inputs"), args=("theta2",)
    )
    meth(
        "machdyn.loops:LoopSystem.solve",
        s,
        values={"theta2": THETA},
        guess={"theta3": 0.5, "theta4": 1.5},
        velocity={"theta2": 10.0},
    )
    for opt in ("velocity", "acceleration", "jerk", "continuation"):
        c["machdyn.loops:LoopSystem.solve"].accepts[opt] = {"none"}
    t3, t4 = _fb_angles()
    meth(
        "machdyn.loops:LoopSystem.evaluate", s, values={"theta2": THETA, "theta3": t3, "theta4": t4}
    )
    for opt in ("velocity", "acceleration", "jerk"):
        c["machdyn.loops:LoopSystem.evaluate"].accepts[opt] = {"none"}
    meth(
        "machdyn.loops:Motion.to_pandas",
        lambda: _loops().solve({"theta2": THETA}, {"theta3": 0.5, "theta4": 1.5}),
    )
    a = np.array([[[2.0], [1.0]], [[4.0], [3.0]]])
    fn("machdyn.loops:lu_factor", a=a)
    c["machdyn.loops:lu_factor"].accepts.update(row_scale={"none"}, col_scale={"none"})
    fn(
        "machdyn.loops:lu_solve",
        f=__import__("machdyn.loops").loops.lu_factor(a),
        b=np.array([[3.0], [7.0]]),
    )


def _loops_vectors():
    from machdyn.loops import LoopSystem

    s = LoopSystem().vector("R1", 8.0, 0.0).vector("R2", 4.0, "theta2")
    return s.vector("R3", 7.0, "theta3").vector("R4", 6.0, "theta4")


def _on_circle(centre: str, radius: str):
    """Check of a dyad solver: where ok, the pin is at ``radius`` from ``centre``."""

    def check(result, kw) -> None:
        ok = np.asarray(result.ok)
        B = np.broadcast_to(result.B, ok.shape)
        A = np.broadcast_to(np.asarray(kw[centre], complex), ok.shape)
        a = np.broadcast_to(np.asarray(kw[radius], float), ok.shape)
        assert np.allclose(np.abs(B - A)[ok], a[ok], rtol=1e-9), "pin off its circle"

    return check


def _add_dyads(c, fn) -> None:
    """The closed-form dyads of machdyn.linkage.dyads (each with an independent check)."""
    d = "machdyn.linkage.dyads"
    fn(f"{d}:rrr", A=0j, C=5 + 0j, a=3.0, b=np.array([4.0, 2.5]), sign=1)
    c[f"{d}:rrr"].check = _on_circle("C", "b")
    fn(f"{d}:rrp", A=2j, a=6.0, G=0j, u=1 + 0j, sign=np.array([1, -1]))
    c[f"{d}:rrp"].check = _on_circle("A", "a")
    fn(f"{d}:rpr", A=0j, C=np.array([3 + 4j, 1 + 0j]), e=0.5, sign=1)

    def rpr_check(result, kw) -> None:
        ok = np.asarray(result.ok)
        C = np.broadcast_to(np.asarray(kw["C"], complex), ok.shape)
        A = np.broadcast_to(np.asarray(kw["A"], complex), ok.shape)
        e = np.broadcast_to(np.asarray(kw["e"], float), ok.shape)
        u = np.broadcast_to(result.u, ok.shape)
        off = ((C - A) * np.conj(u)).imag  # signed distance of A from the line through C
        assert np.allclose(off[ok], e[ok], atol=1e-9 * (1 + np.abs(C - A)[ok]).max(initial=1))

    c[f"{d}:rpr"].check = rpr_check
    fn(f"{d}:line_line", G1=0j, u1=1 + 0j, G2=3 + 1j, u2=np.array([1j, 1 + 1j]))
    fn(f"{d}:solve_pair", c1=1 + 0j, c2=1j, k=np.array([2 + 3j, 1j]))
    for key in ("rrr", "rrp", "rpr", "line_line", "solve_pair"):
        for name in ("A", "C", "G", "u", "G1", "G2", "u1", "u2", "c1", "c2", "k"):
            c[f"{d}:{key}"].accepts.setdefault(name, set()).add("complex")
