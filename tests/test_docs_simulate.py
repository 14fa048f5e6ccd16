"""docs/simulate.md: its Python examples run, in order, in one namespace."""

from __future__ import annotations

import re
from pathlib import Path

DOC = Path(__file__).resolve().parents[1] / "docs" / "simulate.md"
BLOCKS = re.findall(r"```python\n(.*?)```", DOC.read_text(encoding="utf-8"), flags=re.S)


def test_examples_run_in_order():
    namespace: dict = {}
    for index, block in enumerate(BLOCKS):
        exec(compile(block, f"docs/simulate.md block {index + 1}", "exec"), namespace)
    assert len(BLOCKS) >= 3
