"""A safe arithmetic language for user expressions, ``"log10(x)"``, ``"2*x**2 + sin(pi*x)"``.

The CLI (``machdyn synth function --f``) and machine files (function synthesis)
take a function of ``x`` as text. It is never handed to Python's ``eval``: the
text is parsed by :mod:`ast`, every node checked against a short whitelist
(numbers, the variable, ``+ - * / **``, unary signs, ``pi``, ``e`` and a few
functions of one argument), and the tree is evaluated by the small interpreter
below on float64 NumPy arrays. So ``9**9**9`` is ``inf`` at once, not a Python
integer with a billion digits, and no attribute, subscript, call of anything
else or name outside the list can be reached.

Size and time are bounded: at most :data:`MAX_LENGTH` characters and
:data:`MAX_NODES` syntax nodes; evaluating costs one array operation per node.
"""

from __future__ import annotations

import ast
from collections.abc import Callable
from typing import Any

import numpy as np

from .errors import InputError

__all__ = ["FUNCTIONS", "MAX_LENGTH", "MAX_NODES", "parse_function"]

#: Longest expression accepted, in characters.
MAX_LENGTH = 1000
#: Most syntax nodes accepted (numbers, names, operators and calls each count one).
MAX_NODES = 400

#: The functions an expression may call (one argument each).
FUNCTIONS: dict[str, Callable[[np.ndarray], np.ndarray]] = {
    "sin": np.sin,
    "cos": np.cos,
    "tan": np.tan,
    "asin": np.arcsin,
    "acos": np.arccos,
    "atan": np.arctan,
    "sinh": np.sinh,
    "cosh": np.cosh,
    "tanh": np.tanh,
    "exp": np.exp,
    "log": np.log,
    "log10": np.log10,
    "sqrt": np.sqrt,
    "abs": np.abs,
}
_CONSTANTS = {"pi": np.pi, "e": np.e}
_BINARY: dict[type, Callable[[Any, Any], Any]] = {
    ast.Add: np.add,
    ast.Sub: np.subtract,
    ast.Mult: np.multiply,
    ast.Div: np.divide,
    ast.Pow: np.power,
}
_UNARY: dict[type, Callable[[Any], Any]] = {ast.USub: np.negative, ast.UAdd: np.positive}


def parse_function(
    text: str, field: str = "--f", variable: str = "x"
) -> Callable[[np.ndarray], np.ndarray]:
    """Turn an expression in ``x`` into a function of a float array (safe: no ``eval``).

    Only numbers, ``x``, ``+ - * / **``, unary signs, ``pi``, ``e`` and the
    functions of :data:`FUNCTIONS` are accepted. The function returns float64
    values (``inf`` or NaN where the arithmetic overflows or is undefined; the
    caller decides what that means).

    Raises
    ------
    InputError
        Naming ``field``: text that is too long, not an expression, or uses
        anything outside the whitelist.

    Examples
    --------
    >>> f = parse_function("2*x**2 + sin(pi*x)")
    >>> round(float(f(np.array(1.0))), 12)
    2.0
    >>> float(parse_function("x + 9**9**9")(np.array(1.0)))
    inf
    >>> parse_function("__import__('os')")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: --f: only x, numbers, + - * / **, pi, e and sin, ... are allowed
    """
    if not isinstance(text, str):
        raise InputError(field, f"must be an expression in {variable} (text), got {text!r}")
    if len(text) > MAX_LENGTH:
        raise InputError(field, f"is {len(text)} characters long; at most {MAX_LENGTH} are read")
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except (SyntaxError, ValueError, RecursionError, MemoryError):
        raise InputError(field, f"cannot read {text!r} as an expression in {variable}") from None
    nodes = list(ast.walk(tree))
    if len(nodes) > MAX_NODES:
        raise InputError(field, f"has {len(nodes)} terms; at most {MAX_NODES} are evaluated")
    message = f"only {variable}, numbers, + - * / **, pi, e and {', '.join(FUNCTIONS)} are allowed"
    for node in nodes:
        _check(node, variable, field, message)
    body = tree.body

    def func(x: Any) -> np.ndarray:
        values = np.asarray(x, dtype=float)
        with np.errstate(all="ignore"):
            out = _evaluate(body, variable, values)
        return np.asarray(np.broadcast_to(out, values.shape), dtype=float)

    return func


def _check(node: ast.AST, variable: str, field: str, message: str) -> None:
    allowed = (ast.Expression, ast.BinOp, ast.UnaryOp, ast.Call, ast.Name, ast.Load, ast.Constant)
    ok = isinstance(node, allowed) or type(node) in _BINARY or type(node) in _UNARY
    if isinstance(node, ast.BinOp):
        ok = type(node.op) in _BINARY
    elif isinstance(node, ast.UnaryOp):
        ok = type(node.op) in _UNARY
    elif isinstance(node, ast.Name):
        ok = node.id in {variable, *FUNCTIONS, *_CONSTANTS}
    elif isinstance(node, ast.Call):
        ok = (
            isinstance(node.func, ast.Name)
            and node.func.id in FUNCTIONS
            and len(node.args) == 1
            and not node.keywords
        )
    elif isinstance(node, ast.Constant):
        ok = isinstance(node.value, int | float) and not isinstance(node.value, bool)
    if not ok:
        raise InputError(field, message)


def _evaluate(node: ast.AST, variable: str, x: np.ndarray) -> Any:
    """The value of a checked node: float64 arithmetic throughout (no Python integers)."""
    if isinstance(node, ast.Constant):
        return np.float64(float(node.value)) if abs(node.value) < 1e308 else np.float64(np.inf)
    if isinstance(node, ast.Name):
        return x if node.id == variable else np.float64(_CONSTANTS[node.id])
    if isinstance(node, ast.UnaryOp):
        return _UNARY[type(node.op)](_evaluate(node.operand, variable, x))
    if isinstance(node, ast.BinOp):
        left = _evaluate(node.left, variable, x)
        right = _evaluate(node.right, variable, x)
        return _BINARY[type(node.op)](left, right)
    assert isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
    return FUNCTIONS[node.func.id](_evaluate(node.args[0], variable, x))
