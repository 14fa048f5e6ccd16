"""``machdyn synth ...``: three-position motion generation and function generation.

Registered by the application as ``app.add_typer(synth_app, name="synth")``.
Only parsing and presentation live here; the synthesis is
:mod:`machdyn.synthesis`. Angles are in degrees on the command line.
"""

from __future__ import annotations

import ast
from collections.abc import Callable
from typing import Annotated

import numpy as np
import typer

from ..errors import AssemblyError, InputError
from ._common import dumps, print_table

__all__ = ["parse_function", "parse_points", "synth_app"]

synth_app = typer.Typer(
    name="synth",
    help="Synthesis of four-bars: three-position motion generation, function generation.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)


def parse_points(text: str, field: str, count: int) -> list[complex]:
    """Parse ``"x,y; x,y; ..."`` into complex points.

    Examples
    --------
    >>> parse_points("0,5.086; 2.019,3.181", "--c", 2)
    [5.086j, (2.019+3.181j)]
    """
    parts = [p for p in text.replace("\n", ";").split(";") if p.strip()]
    points = []
    for part in parts:
        xy = part.replace(" ", "").split(",")
        try:
            x, y = (float(v) for v in xy)
        except ValueError:
            raise InputError(field, f"expected 'x,y; x,y; ...', could not read {part!r}") from None
        points.append(complex(x, y))
    if len(points) != count:
        raise InputError(field, f"expected {count} points 'x,y; x,y; x,y', got {len(points)}")
    return points


_FUNCTIONS: dict[str, Callable] = {
    "sin": np.sin,
    "cos": np.cos,
    "tan": np.tan,
    "exp": np.exp,
    "log": np.log,
    "log10": np.log10,
    "sqrt": np.sqrt,
    "abs": np.abs,
}
_CONSTANTS = {"pi": np.pi, "e": np.e}
_ALLOWED_NODES = (
    ast.Expression,
    ast.BinOp,
    ast.UnaryOp,
    ast.Call,
    ast.Name,
    ast.Load,
    ast.Constant,
    ast.Add,
    ast.Sub,
    ast.Mult,
    ast.Div,
    ast.Pow,
    ast.USub,
    ast.UAdd,
)


def parse_function(text: str) -> Callable[[np.ndarray], np.ndarray]:
    """Turn an expression in ``x`` (e.g. ``"log10(x)"``, ``"x**1.5"``) into a function.

    Only arithmetic, numbers, ``x``, ``pi``, ``e`` and the functions
    sin, cos, tan, exp, log, log10, sqrt, abs are accepted.

    Examples
    --------
    >>> f = parse_function("2*x**2 + sin(pi*x)")
    >>> round(float(f(np.array(1.0))), 12)
    2.0
    >>> parse_function("__import__('os')")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: --f: only x, numbers, + - * / **, pi, e and sin, ... are allowed
    """
    message = "only x, numbers, + - * / **, pi, e and " + ", ".join(_FUNCTIONS) + " are allowed"
    try:
        tree = ast.parse(text, mode="eval")
    except SyntaxError:
        raise InputError("--f", f"cannot read {text!r} as an expression in x") from None
    for node in ast.walk(tree):
        if not isinstance(node, _ALLOWED_NODES):
            raise InputError("--f", message)
        if isinstance(node, ast.Name) and node.id not in {"x", *_FUNCTIONS, *_CONSTANTS}:
            raise InputError("--f", message)
        if isinstance(node, ast.Call) and not (
            isinstance(node.func, ast.Name) and node.func.id in _FUNCTIONS and not node.keywords
        ):
            raise InputError("--f", message)
        if isinstance(node, ast.Constant) and not isinstance(node.value, int | float):
            raise InputError("--f", message)
    code = compile(tree, "<--f>", "eval")
    names = {"__builtins__": {}, **_FUNCTIONS, **_CONSTANTS}

    def func(x: np.ndarray) -> np.ndarray:
        with np.errstate(all="ignore"):
            return np.asarray(eval(code, names, {"x": np.asarray(x, dtype=float)}), dtype=float)

    return func


def _pair(text: str, field: str) -> tuple[float, float]:
    try:
        a, b = (float(v) for v in text.split(":"))
    except ValueError:
        raise InputError(field, f"expected START:END, got {text!r}") from None
    return a, b


def _point(z: complex) -> str:
    return f"({z.real:.4f}, {z.imag:.4f})"


@synth_app.command("three-position")
def three_position_cmd(
    c: Annotated[str, typer.Option("--c", help="C1..C3 as 'x,y; x,y; x,y'.")],
    d: Annotated[str, typer.Option("--d", help="D1..D3 as 'x,y; x,y; x,y'.")],
    o2: Annotated[
        str | None, typer.Option("--o2", help="Fixed pivot O2 'x,y' (inverted problem).")
    ] = None,
    o4: Annotated[str | None, typer.Option("--o4", help="Fixed pivot O4 'x,y'.")] = None,
    json: Annotated[bool, typer.Option("--json", help="Print JSON instead of tables.")] = False,
) -> None:
    """Four-bar through three positions of a coupler line CD (pivots by bisectors).

    With --o2 and --o4 the fixed pivots are given and the moving pivots are
    found by inversion. Exits with status 1 if the linkage has a circuit,
    branch or order defect (reported on stderr).
    """
    from ..synthesis import three_position, three_position_fixed_pivots

    cs = parse_points(c, "--c", 3)
    ds = parse_points(d, "--d", 3)
    if (o2 is None) != (o4 is None):
        raise InputError("--o2", "give both --o2 and --o4 (fixed pivots), or neither")
    if o2 is None:
        s = three_position(cs, ds)
    else:
        s = three_position_fixed_pivots(
            cs, ds, parse_points(o2, "--o2", 1)[0], parse_points(o4, "--o4", 1)[0]
        )
    if json:
        print(
            dumps(
                {
                    "O2": s.O2,
                    "O4": s.O4,
                    "theta1_deg": float(np.degrees(s.theta1)),
                    "r1": s.r1,
                    "r2": s.r2,
                    "r3": s.r3,
                    "r4": s.r4,
                    "barker_class": s.fourbar.barker_class,
                    "A": s.A,
                    "B": s.B,
                    "theta2_deg": np.degrees(s.theta2),
                    "branch": s.branch,
                    "direction": s.direction,
                    "mu_min_deg": float(np.degrees(s.mu_min)),
                    "defects": list(s.defects),
                }
            )
        )
    else:
        print_table(
            "Three-position synthesis",
            ["quantity", "value"],
            [
                ["O2", _point(s.O2)],
                ["O4", _point(s.O4)],
                ["ground angle theta1 (deg)", float(np.degrees(s.theta1))],
                ["r1 ground", s.r1],
                ["r2 input", s.r2],
                ["r3 coupler", s.r3],
                ["r4 output", s.r4],
                ["Barker class", s.fourbar.barker_class],
                ["min transmission angle (deg)", float(np.degrees(s.mu_min))],
            ],
        )
        print_table(
            "Positions",
            ["position", "A", "B", "theta2 (deg)", "branch"],
            [
                [
                    k + 1,
                    _point(s.A[k]),
                    _point(s.B[k]),
                    float(np.degrees(s.theta2[k])),
                    int(s.branch[k]),
                ]
                for k in range(3)
            ],
        )
    if s.defects:
        raise AssemblyError("the linkage cannot do the job: " + "; ".join(s.defects))


@synth_app.command("function")
def function_cmd(
    f: Annotated[str, typer.Option("--f", help="y = f(x), e.g. 'log10(x)' or 'x**1.5'.")],
    x: Annotated[str, typer.Option("--x", help="Range of x, START:END.")],
    theta2: Annotated[str, typer.Option("--theta2", help="Input angles, START:END (deg).")],
    theta4: Annotated[str, typer.Option("--theta4", help="Output angles, START:END (deg).")],
    n: Annotated[int, typer.Option("--n", help="Precision points (3 exact, more LSQ).")] = 3,
    spacing: Annotated[str, typer.Option("--spacing", help="chebyshev or uniform.")] = "chebyshev",
    r1: Annotated[float, typer.Option("--r1", help="Ground length (scale).")] = 1.0,
    samples: Annotated[int, typer.Option("--samples", help="Structural-error samples.")] = 11,
    json: Annotated[bool, typer.Option("--json", help="Print JSON instead of tables.")] = False,
) -> None:
    """Four-bar function generator by Freudenstein's equation, with its structural error."""
    from ..synthesis import function_generator

    for option, value, most in (("--n", n, 10_000), ("--samples", samples, 100_000)):
        if not 1 <= value <= most:
            raise InputError(option, f"must be between 1 and {most:,}, got {value:,}")
    func = parse_function(f)
    x_range = _pair(x, "--x")
    t2 = np.radians(_pair(theta2, "--theta2"))
    t4 = np.radians(_pair(theta4, "--theta4"))
    g = function_generator(func, x_range, t2, t4, n=n, spacing=spacing, r1=r1)
    se = g.structural_error(n=samples)
    if json:
        print(
            dumps(
                {
                    "r1": g.r1,
                    "r2": g.r2,
                    "r3": g.r3,
                    "r4": g.r4,
                    "K": g.k,
                    "barker_class": g.fourbar.barker_class,
                    "branch": g.branch,
                    "input_offset_deg": float(np.degrees(g.input_offset)),
                    "output_offset_deg": float(np.degrees(g.output_offset)),
                    "x_precision": g.x_precision,
                    "structural_error": {"x": se.x, "error": se.error, "ok": se.ok},
                    "max_abs_error": se.max_abs,
                    "defects": list(g.defects),
                }
            )
        )
    else:
        print_table(
            f"Function generator for y = {f}",
            ["quantity", "value"],
            [
                ["r1 ground", g.r1],
                ["r2 input", g.r2],
                ["r3 coupler", g.r3],
                ["r4 output", g.r4],
                ["K1, K2, K3", ", ".join(f"{k:.6g}" for k in g.k)],
                ["Barker class", g.fourbar.barker_class],
                ["input link offset (deg)", float(np.degrees(g.input_offset))],
                ["output link offset (deg)", float(np.degrees(g.output_offset))],
                ["precision points x", ", ".join(f"{v:.6g}" for v in g.x_precision)],
                ["max |structural error|", f"{se.max_abs:.3e}"],
            ],
        )
        print_table(
            "Structural error",
            ["x", "f(x)", "generated", "error"],
            [
                [float(a), float(b), float(c), "-" if np.isnan(e) else f"{e:.3e}"]
                for a, b, c, e in zip(se.x, se.y_desired, se.y_generated, se.error, strict=True)
            ],
        )
    if g.defects:
        raise AssemblyError("the linkage cannot generate the function: " + "; ".join(g.defects))
