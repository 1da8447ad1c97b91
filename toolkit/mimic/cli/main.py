"""The `mimic` application: one Typer app; each command group lives in its own module."""

from __future__ import annotations

import importlib

import typer

from mimic import __version__
from mimic.cli.common import OneLineUsageErrors

app = typer.Typer(
    name="mimic",
    cls=OneLineUsageErrors,
    help="Learn humanoid robot motions as neural networks and prove them in MuJoCo.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_show_locals=False,
)

#: Modules under mimic.cli that each define ``register(app)``.
COMMAND_MODULES: tuple[str, ...] = (
    "record",
    "trial",
    "view",
    "pipeline",
    "train",
    "robots",
    "play",
    "improve",
)


def _version(value: bool) -> None:
    if value:
        typer.echo(f"mimic {__version__}")
        raise typer.Exit()


@app.callback()
def _root(
    version: bool = typer.Option(
        False, "--version", callback=_version, is_eager=True, help="Print the version and exit."
    ),
) -> None:
    """Learn humanoid robot motions as neural networks and prove them in MuJoCo."""


for _name in COMMAND_MODULES:
    importlib.import_module(f"mimic.cli.{_name}").register(app)
