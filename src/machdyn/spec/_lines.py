"""Line numbers of the keys of a TOML document (tomllib does not report them).

A small scanner over the source text follows table headers (``[a.b]``,
``[[a.b]]``) and ``key = value`` lines, skipping strings, comments and values
that span lines, and records the line of every key path it meets. Paths are
tuples of keys, with 1-based integer indices for the elements of arrays of
tables, as the spec reader names them. A path the scanner did not record (a key
inside an inline table, an element of a multi-line array) is found by its
longest recorded prefix: the line of the value that holds it.
"""

from __future__ import annotations

import re

__all__ = ["KeyLines"]

_BARE = re.compile(r"[A-Za-z0-9_-]+")


def _key(text: str, pos: int) -> tuple[list[str], int]:
    """Parse a dotted key at ``pos``; return its parts and the position after it."""
    parts: list[str] = []
    n = len(text)
    while True:
        while pos < n and text[pos] in " \t":
            pos += 1
        if pos >= n:
            break
        ch = text[pos]
        if ch in "\"'":
            end = pos + 1
            buf = []
            while end < n and text[end] != ch:
                if ch == '"' and text[end] == "\\" and end + 1 < n:
                    esc = text[end + 1]
                    buf.append({"n": "\n", "t": "\t", '"': '"', "\\": "\\"}.get(esc, esc))
                    end += 2
                    continue
                buf.append(text[end])
                end += 1
            parts.append("".join(buf))
            pos = end + 1
        else:
            match = _BARE.match(text, pos)
            if not match:
                break
            parts.append(match.group(0))
            pos = match.end()
        while pos < n and text[pos] in " \t":
            pos += 1
        if pos < n and text[pos] == ".":
            pos += 1
            continue
        break
    return parts, pos


class _Value:
    """Tracks brackets and strings of a value across lines."""

    def __init__(self) -> None:
        self.depth = 0
        self.string: str | None = None  # the closing delimiter of an open multi-line string

    def feed(self, line: str, start: int = 0) -> None:
        i, n = start, len(line)
        while i < n:
            if self.string is not None:
                end = line.find(self.string, i)
                if end < 0:
                    return
                i = end + 3
                self.string = None
                continue
            ch = line[i]
            if ch == "#":
                return
            if line.startswith(('"""', "'''"), i):
                self.string = line[i : i + 3]
                i += 3
                continue
            if ch in "\"'":
                i += 1
                while i < n and line[i] != ch:
                    i += 2 if (ch == '"' and line[i] == "\\") else 1
                i += 1
                continue
            if ch in "[{":
                self.depth += 1
            elif ch in "]}":
                self.depth -= 1
            i += 1

    @property
    def open(self) -> bool:
        return self.depth > 0 or self.string is not None


class KeyLines:
    """The line of every key path of a TOML text.

    Examples
    --------
    >>> text = '''machdyn = 1
    ... [fourbar.hw6]
    ... r1 = 8
    ... coupler = { p = 5, delta = "30 deg" }
    ... [[cam.c.segment]]
    ... motion = "dwell"
    ... [[cam.c.segment]]
    ... beta = 60
    ... '''
    >>> lines = KeyLines(text)
    >>> lines.line(("fourbar", "hw6", "r1")), lines.line(("fourbar", "hw6", "coupler", "p"))
    (3, 4)
    >>> lines.line(("cam", "c", "segment", 2, "beta")), lines.line(("fourbar", "hw6", "r9"))
    (8, 2)
    """

    def __init__(self, text: str) -> None:
        self.lines: dict[tuple, int] = {}
        self._arrays: dict[tuple, int] = {}
        current: tuple = ()
        value = _Value()
        for number, raw in enumerate(text.splitlines(), start=1):
            if value.open:
                value.feed(raw)
                continue
            stripped = raw.lstrip()
            if not stripped or stripped.startswith("#"):
                continue
            offset = len(raw) - len(stripped)
            if stripped.startswith("[["):
                parts, _ = _key(raw, offset + 2)
                current = self._resolve(parts, array=True)
                self._record(current, number)
            elif stripped.startswith("["):
                parts, _ = _key(raw, offset + 1)
                current = self._resolve(parts)
                self._record(current, number)
            else:
                parts, pos = _key(raw, offset)
                if not parts:
                    continue
                self._record((*current, *parts), number)
                eq = raw.find("=", pos)
                if eq >= 0:
                    value.feed(raw, eq + 1)

    def _resolve(self, parts: list[str], array: bool = False) -> tuple:
        path: tuple = ()
        for k, part in enumerate(parts):
            path = (*path, part)
            last = k == len(parts) - 1
            if last and array:
                self._arrays[path] = self._arrays.get(path, 0) + 1
            if path in self._arrays:
                path = (*path, self._arrays[path])
        return path

    def _record(self, path: tuple, number: int) -> None:
        for k in range(1, len(path) + 1):
            self.lines.setdefault(path[:k], number)
        self.lines[path] = number

    def line(self, path: tuple) -> int | None:
        """The line of ``path``, or of its longest recorded prefix (None if none)."""
        path = tuple(path)
        while path:
            if path in self.lines:
                return self.lines[path]
            path = path[:-1]
        return None
