"""Synthesis of four-bar linkages: motion, function and path generation.

The notes' Ch. 3 (graphical synthesis, done algebraically) and Norton,
*Design of Machinery*, ch. 3 and 5.
"""

from __future__ import annotations

from .atlas import CouplerAtlas, atlas, coupler_points
from .atlas_path import Atlas, PathCandidates, open_atlas, path_from_atlas
from .atlas_store import AtlasError, build_atlas
from .cognates import cognates
from .descriptor import curve_descriptor
from .function import (
    FunctionGenerator,
    StructuralError,
    chebyshev_spacing,
    freudenstein_coefficients,
    function_generator,
    lengths_from_freudenstein,
)
from .geometry import circumcentre, intersect_lines, perpendicular_bisector, rigid_motion, rotopole
from .motion import (
    DrivingDyad,
    MotionSynthesis,
    RotopoleLink,
    driving_dyad,
    rotopole_link,
    three_position,
    three_position_fixed_pivots,
    two_position,
)
from .path import PathSynthesis, path_objective, synthesize_path
from .placed import PlacedFourBar
from .quick_return import QuickReturn, quick_return, time_ratio_angle
from .sixbar_path import SixBarPath

__all__ = [
    "Atlas",
    "AtlasError",
    "CouplerAtlas",
    "DrivingDyad",
    "FunctionGenerator",
    "MotionSynthesis",
    "PathCandidates",
    "PathSynthesis",
    "PlacedFourBar",
    "QuickReturn",
    "RotopoleLink",
    "SixBarPath",
    "StructuralError",
    "atlas",
    "build_atlas",
    "chebyshev_spacing",
    "circumcentre",
    "cognates",
    "coupler_points",
    "curve_descriptor",
    "driving_dyad",
    "freudenstein_coefficients",
    "function_generator",
    "intersect_lines",
    "lengths_from_freudenstein",
    "open_atlas",
    "path_from_atlas",
    "path_objective",
    "perpendicular_bisector",
    "quick_return",
    "rigid_motion",
    "rotopole",
    "rotopole_link",
    "synthesize_path",
    "three_position",
    "three_position_fixed_pivots",
    "time_ratio_angle",
    "two_position",
]
