"""The CLI × random argument lists and mutated machine files: one line, never a crash.

Each example starts from a valid command line of one command (TEMPLATES: every
command of ``machdyn --help`` has one; a new command without one fails
``test_every_command_has_a_template``) and mutates it: values replaced by extreme or
malformed ones (400-digit numbers, 1e-320, ±1e300, NaN, text, empty), options
dropped, repeated or added with random values, and input files replaced by mutated
copies (numbers changed, lines dropped or repeated, keys misspelt, bytes that are not
text). The command must then

* exit 0, 1 or 2, never 70 ("internal error") and never with a traceback;
* on failure print exactly one line, ``machdyn: error: ...``, and nothing before it
  (no NumPy warning);
* on success print only ``machdyn: warning:`` lines on stderr, valid JSON with
  ``--json`` (no NaN or Infinity), and — for ``fourbar --json`` — angles that close
  the loop (an independent check of the answer).
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import os
import random
import re
import signal
import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from machdyn.cli import main

EXAMPLES = Path(__file__).resolve().parents[1] / "docs" / "examples"
WORK = Path(tempfile.mkdtemp(prefix="machdyn_fuzz_cli_"))


def _write(name: str, text: str) -> str:
    path = WORK / name
    path.write_text(text)
    return str(path)


PROGRAM = _write(
    "program.toml",
    '[[segment]]\nmotion = "rise"\nlaw = "cycloidal"\nh = 1.0\nbeta = 60\n'
    '[[segment]]\nmotion = "dwell"\nbeta = 120\n'
    '[[segment]]\nmotion = "fall"\nlaw = "cycloidal"\nh = 1.0\nbeta = 60\n'
    '[[segment]]\nmotion = "dwell"\nbeta = 120\n',
)
TABLE = _write("table.csv", "theta_deg,s\n0,0\n60,0.4\n120,1\n180,1\n240,0.5\n300,0.1\n")
PATH_POINTS = _write(
    "path.csv",
    "x,y\n"
    + "\n".join(
        f"{2 * math.cos(t):.6f},{math.sin(t):.6f}"
        for t in np.linspace(0, 2 * np.pi, 8, endpoint=False)
    ),
)
OLD_LINKAGE = _write(  # the linkage file format before machine files (machdyn spec upgrade)
    "old_linkage.toml",
    'title = "slider-crank"\nground = ["O2"]\ndrive = ["crank"]\n'
    "[points]\nO2 = [0, 0]\nA = [1, 0]\nB = [3, 0]\n"
    '[[link]]\nname = "crank"\npoints = ["O2", "A"]\nmass = 1.0\ninertia = 0.1\n'
    '[[link]]\nname = "rod"\npoints = ["A", "B"]\n'
    '[[link]]\nname = "block"\npoints = ["B"]\n'
    '[[slider]]\nblock = "block"\non = "ground"\nat = "B"\ndirection = 0.0\n'
    "[motion.crank]\nvalue = 30\nvelocity = 2.0\n",
)
ATLAS = str(WORK / "atlas")
CAM = ["-s", "rise:cycloidal:1:60", "-s", "dwell:120", "-s", "fall:cycloidal:1:60"]
CAM += ["-s", "dwell:120", "--prime-radius", "4", "--roller-radius", "0.5"]

#: Commands that serve until interrupted: not fuzzed here (tests/test_studio.py checks
#: that a bad file name or port is one error line, exit 1, before anything listens).
SERVES = {"studio"}

#: A valid command line of every command; OUT is replaced by a fresh output path.
TEMPLATES: dict[str, list[str]] = {
    "fourbar": ["8", "4", "7", "6", "--theta2", "0:360:30", "--coupler", "3:30", "--json"],
    "demo": ["--json"],
    "flywheel": [str(EXAMPLES / "torque.csv"), "--omega-avg", "50", "--k", "0.02", "--json"],
    "linkage": [str(EXAMPLES / "fourbar.toml"), "--sweep", "crank=0:90:15", "--forces", "--json"],
    "animate": ["8", "4", "7", "6", "--out", "OUT.svg", "--theta2", "30"],
    "report": [str(EXAMPLES / "hw6.toml"), "--out", "OUT.html", "--samples", "36"],
    "run": [str(EXAMPLES / "hw6.toml"), "--json"],
    "simulate": [str(EXAMPLES / "motor.toml"), "--json"],
    "tolerance": [str(EXAMPLES / "motor.toml"), "--samples", "200", "--json"],
    "balance static": ["--mass", "2,3,30", "--mass", "1.5,4,160", "--radius", "2", "--json"],
    "balance rotor": [
        "--mass",
        "1,1,0,1",
        "--mass",
        "1,1,180,3",
        "--plane-a",
        "0",
        "--plane-b",
        "4",
    ],
    "balance bearings": [
        "--force",
        "5,45,-14",
        "--force",
        "2,-120,-4",
        "--omega",
        "100",
        "--plane-a",
        "0",
        "--plane-b",
        "7",
        "--json",
    ],
    "cam": [*CAM, "--points", "360", "--json"],
    "cam laws": [],
    "gear pair": ["--np", "24", "--ng", "60", "--pd", "8", "--json"],
    "gear min-teeth": ["--phi", "20", "--ng", "101", "--json"],
    "gear profile": ["-N", "18", "-m", "2", "-o", "OUT.csv", "--points", "20"],
    "gear plot": ["--np", "18", "--ng", "40", "-m", "1", "-o", "OUT.svg"],
    "gear train": ["20:40,30:90:internal", "--json"],
    "gear reverted": ["18", "--json"],
    "gear planetary": [
        "--sun",
        "40",
        "--planet",
        "20",
        "--ring",
        "80",
        "--speed",
        "sun=1",
        "--speed",
        "arm=0",
    ],
    "synth three-position": [
        "--c",
        "0,5.086; 2.019,3.181; 3.933,4.051",
        "--d",
        "0.741,2.703; 4.428,2.529; 6.304,4.83",
        "--json",
    ],
    "synth function": [
        "--f",
        "log10(x)",
        "--x",
        "1:2",
        "--theta2",
        "45:105",
        "--theta4",
        "135:225",
        "--json",
    ],
    "synth path": [PATH_POINTS, "--atlas", ATLAS, "-n", "1", "--time-limit", "30", "--json"],
    "atlas build": ["OUT", "--count", "20", "--chunk-size", "20", "--no-progress"],
    "atlas info": [ATLAS],
    "spec check": [str(EXAMPLES / "fourbar.toml")],
    "spec upgrade": [OLD_LINKAGE],
    "spec schema": [],
    # a second template of a command after "#": here the sub-commands' --spec FILE (#11)
    "gear pair #spec": ["--spec", str(EXAMPLES / "gears.toml"), "--json"],
    "gear train #spec": ["--spec", str(EXAMPLES / "gears.toml"), "--csv"],
    "gear planetary #spec": ["--spec", str(EXAMPLES / "gears.toml"), "--part", "epicyclic"],
    "gear profile #spec": [
        "--spec",
        str(EXAMPLES / "gears.toml"),
        "-o",
        "OUT.csv",
        "--points",
        "8",
    ],
    "flywheel #spec": ["--spec", str(EXAMPLES / "flywheel.toml"), "--json"],
    "balance rotor #spec": ["--spec", str(EXAMPLES / "rotor.toml"), "--json"],
    "balance static #spec": ["--spec", str(EXAMPLES / "disc.toml"), "--part", "disc", "--csv"],
    "synth three-position #spec": ["--spec", str(EXAMPLES / "synthesis.toml"), "--json"],
    "synth function #spec": ["--spec", str(EXAMPLES / "synthesis.toml"), "--part", "log"],
}


def command(name: str) -> list[str]:
    """The command words of a TEMPLATES key (``"gear pair #spec"`` -> gear, pair)."""
    return name.split("#")[0].split()


#: Values a mutation puts in place of a number, a name or a range.
VALUES = [
    "0",
    "-1",
    "1",
    "8",
    "0.5",
    "1e308",
    "-1e308",
    "1e300",
    "-1e300",
    "1e-320",
    "5e-324",
    "1e999",
    "nan",
    "inf",
    "-inf",
    "1" + "0" * 400,
    "-" + "9" * 400,
    "abc",
    "",
    " ",
    "1,2",
    "0:360:30",
    "0:360:0",
    "10:0:1",
    "0:1e9:1e-9",
    "::",
    "1:2:3:4",
    "x",
    "x+9**9**9",
    "crank=0:360:1",
    "crank=nan",
    "=",
    "2,3",
    "1,2,3,4,5",
    "sun=1",
    "internal",
    "-5:-4",
    "1" * 60,
    "\x00",
    "é",
    "--json",
    "-",
    "0x10",
    "1_000",
]

_NUMBER = re.compile(rb"(?<![\w.])-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?")


def _mutate_file(source: str, rng: random.Random) -> str:
    """A copy of a machine/CSV file with a few random edits."""
    data = Path(source).read_bytes()
    lines = data.split(b"\n")
    for _ in range(rng.randint(1, 3)):
        kind = rng.randrange(6)
        i = rng.randrange(len(lines))
        if kind == 0:  # a number replaced
            numbers = list(_NUMBER.finditer(lines[i]))
            if numbers:
                m = rng.choice(numbers)
                new = rng.choice(VALUES).encode("utf-8", "replace")
                lines[i] = lines[i][: m.start()] + new + lines[i][m.end() :]
        elif kind == 1:
            del lines[i]
        elif kind == 2:
            lines.insert(i, lines[i])
        elif kind == 3:  # a key misspelt
            lines[i] = re.sub(rb"^(\s*)(\w)", rb"\1x\2", lines[i])
        elif kind == 4:
            lines[i] = bytes(rng.randrange(256) for _ in range(rng.randint(1, 8)))
        else:  # truncated
            lines = lines[: i + 1]
        if not lines:
            lines = [b""]
    path = WORK / f"mutated_{rng.randrange(10**9)}{Path(source).suffix}"
    path.write_bytes(b"\n".join(lines))
    return str(path)


def _known_options(command: list[str]) -> list[str]:
    import typer

    from machdyn.cli import app

    node = typer.main.get_command(app)
    for word in command:
        node = node.commands[word]
    return [opt for p in node.params for opt in p.opts if opt.startswith("-")]


def _is_file(text: str) -> bool:
    try:
        return Path(text).is_file()
    except (OSError, ValueError):  # a name too long, a NUL byte
        return False


def _mutate(name: str, rng: random.Random) -> list[str]:
    args = [a.replace("OUT", str(WORK / f"out_{rng.randrange(10**9)}")) for a in TEMPLATES[name]]
    for _ in range(rng.randint(1, 3)):
        kind = rng.choices(range(4), weights=(6, 1, 1, 2))[0]
        values = [k for k, a in enumerate(args) if not a.startswith("-") or a[1:2].isdigit()]
        if kind == 0 and args:  # a value (or a file) replaced, rarely an option's name
            i = rng.choice(values) if values and rng.random() < 0.9 else rng.randrange(len(args))
            if _is_file(args[i]) and rng.random() < 0.7:
                args[i] = _mutate_file(args[i], rng)
            else:
                args[i] = rng.choice(VALUES)
        elif kind == 1 and args:
            del args[rng.randrange(len(args))]
        elif kind == 2 and args:
            i = rng.randrange(len(args))
            args.insert(i, args[i])
        else:  # an option of the command with a random value
            options = _known_options(command(name))
            if options:
                args += [rng.choice(options), rng.choice(VALUES)]
    return args


class _Timeout(BaseException):  # not caught by main()'s "except Exception"
    pass


def _alarm(signum, frame):
    raise _Timeout


def _build_atlas() -> None:
    if not (WORK / "atlas" / "manifest.json").exists():
        status, _, err = run(["atlas", "build", ATLAS, "--count", "400", "--no-progress"])
        assert status == 0, err


def run(argv: list[str], seconds: float = 60.0) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    old = signal.signal(signal.SIGALRM, _alarm)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    here = os.getcwd()
    try:
        os.chdir(WORK)
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            status = main(argv)
    finally:
        os.chdir(here)
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)
    return status, out.getvalue(), err.getvalue()


def check(argv: list[str], status: int, out: str, err: str) -> None:
    where = f"machdyn {' '.join(map(repr, argv))}"
    assert status in (0, 1, 2), f"{where}: exit {status}\n{err}"
    assert "Traceback" not in err + out, where
    if status:
        assert err.count("\n") == 1 and err.startswith("machdyn: error: "), f"{where}:\n{err}"
        return
    stray = [
        line
        for line in err.splitlines()
        if re.search(r"Warning|error", line) and not line.startswith("machdyn: warning: ")
    ]  # progress bars may be there; Python's own warnings may not
    assert not stray, f"{where}: {stray}"
    if "--json" in argv and out.strip():
        payload = json.loads(out, parse_constant=lambda c: pytest.fail(f"{where}: {c} in JSON"))
        if argv[0] == "fourbar" and isinstance(payload, dict):
            _loop_closes(argv, payload)


def _loop_closes(argv: list[str], payload: dict) -> None:
    """The answer of ``fourbar --json``: its angles close the vector loop."""
    r1, r2, r3, r4 = (float(v) for v in argv[1:5])
    rows = payload.get("rows") or payload.get("kinematics") or []
    for row in rows if isinstance(rows, list) else []:
        if not isinstance(row, dict) or not row.get("ok", True):
            continue
        t2, t3, t4 = (row.get(k) for k in ("theta2_deg", "theta3_deg", "theta4_deg"))
        if None in (t2, t3, t4):
            continue
        t2, t3, t4 = np.radians([t2, t3, t4])
        loop = r2 * np.exp(1j * t2) + r3 * np.exp(1j * t3) - r4 * np.exp(1j * t4) - r1
        assert abs(loop) <= 1e-6 * max(r1, r2, r3, r4), f"{argv}: {row}"


def test_every_command_has_a_template():
    import typer

    from machdyn.cli import app

    def leaves(node, path):
        subs = getattr(node, "commands", {})
        if not subs or getattr(node, "invoke_without_command", False):
            yield " ".join(path)
        for name, sub in subs.items():
            yield from leaves(sub, [*path, name])

    commands = {c for c in leaves(typer.main.get_command(app), []) if c} - SERVES
    templated = {" ".join(command(name)) for name in TEMPLATES}
    assert not commands - templated, f"add a template to tests/test_fuzz_cli.py: {commands}"


@pytest.mark.parametrize("name", sorted(TEMPLATES))
def test_templates_run(name):
    argv = [*command(name), *TEMPLATES[name]]
    argv = [a.replace("OUT", str(WORK / f"template_{name.replace(' ', '_')}")) for a in argv]
    _build_atlas()
    status, out, err = run(argv)
    check(argv, status, out, err)
    assert status == 0, err


#: Commands that are slow whatever their arguments (drawing, Dask): fewer examples.
SLOW = {"animate", "report", "gear plot", "atlas build", "synth path"}


@settings(max_examples=400, deadline=None, derandomize=True)
@given(st.sampled_from(sorted(set(TEMPLATES) - SLOW)), st.randoms(use_true_random=False))
def test_random_command_lines(name, rng):
    _build_atlas()
    argv = [*command(name), *_mutate(name, rng)]
    check(argv, *run(argv))


@pytest.mark.slow
@settings(max_examples=40, deadline=None, derandomize=True)
@given(st.sampled_from(sorted(SLOW)), st.randoms(use_true_random=False))
def test_random_command_lines_of_slow_commands(name, rng):
    _build_atlas()
    argv = [*command(name), *_mutate(name, rng)]
    check(argv, *run(argv))


def test_a_report_point_on_no_link_is_one_error_line():
    # Issue #17: `report = ["P"]` with P on no link ended in KeyError (exit 70).
    text = (EXAMPLES / "fourbar.toml").read_text()
    loose = _write(
        "loose_point.toml", text.replace('points = ["A", "B", "P"]', 'points = ["A", "B"]')
    )
    argv = ["linkage", loose, "--sweep", "crank=0:90:15", "--json"]
    status, out, err = run(argv)
    check(argv, status, out, err)
    assert status == 1 and "report[1]: point 'P' is on no link" in err, err
