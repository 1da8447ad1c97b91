"""Files in and out: one rule for every command.

Inputs: ``input_file`` says in one line whether a path is missing, a folder, or unreadable.

Outputs:

* A command refuses to replace an existing output unless told to (``--force``):
  ``check_output`` runs before any work, so a long trial never fails at its end for that.
* A file is written under a temporary name in the same folder
  (``NAME.partial-XXXXXX.SUFFIX``) and moved into place (``os.replace``) only when complete.
  A failed command removes its temporary file: it never leaves a stub and never destroys a
  good file. A killed command may leave its ``.partial-`` file behind; a killed recording's
  partial file reads like any truncated recording (``mimic info`` shows what it holds).
* Parent folders are created when the file is written (``check_output`` only checks that
  they can be).
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path

from mimic.errors import MimicError

__all__ = [
    "OutputError",
    "input_file",
    "check_output",
    "check_outputs",
    "PendingOutput",
    "atomic_output",
    "PARTIAL_MARK",
]

#: Part of the name of every temporary output file (``kick.partial-1a2b3c.mcap``).
PARTIAL_MARK = ".partial-"


class OutputError(MimicError):
    """An output that exists (and no ``--force``), is a folder, or cannot be written."""


def input_file(path: str | Path, what: str = "file", hint: str = "") -> Path:
    """``path`` if it is a readable file, else one clear error.

    Args:
        what: what the file should be (``recording``, ``model file``), for the message.
        hint: what to do when it is missing (appended after ``;``).

    Raises:
        MimicError: missing, a folder, or not readable.
    """
    path = Path(path)
    if path.is_dir():
        raise MimicError(f"{path}: is a directory, not a {what}; give a {what} inside it")
    if not path.exists():
        missing = what if what.endswith("file") else "file"
        raise MimicError(f"{path}: no such {missing}" + (f"; {hint}" if hint else ""))
    if not os.access(path, os.R_OK):
        raise MimicError(f"{path}: {what} not readable (permission denied)")
    return path


def check_output(path: str | Path, *, force: bool = False, flag: str = "--force") -> Path:
    """Before the work: ``path`` can be written (its folder exists or can be created; nothing
    is created yet).

    Raises:
        OutputError: ``path`` is a folder, exists and ``force`` is False, or its folder cannot
            be created or written.
    """
    path = Path(path)
    if path.is_dir():
        raise OutputError(f"{path}: is a directory; give a file name for the output")
    if path.exists() and not force:
        raise OutputError(f"{path} exists; pass {flag} to replace it, or choose another name")
    existing = Path(os.path.abspath(path)).parent
    while not existing.exists():
        existing = existing.parent
    if not existing.is_dir():
        raise OutputError(f"{path}: cannot create the folder {path.parent} ({existing} is a file)")
    if not os.access(existing, os.W_OK | os.X_OK):
        raise OutputError(f"{path}: cannot write in {existing} (permission denied)")
    return path


def check_outputs(paths: Iterable[str | Path | None], *, force: bool = False) -> list[Path]:
    """``check_output`` for each path given (None entries are skipped); no path twice."""
    out: list[Path] = []
    for p in paths:
        if p is None:
            continue
        p = Path(p)
        if any(os.path.abspath(p) == os.path.abspath(q) for q in out):
            raise OutputError(f"{p} is given for two outputs; give each its own file")
        out.append(check_output(p, force=force))
    return out


def _make_parent(path: Path) -> None:
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        raise OutputError(
            f"{path}: cannot create the folder {path.parent} ({err.strerror or err})"
        ) from None


class PendingOutput:
    """A file being written under a temporary name beside ``path``.

    ``commit`` moves it into place; ``discard`` removes it. With ``overwrite`` False,
    ``commit`` refuses (and keeps the temporary file) when ``path`` appeared meanwhile.

    Attributes:
        path: the output's final name.
        tmp: where it is written until ``commit``.
    """

    def __init__(self, path: str | Path, *, overwrite: bool = True) -> None:
        self.path = Path(path)
        self.overwrite = overwrite
        if self.path.is_dir():
            raise OutputError(f"{self.path}: is a directory; give a file name for the output")
        _make_parent(self.path)
        try:
            fd, tmp = tempfile.mkstemp(
                dir=self.path.parent, suffix=self.path.suffix, prefix=self.path.stem + PARTIAL_MARK
            )
        except OSError as err:
            raise OutputError(
                f"{self.path}: cannot write in {self.path.parent} ({err.strerror or err})"
            ) from None
        os.close(fd)
        self.tmp = Path(tmp)
        self.done = False

    def commit(self) -> Path:
        """Move the written file to its name; returns the name."""
        if self.done:
            return self.path
        if self.overwrite:
            os.replace(self.tmp, self.path)
        else:
            try:
                os.link(self.tmp, self.path)  # fails if the name exists: never replaces
            except FileExistsError:
                raise OutputError(
                    f"{self.path} appeared while this command ran; kept the new "
                    f"file as {self.tmp}; pass --force to replace"
                ) from None
            except OSError:  # no hard links here: check, then move
                if self.path.exists():
                    raise OutputError(
                        f"{self.path} appeared while this command ran; kept the "
                        f"new file as {self.tmp}; pass --force to replace"
                    ) from None
                os.replace(self.tmp, self.path)
            else:
                os.unlink(self.tmp)
        self.done = True
        return self.path

    def discard(self) -> None:
        """Remove the temporary file (nothing is left under either name)."""
        if not self.done:
            self.done = True
            try:
                os.unlink(self.tmp)
            except FileNotFoundError:
                pass


@contextmanager
def atomic_output(path: str | Path, *, overwrite: bool = True) -> Iterator[Path]:
    """Write to the yielded temporary path; it becomes ``path`` when the block succeeds.

    Example::

        with atomic_output("out/kick.parquet") as tmp:
            table.write_parquet(tmp)
    """
    pending = PendingOutput(path, overwrite=overwrite)
    try:
        yield pending.tmp
    except BaseException:
        pending.discard()
        raise
    pending.commit()
