"""The safe expression language of `synth function --f` and machine files (machdyn._expression)."""

from __future__ import annotations

import time

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from machdyn import InputError
from machdyn._expression import MAX_LENGTH, MAX_NODES, parse_function

X = np.linspace(0.5, 3.0, 7)


@pytest.mark.parametrize(
    "text",
    [
        "__import__('os').system('true')",
        "x.__class__",
        "(lambda: 1)()",
        "[x for x in ()]",
        "x[0]",
        "open('f')",
        "sin(x, 2)",
        "sin(x=1)",
        "y + 1",
        "'a' * 3",
        "True + x",
        "x if x else 1",
        "x @ x",
        "x // 2",
        "x % 2",
        "x < 1",
        "print",
        "",
        "1 +",
    ],
)
def test_anything_outside_the_whitelist_is_refused(text):
    with pytest.raises(InputError) as err:
        parse_function(text)
    assert err.value.field == "--f"


def test_huge_powers_are_float_overflow_not_python_integers():
    """`9**9**9` in Python integers never finishes; here it is inf at once."""
    start = time.perf_counter()
    values = parse_function("x + 9**9**9")(X)
    assert np.all(np.isposinf(values))
    assert float(parse_function("2**-9**9**9")(1.0)) == 0.0
    assert np.isposinf(float(parse_function("1" + "0" * 400)(1.0)))  # a 401-digit literal
    assert time.perf_counter() - start < 30.0  # guards against a hang, not a timing


def test_size_is_bounded():
    with pytest.raises(InputError, match="characters"):
        parse_function("x+" * MAX_LENGTH + "x")
    with pytest.raises(InputError, match="terms"):
        parse_function("+".join(["x"] * (MAX_NODES // 2 + 10)))
    with pytest.raises(InputError):
        parse_function("(" * 300 + "x" + ")" * 300)  # nested too deep for the parser


def test_a_constant_broadcasts_to_the_samples():
    assert parse_function("2")(X).tolist() == [2.0] * X.size


# Random expressions, built twice from one recipe: as text for the parser and as a NumPy
# value computed directly (the independent check).
_LEAVES = st.sampled_from([("x", lambda x: x), ("pi", lambda x: np.pi), ("2.5", lambda x: 2.5)])
_UNARY = {"sin": np.sin, "cos": np.cos, "exp": np.exp, "sqrt": np.sqrt, "abs": np.abs}
_BINARY = {"+": np.add, "-": np.subtract, "*": np.multiply, "/": np.divide, "**": np.power}


def _extend(children):
    unary = st.tuples(st.sampled_from(sorted(_UNARY)), children).map(
        lambda t: (f"{t[0]}({t[1][0]})", lambda x, f=_UNARY[t[0]], g=t[1][1]: f(g(x)))
    )
    binary = st.tuples(children, st.sampled_from(sorted(_BINARY)), children).map(
        lambda t: (
            f"({t[0][0]}) {t[1]} ({t[2][0]})",
            lambda x, f=_BINARY[t[1]], a=t[0][1], b=t[2][1]: f(a(x), b(x)),
        )
    )
    negated = children.map(lambda t: (f"-({t[0]})", lambda x, g=t[1]: -g(x)))
    return unary | binary | negated


@given(st.recursive(_LEAVES, _extend, max_leaves=12))
def test_random_expressions_match_numpy(expression):
    text, direct = expression
    with np.errstate(all="ignore"):
        expected = np.broadcast_to(np.asarray(direct(X), dtype=float), X.shape)
    got = parse_function(text)(X)
    np.testing.assert_array_equal(got, expected)
