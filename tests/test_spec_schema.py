"""The published JSON Schema, and a fuzzer over machine files (bad input: one line, status 1).

Every example in docs/examples/ that is a machine file validates against the
schema; each kind of bad input is refused by the schema *and* by the reader,
whose message names the key (and its line) in one line; ``machdyn run`` on a
bad file exits 1 with that line and no traceback, and never prints a result.
"""

from __future__ import annotations

import copy
import math
import tomllib
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from machdyn.cli import main
from machdyn.errors import MachdynError
from machdyn.spec import SpecError, dumps, from_spec, load_machine, read, schema
from machdyn.spec._schema import build

jsonschema = pytest.importorskip("jsonschema")

EXAMPLES = Path(__file__).resolve().parents[1] / "docs" / "examples"
MACHINE_FILES = sorted(
    p for p in EXAMPLES.glob("*.toml") if tomllib.loads(p.read_text()).get("machdyn") == 1
)
VALIDATOR = jsonschema.Draft202012Validator(schema())


def test_the_packaged_schema_is_the_one_the_reader_describes():
    assert schema() == build()
    jsonschema.Draft202012Validator.check_schema(schema())


@pytest.mark.parametrize("path", MACHINE_FILES, ids=lambda p: p.name)
def test_every_example_validates_and_reads(path):
    doc = tomllib.loads(path.read_text())
    assert not list(VALIDATOR.iter_errors(doc))
    assert load_machine(path).parts
    assert not list(VALIDATOR.iter_errors(load_machine(path).to_spec()))


def test_there_are_machine_file_examples():
    assert any(p.name == "hw6.toml" for p in MACHINE_FILES)


# ------------------------------------------------------------------ bad input
def _hw6() -> dict:
    return tomllib.loads((EXAMPLES / "hw6.toml").read_text())


def _set(doc: dict, path: tuple, value) -> dict:
    doc = copy.deepcopy(doc)
    table = doc
    for key in path[:-1]:
        table = table[key]
    if value is _DROP:
        del table[path[-1]]
    else:
        table[path[-1]] = value
    return doc


