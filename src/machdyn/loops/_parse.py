"""Parsing of the small text languages of the vector-loop core.

* loops and point chains: signed sums of vector names, ``"R2 + R3 - R4 - R1"``,
  ``"-R1 + R2 + R3 = 0"``, ``"R2 + R3 = R4 + R1"``;
* linear constraints: ``"theta3p = theta3 + alpha"``, ``"r2*theta2 + r3*theta3 = c"``.

Everything here is pure string handling; malformed text raises
:class:`~machdyn.errors.InputError` naming the field and the offending position.
"""

from __future__ import annotations

import re
from collections.abc import Mapping

from ..errors import InputError

__all__ = ["parse_linear", "parse_signed_sum"]

_NAME = r"[A-Za-z_][A-Za-z0-9_]*"
_NUMBER = r"(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?"
_TOKEN = re.compile(rf"\s*(?:(?P<name>{_NAME})|(?P<number>{_NUMBER})|(?P<op>[-+*=]))")


def _tokens(text: str, field: str) -> list[tuple[str, str, int]]:
    """Split ``text`` into (kind, value, position) tokens or raise naming the position."""
    out: list[tuple[str, str, int]] = []
    pos = 0
    stripped = text.rstrip()
    while pos < len(stripped):
        match = _TOKEN.match(stripped, pos)
        if match is None or match.end() == pos:
            raise InputError(field, f"cannot parse {text!r}: unexpected {stripped[pos:]!r}")
        kind = match.lastgroup or ""
        out.append((kind, match.group(kind), match.start(kind)))
        pos = match.end()
    return out


def _split_sides(text: str, field: str) -> list[list[tuple[str, str, int]]]:
    tokens = _tokens(text, field)
    sides: list[list[tuple[str, str, int]]] = [[]]
    for token in tokens:
        if token == ("op", "=", token[2]):
            sides.append([])
        else:
            sides[-1].append(token)
    if len(sides) > 2:
        raise InputError(field, f"cannot parse {text!r}: more than one '='")
    if any(not side for side in sides):
        raise InputError(field, f"cannot parse {text!r}: an empty side of '='")
    return sides


def _terms(side: list[tuple[str, str, int]], text: str, field: str) -> list[tuple[int, list]]:
    """Group one side into signed terms: (sign, [factor tokens])."""
    terms: list[tuple[int, list]] = []
    sign = 1
    factors: list = []
    expect_factor = True
    sign_seen = False
    for kind, value, pos in side:
        if kind == "op" and value in "+-":
            if expect_factor and (terms or factors or sign_seen):
                raise InputError(field, f"cannot parse {text!r}: unexpected {value!r} at {pos}")
            if not expect_factor:
                terms.append((sign, factors))
                factors = []
            sign = 1 if value == "+" else -1
            expect_factor = True
            sign_seen = True
        elif kind == "op" and value == "*":
            if expect_factor:
                raise InputError(field, f"cannot parse {text!r}: unexpected '*' at {pos}")
            expect_factor = True
        else:
            if not expect_factor:
                raise InputError(
                    field, f"cannot parse {text!r}: missing '+', '-' or '*' before {value!r}"
                )
            factors.append((kind, value))
            expect_factor = False
    if expect_factor:
        raise InputError(field, f"cannot parse {text!r}: it ends with an operator")
    terms.append((sign, factors))
    return terms


def parse_signed_sum(text: str, field: str = "loop") -> dict[str, int]:
    """Parse a signed sum of vector names into ``{name: coefficient}``.

    Both sides of an optional ``=`` are allowed (the right side is moved to the
    left); a right side of ``0`` is the usual loop-closure form.

    Examples
    --------
    >>> parse_signed_sum("R2 + R3 - R4 - R1")
    {'R2': 1, 'R3': 1, 'R4': -1, 'R1': -1}
    >>> parse_signed_sum("-R1 + R2 + R3 = 0")
    {'R1': -1, 'R2': 1, 'R3': 1}
    >>> parse_signed_sum("R2 + R3 = R1 + R4")
    {'R2': 1, 'R3': 1, 'R1': -1, 'R4': -1}
    """
    if not isinstance(text, str) or not text.strip():
        raise InputError(field, f"must be a signed sum of vector names, got {text!r}")
    out: dict[str, int] = {}
    for side_sign, side in zip((1, -1), _split_sides(text, field), strict=False):
        if len(side) == 1 and side[0][:2] == ("number", side[0][1]) and float(side[0][1]) == 0:
            continue
        for sign, factors in _terms(side, text, field):
            if len(factors) != 1 or factors[0][0] != "name":
                shown = "*".join(v for _, v in factors)
                raise InputError(
                    field,
                    f"cannot parse {text!r}: {shown!r} is not a vector name "
                    "(write a signed sum such as 'R2 + R3 - R4 - R1')",
                )
            name = factors[0][1]
            out[name] = out.get(name, 0) + side_sign * sign
    out = {name: coef for name, coef in out.items() if coef != 0}
    if not out:
        raise InputError(field, f"{text!r} names no vector (or all cancel)")
    return out


def parse_linear(
    text: str, constants: Mapping[str, float], field: str = "constraint"
) -> tuple[dict[str, float], float]:
    """Parse ``lhs = rhs``, linear in the variables, into ``({var: coef}, c0)``.

    The equation is ``sum(coef * var) + c0 = 0``. A name found in ``constants``
    is a constant; any other name is a variable. Each term is a product of
    numbers and constants with at most one variable.

    Examples
    --------
    >>> parse_linear("theta3p = theta3 + alpha", {"alpha": 0.5})
    ({'theta3p': 1.0, 'theta3': -1.0}, -0.5)
    >>> parse_linear("r2*theta2 + r3*theta3 = c", {"r2": 2.0, "r3": 3.0, "c": 1.0})
    ({'theta2': 2.0, 'theta3': 3.0}, -1.0)
    """
    if not isinstance(text, str) or "=" not in text:
        raise InputError(field, f"must be an equation 'lhs = rhs', got {text!r}")
    sides = _split_sides(text, field)
    coefs: dict[str, float] = {}
    c0 = 0.0
    for side_sign, side in zip((1.0, -1.0), sides, strict=True):
        for sign, factors in _terms(side, text, field):
            value = side_sign * sign
            variable = None
            for kind, token in factors:
                if kind == "number":
                    value *= float(token)
                elif token in constants:
                    value *= float(constants[token])
                elif variable is None:
                    variable = token
                else:
                    raise InputError(
                        field,
                        f"{text!r} is not linear: {variable}*{token} multiplies two "
                        "variables (give constants as keyword values)",
                    )
            if variable is None:
                c0 += value
            else:
                coefs[variable] = coefs.get(variable, 0.0) + value
    coefs = {name: coef for name, coef in coefs.items() if coef != 0.0}
    if not coefs:
        raise InputError(field, f"{text!r} contains no variable (every name is a constant)")
    return coefs, c0
