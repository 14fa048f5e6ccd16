"""``machdyn synth ...`` builds only the synth group (as ``run`` and ``studio`` do)."""

from __future__ import annotations

import subprocess
import sys

_CHILD = """
import sys
from machdyn.cli import main
status = main(sys.argv[1:])
print("STATUS", status, "cam" if "machdyn.cli.cam" in sys.modules else "no-cam",
      "app" if "machdyn.cli.app" in sys.modules else "no-app")
"""


def _run(*args: str) -> tuple[str, str]:
    done = subprocess.run([sys.executable, "-c", _CHILD, *args], capture_output=True, text=True,
                          check=True)  # fmt: skip
    return done.stdout, done.stderr


def test_synth_path_help_without_the_other_subcommands():
    out, _ = _run("synth", "path", "--help")
    assert "machdyn synth path" in out and "--atlas" in out
    assert "STATUS 0 no-cam no-app" in out


def test_synth_usage_errors_as_before():
    out, err = _run("synth", "nosuch")
    assert "STATUS 2 no-cam no-app" in out
    assert "No such command 'nosuch'" in err
    out, _ = _run("fourbar", "--help")  # any other command: the whole application
    assert "STATUS 0 cam app" in out
