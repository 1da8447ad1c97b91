"""What every command shares: turning toolkit errors into one line and an exit code."""

from __future__ import annotations

import functools
import sys
from collections.abc import Callable
from typing import TypeVar

import typer
from rich.console import Console

from mimic.errors import MimicError

__all__ = ["console", "err_console", "reports_errors", "fail"]

console = Console()
err_console = Console(stderr=True)
F = TypeVar("F", bound=Callable)


def fail(message: str, code: int = 2) -> None:
    """Print ``error: message`` on stderr and exit with ``code``."""
    err_console.print(f"[bold red]error:[/] {message}", highlight=False, soft_wrap=True)
    raise typer.Exit(code)


def reports_errors(func: F) -> F:
    """Decorator for commands: a ``MimicError`` becomes one clear line and a non-zero exit;
    Ctrl-C exits with 130 after whatever cleanup the library did (files are closed)."""

    @functools.wraps(func)
    def wrapper(*args, **kwargs):
        try:
            return func(*args, **kwargs)
        except MimicError as err:
            fail(str(err), err.exit_code)
        except KeyboardInterrupt:
            err_console.print("interrupted", highlight=False)
            sys.stderr.flush()
            raise typer.Exit(130) from None

    return wrapper  # type: ignore[return-value]
