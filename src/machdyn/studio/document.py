"""The studio's document: a machine document (``docs/spec.md``), read, written and edited.

The page holds one plain spec dict; this module normalises what comes in (a
template, a file the user dropped on the page) through the spec reader, writes
it back to the one file the user named on the command line, and applies the
few edits that need more than setting a number: renaming a point or a link
everywhere it is referred to, and setting a link side's length.
"""

from __future__ import annotations

import copy
import json
import math
import tomllib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from ..errors import InputError

__all__ = ["edit", "from_text", "normalise", "read_text", "save", "session"]


def normalise(doc: Mapping[str, Any]) -> dict[str, Any]:
    """The document as the spec reader reads it back: bare numbers in its ``[units]``.

    Raises the reader's error (naming the key) if the document is not valid.
    """
    from ..spec import read

    return read(doc).to_spec()


def from_text(text: str, name: str) -> dict[str, Any]:
    """A document from a machine file's text (TOML, or JSON when ``name`` ends in .json).

    Old ``machdyn linkage`` files are upgraded as :func:`machdyn.load` does; a
    ``[fourbar]`` or ``[slider_crank]`` part is drawn as a linkage (:func:`read_text`).
    """
    return read_text(text, name)[0]


def read_text(text: str, name: str) -> tuple[dict[str, Any], list[str]]:
    """The document of a machine file's text and what the page should tell about it.

    The notes say how a ``[fourbar]``/``[slider_crank]`` part was drawn as a linkage
    and what of it a linkage part cannot keep (:func:`machdyn.studio.convert.linkage_document`).
    """
    from .convert import linkage_document

    source = Path(name).name or "dropped file"
    if source.lower().endswith(".json"):
        try:
            doc = json.loads(text)
        except json.JSONDecodeError as exc:
            raise InputError(
                f"{source}:{exc.lineno}", f"JSON syntax error: {exc.msg} (column {exc.colno})"
            ) from None
        from ..spec import read

        return linkage_document(read(doc))
    try:
        tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(source, f"TOML syntax error: {exc}") from None
    from ..spec import loads  # the reader with line numbers and the old-format upgrade

    named = source if source.lower().endswith(".toml") else f"{source}.toml"
    return linkage_document(loads(text, named))


def session(file: Path | None, templates: Mapping[str, str]) -> dict[str, Any]:
    """What the page needs first: the file given on the command line (read) and the templates."""
    from .. import __version__

    out: dict[str, Any] = {
        "file": None if file is None else file.name,
        "doc": None,
        "error": None,
        "notes": [],
        "templates": dict(templates),
        "version": __version__,
    }
    if file is not None and file.exists():
        try:
            out["doc"], out["notes"] = read_text(file.read_text(encoding="utf-8"), file.name)
        except (InputError, UnicodeDecodeError, OSError) as exc:
            out["error"] = str(exc)
    return out


def save(file: Path | None, doc: Mapping[str, Any]) -> dict[str, Any]:
    """Write ``doc`` as TOML to the file named on the command line (the only one written).

    A document the spec reader refuses is not written (the reader's error, naming the
    key, is raised instead): a saved file always opens again, here and in ``machdyn run``.
    """
    from ..spec import dumps

    if file is None:
        raise InputError(
            "file",
            "the studio was started without a file: use Download to keep the design, "
            "or start it as 'machdyn studio NAME.toml'",
        )
    normalise(doc)  # (the file on disk is left as it was)
    _keeps_all(file)
    text = dumps(dict(doc)) if file.suffix.lower() != ".json" else json.dumps(doc, indent=2)
    file.write_text(text, encoding="utf-8")
    return {"saved": file.name, "bytes": len(text.encode("utf-8"))}


def _keeps_all(file: Path) -> None:
    """Refuse to overwrite a [fourbar]/[slider_crank] file whose drawing would lose keys."""
    from .convert import NOT_KEPT

    try:
        lost = [n for n in read_text(file.read_text(encoding="utf-8"), file.name)[1]
                if n.startswith(NOT_KEPT)]  # fmt: skip
    except (InputError, UnicodeDecodeError, OSError):
        return  # a file that does not open loses nothing the studio could show
    if lost:
        raise InputError(
            "file",
            f"{file.name} has keys the studio's linkage cannot hold, and Save would lose them "
            f"({' '.join(lost)}) Use Download to keep the design in a new file.",
        )


# ------------------------------------------------------------------- edits
_POINT_KEYS = {
    "sliders": ("at", "through", "direction"),
    "slots": ("pin", "through", "direction"),
    "actuators": ("start", "end"),
    "rolls": ("centre_a", "centre_b"),
    "motors": ("at",),
    "springs": ("start", "end"),
    "torsion_springs": ("at",),
}
_LINK_KEYS = {
    "sliders": ("block", "on"),
    "slots": ("link", "on"),
    "actuators": ("links",),
    "rolls": ("link_a", "link_b"),
    "motors": ("links",),
    "springs": ("links",),
    "torsion_springs": ("links",),
}


def _part(doc: dict, op: Mapping[str, Any]) -> dict:
    parts = doc.get("linkage") or {}
    name = op.get("part") or next(iter(parts), None)
    if name not in parts:
        raise InputError("op.part", f"no linkage part {name!r}")
    return parts[name]


