"""The ``machdyn`` command line.

Each topic lives in its own module (``fourbar.py``, ``cam.py``, ``gear.py``,
...) exposing a function or a ``typer.Typer`` that is registered here. The CLI
only parses, calls the library and presents; no physics lives in this package.

Errors never end in a traceback: :func:`main` prints one line to stderr and
returns a non-zero exit status (2 for usage errors, 1 for bad values, files
that cannot be read or written and requests beyond the memory budget, 70 for an
internal error — a bug; set ``MACHDYN_DEBUG=1`` to see its traceback).

Warnings raised while a command runs (NumPy's RuntimeWarnings among them) are
held back: after a failure only the one error line is printed, after a success
each distinct warning follows the output as one ``machdyn: warning:`` line.
"""

from __future__ import annotations

import functools
import os
import sys
import warnings
from collections.abc import Sequence
from typing import Any

import typer

from ..errors import MachdynError

__all__ = ["OPTIONAL", "app", "main"]

#: Optional packages and the extra of machdyn that installs each (``pip install 'machdyn[plot]'``).
OPTIONAL = {"matplotlib": "plot", "pandas": "pandas", "ezdxf": "dxf", "PIL": "plot"}


def __getattr__(name: str) -> Any:
    if name == "app":  # the full application, every subcommand registered
        return _full_app()
    raise AttributeError(f"module 'machdyn.cli' has no attribute {name!r}")


def _command(args: list[str]) -> Any:
    """The click command for ``args``: ``run``, ``studio`` and ``synth`` load only what they need.

    Importing every subcommand costs about 0.15 s; ``machdyn run`` on a
    four-bar file has a cold-start budget of 0.6 s in all, and a ``machdyn synth
    path`` call is timed whole by those who try it (docs/synthesis.md).
    """
    if args[:1] in (["run"], ["studio"], ["synth"]):  # (the studio's start-up budget is 2 s)
        fast = typer.Typer(add_completion=False, pretty_exceptions_enable=False)
        fast.callback()(lambda: None)
        if args[0] == "synth":
            from .synth import synth_app

            fast.add_typer(synth_app, name="synth")
            return typer.main.get_command(fast)
        if args[0] == "run":
            from .run import run as command
        else:
            from .studio import studio as command

        fast.command(args[0])(command)
        return typer.main.get_command(fast)
    return _full_command()


@functools.cache
def _full_command() -> Any:
    """The click command of the whole application, built once per process (~0.2 s)."""
    return typer.main.get_command(_full_app())


def _full_app() -> Any:
    from .app import app

    globals()["app"] = app  # the Typer object, not the submodule of the same name
    return app


def main(argv: Sequence[str] | None = None) -> int:
    """Run the CLI and return its exit status (the console-script entry point)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("default")
        status = _run(list(sys.argv[1:] if argv is None else argv))
    if status == 0:
        for line in dict.fromkeys(f"{w.category.__name__}: {w.message}" for w in caught):
            print(f"machdyn: warning: {' '.join(line.split())}", file=sys.stderr)
    return status


def _fast_run(args: list[str]) -> dict[str, Any] | None:
    """The arguments of a plain ``machdyn run FILE [--part P] [--json|--csv] [--out D]``.

    Building typer's command (it imports pydantic to coerce parameters) costs
    about 0.15 s, a quarter of ``machdyn run``'s cold-start budget; these few
    options are read here instead. Anything else (``--help``, a misspelt
    option) goes through typer, which prints its usage message.
    """
    if args[:1] != ["run"]:
        return None
    out: dict[str, Any] = {"part": None, "json": False, "csv_out": False, "out": None}
    files: list[str] = []
    rest = iter(args[1:])
    for arg in rest:
        name, eq, value = arg.partition("=")
        if name in ("--part", "--out"):
            if not eq:
                value = next(rest, "")
            if not value or value.startswith("-"):
                return None
            out["part" if name == "--part" else "out"] = value
        elif arg in ("--json", "--csv"):
            out["json" if arg == "--json" else "csv_out"] = True
        elif arg.startswith("-"):
            return None
        else:
            files.append(arg)
    if len(files) != 1:
        return None
    from pathlib import Path

    out["file"] = Path(files[0])
    out["out"] = None if out["out"] is None else Path(out["out"])
    return out


def _run(args: list[str]) -> int:
    try:
        fast = _fast_run(args)
        if fast is not None:
            from .run import run

            run(**fast)
        else:
            _command(args).main(args=args, prog_name="machdyn", standalone_mode=False)
    except typer.Exit as exc:
        return int(getattr(exc, "exit_code", 0) or 0)
    except typer.Abort:
        print("machdyn: aborted", file=sys.stderr)
        return 1
    except MachdynError as exc:
        return _fail(str(exc), 1)
    except ImportError as exc:  # an optional package that is not installed
        package = (getattr(exc, "name", None) or "").split(".")[0]
        if package not in OPTIONAL:
            raise
        extra = OPTIONAL[package]
        return _fail(
            f"this needs {package}, which is not installed: pip install 'machdyn[{extra}]'", 1
        )
    except BrokenPipeError:  # the reader went away (`machdyn ... | head`): stop quietly
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())  # so the flush at exit does not raise again
        return 1  # as click does for the sub-commands it runs
    except OSError as exc:  # a file that cannot be read or written
        where = f"{exc.filename}: " if exc.filename else ""
        return _fail(f"{where}{exc.strerror or exc}", 1)
    except MemoryError:
        return _fail(
            "not enough memory for this request; ask for fewer samples or points "
            "(MACHDYN_MEMORY_LIMIT sets the budget machdyn checks up front)",
            1,
        )
    except RecursionError:
        return _fail("the input is nested too deeply to be read", 1)
    except KeyboardInterrupt:
        return _fail("interrupted", 130)
    except UnicodeDecodeError as exc:
        return _fail(f"an input file is not UTF-8 text ({exc.reason} at byte {exc.start})", 1)
    except Exception as exc:
        # Usage errors of the click that typer bundles (or depends on, for older
        # typer releases): duck-typed so either one works.
        if hasattr(exc, "format_message") and hasattr(exc, "exit_code"):
            return _fail(exc.format_message(), int(exc.exit_code) or 2)
        if os.environ.get("MACHDYN_DEBUG"):
            raise
        return _fail(
            f"internal error: {type(exc).__name__}: {exc} (set MACHDYN_DEBUG=1 for a traceback)",
            70,
        )
    return 0


def _fail(message: str, status: int) -> int:
    print(f"machdyn: error: {' '.join(message.split())}", file=sys.stderr)
    return status


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