_DROP = object()
R2 = ("fourbar", "hw6", "r2")
CASES = {
    "dropped key": (R2, _DROP, "missing: required"),
    "wrong type": (R2, [4], "expected a length"),
    "wrong type, table": (("fourbar", "hw6", "motion"), 3, "expected a table"),
    "wrong dimension": (R2, "4 kg", "expected a length like '120 mm', got '4 kg'"),
    "wrong dimension, mass": (("fourbar", "hw6", "link3", "mass"), "3 m", "expected a mass"),
    "unknown unit": (R2, "4 furlongz", "unknown unit 'furlongz'"),
    "unknown key": (("fourbar", "hw6", "r5"), 1.0, "r5: unknown key; valid keys"),
    "unknown top-level key": (("fourbars",), {}, "fourbars: unknown key"),
    "nan": (R2, math.nan, "must be finite"),
    "inf": (R2, math.inf, "must be finite"),
    "nan with a unit": (R2, "nan in", "must be finite"),
    "huge": (R2, 1e300, "too large"),
    "negative": (R2, -4, "must be positive"),
    "choice": (("fourbar", "hw6", "form"), 3, "must be one of 1, 2"),
    "version": (("machdyn",), 2, "this file is format 2"),
    "units entry of the wrong kind": (("units", "length"), "kg", "[units] length: expected"),
    "empty name": (("fourbar", ""), {"r1": 1, "r2": 1, "r3": 1, "r4": 1}, "must not be empty"),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_each_bad_input_is_refused_by_schema_reader_and_command(case, tmp_path, capsys):
    path, value, needle = CASES[case]
    doc = _set(_hw6(), path, value)
    assert list(VALIDATOR.iter_errors(doc)), f"the schema accepts {case}"
    with pytest.raises(SpecError) as info:
        from_spec(doc)
    assert needle in str(info.value) and "\n" not in str(info.value)
    try:
        text = dumps(doc)
    except MachdynError:  # NaN and inf cannot be written: put them in by hand
        text = dumps(_set(doc, path, 12345.5)).replace("12345.5", str(value).lower())
    file = tmp_path / "bad.toml"
    file.write_text(text)
    status = main(["run", str(file)])
    out, err = capsys.readouterr()
    assert status == 1 and out == "", out
    assert err.startswith(f"machdyn: error: {file}:") and err.count("\n") == 1, err
    assert needle in err and "Traceback" not in err


def test_duplicate_keys_and_broken_toml_are_syntax_errors(tmp_path, capsys):
    file = tmp_path / "dup.toml"
    file.write_text("machdyn = 1\n[fourbar.a]\nr1 = 1\nr1 = 2\n")
    assert main(["run", str(file)]) == 1
    err = capsys.readouterr().err
    expected = f"{file}:4: TOML syntax error: Cannot overwrite a value (column 7)"
    assert err == f"machdyn: error: {expected}\n"


# ------------------------------------------------------------------ the fuzzer
def _paths(doc, prefix=()):
    """Every key path of a document (tables and their keys)."""
    if isinstance(doc, dict):
        for key, value in doc.items():
            yield (*prefix, key)
            yield from _paths(value, (*prefix, key))


DOCS = {p.name: tomllib.loads(p.read_text()) for p in MACHINE_FILES}
ALL_PATHS = [(name, path) for name, doc in DOCS.items() for path in _paths(doc)]
VALUES = st.one_of(
    st.just(_DROP),
    st.none().map(lambda _: "12 kg"),
    st.sampled_from(["3 furlongz", "nan", "1e999 mm", "ü", "", " ", "O2", "30 deg", "10 Hz"]),
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(-(10**20), 10**20),
    st.booleans(),
    st.lists(st.integers(0, 3), max_size=4),
    st.dictionaries(st.text(min_size=1, max_size=3), st.integers(), max_size=2),
    st.text(max_size=8),
)


@settings(suppress_health_check=[HealthCheck.too_slow], deadline=None, max_examples=150)
@given(where=st.sampled_from(ALL_PATHS), value=VALUES)
def test_fuzzed_files_are_read_completely_or_refused_in_one_line(where, value):
    name, path = where
    doc = _set(DOCS[name], path, value)
    try:
        machine = read(doc)  # always a Machine (from_spec gives a lone part's model)
    except SpecError as exc:
        message = str(exc)
        assert "\n" not in message and message, message
        assert ":" in message
        return
    except MachdynError as exc:  # pragma: no cover - every reader error is a SpecError
        pytest.fail(f"not a SpecError: {type(exc).__name__}: {exc}")
    # accepted: then it is a complete machine that runs without a traceback, or stops
    # with one line naming what it cannot do (a sweep outside a rocker's range, ...)
    try:
        results = machine.run()
    except MachdynError as exc:
        assert "\n" not in str(exc)
        return
    assert set(results) == set(machine.parts)


def test_json_machine_files_read_like_toml(tmp_path, capsys):
    import json

    doc = _hw6()
    file = tmp_path / "hw6.json"
    file.write_text(json.dumps(doc))
    assert load_machine(file).to_spec() == load_machine(EXAMPLES / "hw6.toml").to_spec()
    file.write_text('{"machdyn": 1, "fourbar": {"a": {"r1": "8 kg", "r2": 4, "r3": 7, "r4": 6}}}')
    with pytest.raises(SpecError, match="r1: expected a length"):
        load_machine(file)
    file.write_text('{"machdyn": 1,\n "fourbar": }')
    assert main(["run", str(file)]) == 1
    assert f"{file}:2: JSON syntax error" in capsys.readouterr().err


# ------------------------------------------------------------------ every quantity of every example
def _leaves(doc, prefix=()):
    if isinstance(doc, dict):
        for key, value in doc.items():
            yield from _leaves(value, (*prefix, key))
    elif isinstance(doc, list):
        for i, value in enumerate(doc):
            yield from _leaves(value, (*prefix, i))
    else:
        yield prefix, doc


def _quantity_like(value) -> bool:
    """A number, or text with a unit (``"30 deg"``)."""
    from machdyn.units import parse

    if isinstance(value, bool):
        return False
    if isinstance(value, int | float):
        return True
    try:
        return isinstance(value, str) and bool(parse(value)[1])
    except ValueError:
        return False


QUANTITIES = [
    (name, path)
    for name, doc in DOCS.items()
    for path, value in _leaves(doc)
    if path != ("machdyn",) and _quantity_like(value)
]


@pytest.mark.parametrize("bad", ["3 A", "3 furlongz"], ids=["wrong dimension", "unknown unit"])
def test_every_quantity_of_every_example_names_its_key_when_wrong(bad):
    """A current where a length (mass, speed, count...) is due, or a unit pint does not know:
    refused, naming the file, the key's line and the key, for every number of every example."""
    from machdyn.spec import loads

    assert len(QUANTITIES) > 150
    for name, path in QUANTITIES:
        text = dumps(_set(DOCS[name], path, bad))
        with pytest.raises(SpecError) as info:
            loads(text, name)
        message = str(info.value)
        key = [k for k in path if isinstance(k, str)][-1]
        assert message.startswith(f"{name}:") and "\n" not in message, message
        assert message.split(":")[1].isdigit(), f"no line: {message}"
        assert key in message and ("'3 A'" in message or "furlongz" in message), (path, message)
