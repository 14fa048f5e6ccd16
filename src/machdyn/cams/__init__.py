"""Cams: follower motion laws, cam programs, radial cam geometry and sizing.

Everything follows the notes' Chapter 8 (review lecture 3) and Norton,
*Design of Machinery*, Ch. 8. Angles are radians; lengths any consistent unit.

Examples
--------
>>> import numpy as np
>>> from machdyn import cams
>>> program = cams.CamProgram([
...     cams.Segment("rise", np.radians(60), 1.0, "cycloidal"),
...     cams.Segment("dwell", np.radians(120)),
...     cams.Segment("fall", np.radians(60), 1.0, "cycloidal"),
...     cams.Segment("dwell", np.radians(120)),
... ])
>>> cam = cams.TranslatingRoller(prime_radius=3.0, roller_radius=0.5).profile(program)
>>> [check.passed for check in cam.checks()]
[True, True, True]
>>> round(float(np.degrees(cams.pressure_angle(0.4, 1.2, 2.1, 0.1))), 2)
23.77
"""

from __future__ import annotations

from .critical_path import CriticalPathMotion
from .geometry import (
    CamProfile,
    DesignCheck,
    OscillatingRoller,
    SurfaceSelfIntersection,
    TranslatingFlatFace,
    TranslatingRoller,
    cam_profile,
    flat_face_radius_of_curvature,
    pitch_curve,
    pressure_angle,
    radius_of_curvature,
    roller_surface,
    surface_self_intersection,
)
from .io import write_csv, write_dxf
from .laws import (
    LAW_NAMES,
    LawValues,
    MotionLaw,
    PolynomialLaw,
    constant_velocity,
    cycloidal,
    dwell,
    fall,
    get_law,
    modified_sine,
    modified_trapezoid,
    poly345,
    poly4567,
    polynomial_law,
    scca,
    scca_peak_factor,
    simple_harmonic,
)
from .plot import plot_profile, plot_svaj
from .program import CamProgram, ContinuityReport, Discontinuity, Motion, Segment, TimeMotion
from .sizing import Sizing, size_flat_face, size_oscillating_roller, size_roller

__all__ = [
    "LAW_NAMES",
    "CamProfile",
    "CamProgram",
    "ContinuityReport",
    "CriticalPathMotion",
    "DesignCheck",
    "Discontinuity",
    "LawValues",
    "Motion",
    "MotionLaw",
    "OscillatingRoller",
    "PolynomialLaw",
    "Segment",
    "Sizing",
    "SurfaceSelfIntersection",
    "TimeMotion",
    "TranslatingFlatFace",
    "TranslatingRoller",
    "cam_profile",
    "constant_velocity",
    "cycloidal",
    "dwell",
    "fall",
    "flat_face_radius_of_curvature",
    "get_law",
    "modified_sine",
    "modified_trapezoid",
    "pitch_curve",
    "plot_profile",
    "plot_svaj",
    "poly345",
    "poly4567",
    "polynomial_law",
    "pressure_angle",
    "radius_of_curvature",
    "roller_surface",
    "scca",
    "scca_peak_factor",
    "simple_harmonic",
    "size_flat_face",
    "size_oscillating_roller",
    "size_roller",
    "surface_self_intersection",
    "write_csv",
    "write_dxf",
]
