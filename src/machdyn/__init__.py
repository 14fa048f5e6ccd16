"""machdyn: kinematics and dynamics of machines — planar linkages, cams and gears.

The top level exposes the everyday entry points; topics with many functions
live in subpackages that are imported on first use (``machdyn.cams``,
``machdyn.gears``, ...), so ``import machdyn`` stays fast.

Examples
--------
>>> import machdyn
>>> machdyn.mobility(4, 4)
1
"""

from __future__ import annotations

import importlib
from typing import Any

from .classify import barker_class, classify, is_grashof
from .errors import AssemblyError, InputError, MachdynError, ModelError, SingularityError
from .fourbar import FourBar
from .mobility import Joint, mobility, mobility_of
from .sensitivity import sensitivity
from .simulate import simulate
from .slidercrank import InvertedSliderCrank, SliderCrank
from .tolerance import tolerance

__version__ = "0.1.0"

__all__ = [
    "AssemblyError",
    "FourBar",
    "InputError",
    "InvertedSliderCrank",
    "Joint",
    "MachdynError",
    "ModelError",
    "SingularityError",
    "SliderCrank",
    "__version__",
    "barker_class",
    "classify",
    "is_grashof",
    "mobility",
    "mobility_of",
    "sensitivity",
    "simulate",
    "tolerance",
]

# Subpackages and modules loaded lazily on attribute access.
_LAZY_MODULES = frozenset(
    {
        "balancing",
        "cams",
        "dynamics",
        "flywheel",
        "gears",
        "inversions",
        "linkage",
        "loops",
        "massprops",
        "plot",
        "rotor",
        "shaking",
        "spec",
        "synthesis",
        "units",
        "viewer",
        "virtual_work",
    }
)


#: Functions of lazily loaded modules offered at the top level.
_LAZY_FUNCTIONS = {"load": "spec", "from_spec": "spec"}


def __getattr__(name: str) -> Any:
    if name in _LAZY_MODULES:
        return importlib.import_module(f".{name}", __name__)
    if name in _LAZY_FUNCTIONS:
        return getattr(importlib.import_module(f".{_LAZY_FUNCTIONS[name]}", __name__), name)
    raise AttributeError(f"module 'machdyn' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(__all__) | _LAZY_MODULES | set(_LAZY_FUNCTIONS))
