"""``machdyn studio [FILE]``: design a mechanism in the browser (a local web app).

Only parsing and starting: the server is :class:`machdyn.studio.server.Studio`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ..errors import InputError

__all__ = ["studio"]


def studio(
    file: Annotated[
        Path | None,
        typer.Argument(help="Machine file to open and save to (created on the first save)."),
    ] = None,
    port: Annotated[int, typer.Option("--port", help="Port on 127.0.0.1 (0: any free one).")] = 0,
    no_browser: Annotated[
        bool, typer.Option("--no-browser", help="Print the address; do not open a browser.")
    ] = False,
) -> None:
    """Open the studio: sketch, drag, analyse and synthesise linkages in the browser."""
    if file is not None and file.exists() and not file.is_file():
        raise InputError(str(file), "not a file")
    if file is not None and file.suffix.lower() not in (".toml", ".json"):
        raise InputError(str(file), "a machine file ends in .toml or .json")
    if not 0 <= port <= 65535:
        raise InputError("--port", f"must be 0 to 65535, got {port}")
    from ..studio.server import Studio

    server = Studio(file, port=port)
    import webbrowser

    def opened() -> None:
        print(f"machdyn studio: {server.url}  (Ctrl-C stops it)", flush=True)
        if not no_browser:
            webbrowser.open(server.url)

    server.on_ready = opened
    try:
        server.serve_forever()
    except KeyboardInterrupt:
        print("machdyn studio: stopped", flush=True)