def _swap(value: Any, old: str, new: str) -> Any:
    if value == old:
        return new
    if isinstance(value, list):
        return [_swap(v, old, new) for v in value]
    return value


def _rename_point(part: dict, old: str, new: str) -> None:
    if old not in part.get("points", {}):
        raise InputError("op.old", f"no point {old!r}")
    if new in part["points"]:
        raise InputError("op.new", f"a point {new!r} exists already")
    part["points"] = {(new if k == old else k): v for k, v in part["points"].items()}
    for key in ("ground", "report"):
        if key in part:
            part[key] = _swap(part[key], old, new)
    for link in part.get("links", {}).values():
        link["points"] = _swap(link["points"], old, new)
        if link.get("cg") == old:
            link["cg"] = new
    for table, keys in _POINT_KEYS.items():
        for entry in part.get(table, {}).values():
            for k in keys:
                if k in entry:
                    entry[k] = _swap(entry[k], old, new)
    for force in part.get("forces", []):
        force["at"] = _swap(force["at"], old, new)


def _rename_link(part: dict, old: str, new: str) -> None:
    links = part.get("links", {})
    if old not in links:
        raise InputError("op.old", f"no link {old!r}")
    taken = set(links) | {n for t in _LINK_KEYS for n in part.get(t, {})}
    if new in taken or new == "ground":
        raise InputError("op.new", f"the name {new!r} is taken")
    part["links"] = {(new if k == old else k): v for k, v in links.items()}
    part["drive"] = _swap(part.get("drive", []), old, new)
    for table, keys in _LINK_KEYS.items():
        for entry in part.get(table, {}).values():
            for k in keys:
                if k in entry:
                    entry[k] = _swap(entry[k], old, new)
    for force in part.get("forces", []):
        force["link"] = _swap(force["link"], old, new)
    for key in ("torques", "motion"):
        if key in part:
            part[key] = {(new if k == old else k): v for k, v in part[key].items()}


def _set_length(part: dict, op: Mapping[str, Any]) -> None:
    """Move point ``to`` along the line from ``from`` so that the side has ``value``."""
    pts = part.get("points", {})
    a, b = op.get("from"), op.get("to")
    if a not in pts or b not in pts:
        raise InputError("op", f"points {a!r} and {b!r} must both exist")
    value = op.get("value")
    if isinstance(value, bool) or not isinstance(value, int | float) or not value > 0:
        raise InputError("op.value", f"a length must be a positive number, got {value!r}")
    if not math.isfinite(value):
        raise InputError("op.value", f"must be finite, got {value!r}")
    (xa, ya), (xb, yb) = pts[a], pts[b]
    dx, dy = float(xb) - float(xa), float(yb) - float(ya)
    d = math.hypot(dx, dy)
    if d == 0.0:
        raise InputError("op", f"{a} and {b} coincide: the side has no direction to stretch along")
    pts[b] = [float(xa) + dx * value / d, float(ya) + dy * value / d]


def _flip(doc: dict, part: dict, op: Mapping[str, Any]) -> None:
    """Redraw the part on the other assembly of a dyad group (``Linkage.flipped``)."""
    from ..spec import read

    group = op.get("group")
    if not isinstance(group, str):
        raise InputError("op.group", f"a group's name is text, got {group!r}")
    name = next(k for k, v in doc["linkage"].items() if v is part)
    lk = read(doc).parts[name].model.flipped(group)
    part["points"] = {p: [float(z.real), float(z.imag)] for p, z in lk.points.items()}


def edit(doc: Mapping[str, Any], op: Mapping[str, Any]) -> dict[str, Any]:
    """Apply one edit to a copy of ``doc``.

    ``op`` is ``{"kind": "rename_point" | "rename_link", "old": ..., "new": ...}`` or
    ``{"kind": "length", "from": P, "to": Q, "value": L}`` (``Q`` moves along ``PQ``), or
    ``{"kind": "flip", "group": "RRR dyad (coupler, rocker)"}`` (the other assembly of
    that dyad, :meth:`Linkage.flipped`), with an optional ``"part"``.

    Examples
    --------
    >>> doc = {"machdyn": 1, "linkage": {"a": {"points": {"O": [0, 0], "A": [3, 4]},
    ...        "ground": ["O"], "drive": ["crank"], "links": {"crank": {"points": ["O", "A"]}}}}}
    >>> longer = edit(doc, {"kind": "length", "from": "O", "to": "A", "value": 10})
    >>> longer["linkage"]["a"]["points"]["A"]
    [6.0, 8.0]
    >>> edit(doc, {"kind": "rename_link", "old": "crank", "new": "arm"})["linkage"]["a"]["drive"]
    ['arm']
    """
    out = copy.deepcopy(dict(doc))
    part = _part(out, op)
    kind = op.get("kind")
    if kind in ("rename_point", "rename_link"):
        old, new = op.get("old"), op.get("new")
        if not isinstance(new, str) or not new.strip() or new != new.strip():
            raise InputError("op.new", f"a name is text without spaces at its ends, got {new!r}")
        (_rename_point if kind == "rename_point" else _rename_link)(part, old, new)
    elif kind == "length":
        _set_length(part, op)
    elif kind == "flip":
        _flip(out, part, op)
    else:
        raise InputError(
            "op.kind", f"must be rename_point, rename_link, length or flip, got {kind!r}"
        )
    return out
