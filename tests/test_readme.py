"""The README's promises: its quick start runs and it keeps exactly two set-up commands."""

from __future__ import annotations

import re
from pathlib import Path

README = Path(__file__).resolve().parents[1] / "README.md"


def blocks(lang: str) -> list[str]:
    return re.findall(rf"```{lang}\n(.*?)```", README.read_text(), flags=re.S)


def test_quick_start_runs():
    (code, *_) = blocks("python")
    namespace: dict = {}
    exec(compile(code, "README quick start", "exec"), namespace)
    assert namespace["fb"].barker_class == "GCRR"


def test_exactly_two_setup_commands_and_ci_runs_the_test_one():
    setup = README.read_text().split("## Set up", 1)[1].split("\n## ", 1)[0]
    commands = [b.strip() for b in re.findall(r"```bash\n(.*?)```", setup, flags=re.S)]
    assert commands == [
        "pip install . && machdyn demo",
        'pip install -e ".[test]" && python -m pytest',
    ]
    ci = (README.parent / ".ci" / "run").read_text()
    assert commands[1] in ci
