"""Every command of the README's command-line block runs as written (exit status 0).

The commands run in a scratch folder that sees the repository's ``docs/``
(they read ``docs/examples/...`` and write files such as ``torque.csv`` next to
the user), in order: a later command may read what an earlier one wrote.
"""

from __future__ import annotations

import os
import shlex
from pathlib import Path

import pytest

from machdyn.cli import main

ROOT = Path(__file__).resolve().parents[1]
#: Commands too heavy for the test suite, with the reason (they have their own tests).
HEAVY: dict[str, str] = {}


def readme_commands() -> list[str]:
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    block = text.split("From the command line", 1)[1].split("```bash\n", 1)[1].split("```", 1)[0]
    commands, current = [], ""
    for line in block.splitlines():
        line = line.split("  #", 1)[0].rstrip() if "  #" in line else line.rstrip()
        current += line.rstrip("\\").strip() + " "
        if not line.endswith("\\"):
            if current.strip():
                commands.append(current.strip())
            current = ""
    return commands


def test_the_block_is_found():
    commands = readme_commands()
    assert len(commands) >= 10 and all(c.startswith("machdyn ") for c in commands)


def test_every_readme_command_runs(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    (tmp_path / "docs").symlink_to(ROOT / "docs")
    here = os.getcwd()
    os.chdir(tmp_path)
    try:
        for command in readme_commands():
            if any(key in command for key in HEAVY):
                continue
            args = shlex.split(command)[1:]
            status = main(args)
            err = capsys.readouterr().err
            assert status == 0, f"{command}: {err}"
            assert "error" not in err, f"{command}: {err}"
    finally:
        os.chdir(here)
    assert (tmp_path / "torque.csv").is_file()
