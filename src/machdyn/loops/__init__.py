"""The general vector-loop solver: the notes' position/velocity method as a library.

Describe a mechanism by vectors ``d·e^{jθ}``, vector loops written as text,
linear constraints and named points; solve positions by batched Newton–Raphson
(with continuation along a sweep) and velocities, accelerations and jerks by one
linear solve per order.

Examples
--------
>>> import numpy as np
>>> from machdyn.loops import LoopSystem
>>> s = (LoopSystem()
...      .vector("R1", 8.0, 0.0).vector("R2", 4.0, "theta2")
...      .vector("R3", 7.0, "theta3").vector("R4", 6.0, "theta4")
...      .loop("R2 + R3 - R4 - R1").inputs("theta2"))
>>> s.check().dof
1
"""

from __future__ import annotations

from .model import LoopSystem, Vector
from .result import Motion, SystemReport
from .solve import lu_factor, lu_solve

__all__ = ["LoopSystem", "Motion", "SystemReport", "Vector", "lu_factor", "lu_solve"]
