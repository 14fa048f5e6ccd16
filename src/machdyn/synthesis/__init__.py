"""Synthesis of four-bar linkages: motion, function and path generation.

The notes' Ch. 3 (graphical synthesis, done algebraically) and Norton,
*Design of Machinery*, ch. 3 and 5.
"""

from __future__ import annotations

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
from .placed import PlacedFourBar

__all__ = [
    "DrivingDyad",
    "FunctionGenerator",
    "MotionSynthesis",
    "PlacedFourBar",
    "RotopoleLink",
    "StructuralError",
    "chebyshev_spacing",
    "circumcentre",
    "driving_dyad",
    "freudenstein_coefficients",
    "function_generator",
    "intersect_lines",
    "lengths_from_freudenstein",
    "perpendicular_bisector",
    "rigid_motion",
    "rotopole",
    "rotopole_link",
    "three_position",
    "three_position_fixed_pivots",
    "two_position",
]
