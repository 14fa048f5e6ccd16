"""The typer application and the registration of every subcommand."""

from __future__ import annotations

import typer

app = typer.Typer(
    name="machdyn",
    help="Kinematics and dynamics of machines: linkages, cams and gears.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)


@app.callback()
def _root() -> None:
    """Kinematics and dynamics of machines: linkages, cams and gears."""


def _register() -> None:
    # Imported here so that each module can import ``app`` from this one.
    from . import fourbar  # noqa: F401  (registers `fourbar` and `demo` on app)
    from .atlas import atlas_app
    from .balance import balance_app
    from .cam import cam_app
    from .flywheel import flywheel as flywheel_command
    from .gear import gear_app
    from .linkage import linkage
    from .plot import animate
    from .report import report
    from .run import run, spec_app
    from .simulate import simulate_command, tolerance_command
    from .studio import studio
    from .synth import synth_app

    app.command("flywheel")(flywheel_command)
    app.add_typer(balance_app, name="balance")
    app.add_typer(cam_app, name="cam")
    app.add_typer(gear_app, name="gear")
    app.command("linkage")(linkage)
    app.command("animate")(animate)
    app.command("report")(report)
    app.add_typer(synth_app, name="synth")
    app.add_typer(atlas_app, name="atlas")
    app.command("run")(run)
    app.add_typer(spec_app, name="spec")
    app.command("studio")(studio)
    app.command("simulate")(simulate_command)
    app.command("tolerance")(tolerance_command)


_register()
