"""Exceptions raised by machdyn.

Every error machdyn raises on purpose derives from :class:`MachdynError`, so a
caller (or the CLI) can catch one type. Errors about a bad value also derive
from :class:`ValueError` and carry the name of the offending field.

Failures that belong to *one sample* of a sweep (a pose that cannot be
assembled, a toggle) are not raised: they are reported per sample in the
result's ``ok`` mask and ``reason`` array.
"""

from __future__ import annotations

__all__ = [
    "AssemblyError",
    "InputError",
    "MachdynError",
    "ModelError",
    "SingularityError",
    "UnknownNameError",
]


class MachdynError(Exception):
    """Base class of every error machdyn raises deliberately."""


class InputError(MachdynError, ValueError):
    """A parameter has a value machdyn cannot use.

    Parameters
    ----------
    field : str
        Name of the offending parameter, as the user wrote it.
    message : str
        What is wrong and what would be right.

    Examples
    --------
    >>> err = InputError("r2", "must be a positive length, got -1.0")
    >>> str(err)
    'r2: must be a positive length, got -1.0'
    >>> err.field
    'r2'
    """

    def __init__(self, field: str, message: str) -> None:
        self.field = field
        self.message = message
        super().__init__(f"{field}: {message}")


class UnknownNameError(InputError, KeyError):
    """A name (link, point, joint, variable) the model does not have.

    Also a :class:`KeyError`, as the mapping-style lookups that raise it
    (``motion.angle("coupler")``, ``forces.F("crank", "coupler")``) promise.

    Examples
    --------
    >>> err = UnknownNameError("link", "unknown link 'arm'; known: crank, rocker")
    >>> str(err)
    "link: unknown link 'arm'; known: crank, rocker"
    >>> isinstance(err, KeyError) and isinstance(err, InputError)
    True
    """

    def __str__(self) -> str:  # KeyError would quote the message
        return BaseException.__str__(self)


class ModelError(MachdynError, ValueError):
    """A mechanism model is structurally wrong.

    Unknown vector or variable names in a loop, an under- or over-determined
    system, a redundant formulation, a mobility that does not match the number
    of drivers.
    """


class AssemblyError(MachdynError, ValueError):
    """A mechanism cannot be assembled (at all, or at a requested input)."""


class SingularityError(MachdynError, ArithmeticError):
    """A linear system of the analysis is singular (a toggle or dead point)."""
