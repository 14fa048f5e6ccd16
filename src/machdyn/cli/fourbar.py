"""``machdyn fourbar`` and ``machdyn demo`` (filled in by the FourBar work)."""

from __future__ import annotations

from .app import app


@app.command()
def demo() -> None:
    """Analyse a built-in four-bar and print its class, limits and kinematics."""
    print("machdyn demo: the four-bar analysis is being built")
