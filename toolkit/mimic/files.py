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
* An output is never also an input: ``check_output(..., inputs=...)`` refuses, with or
  without ``--force`` (``mimic play M.mimic -o M.mimic`` would destroy the model).
* One writer per output: while a command writes a file (``PendingOutput``, or from
  ``claim_output`` on, for a command that waits before it writes) it holds an exclusive lock
  (``.NAME.lock`` beside it, removed when done; a killed command's lock is released by the
  system), and a second command for the same file is refused at once.
* Outputs get the mode a plain ``open()`` gives (``0o666`` less the umask), not the
  ``0o600`` of a temporary file.
"""

from __future__ import annotations

import os
import tempfile
import threading
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
    "claim_output",
    "same_file",
    "spec_files",
    "plain_file_mode",
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


def same_file(a: str | Path, b: str | Path) -> bool:
    """True when ``a`` and ``b`` name one file (links and ``..`` resolved)."""
    try:
        return os.path.samefile(a, b)
    except OSError:  # one of them does not exist (yet)
        return os.path.realpath(a) == os.path.realpath(b)


def spec_files(*specs: str | Path | None) -> list[Path]:
    """The files agent specs name (``kick.mimic+balance``: ``kick.mimic``; ``walk.json``,
    ``kick.txt``), for ``check_output``'s ``inputs``; names of shipped motions and behaviours
    (no suffix) name no file."""
    out = []
    for spec in specs:
        if spec is None:
            continue
        path = Path(str(spec).removesuffix("+balance"))
        if path.suffix:
            out.append(path)
    return out


def check_output(
    path: str | Path,
    *,
    force: bool = False,
    flag: str = "--force",
    inputs: Iterable[str | Path | None] = (),
) -> Path:
    """Before the work: ``path`` can be written (its folder exists or can be created; nothing
    is created yet), is none of the command's ``inputs``, and no other command is writing it.

    Raises:
        OutputError: ``path`` is a folder, is an input, exists and ``force`` is False, another
            command is writing it, or its folder cannot be created or written.
    """
    path = Path(path)
    if path.is_dir():
        raise OutputError(f"{path}: is a directory; give a file name for the output")
    for source in inputs:
        if source is not None and same_file(path, source):
            raise OutputError(
                f"{path} is also an input of this command; give the output another name"
            )
    holder = _claim_holder(path)
    if holder is not None:
        raise OutputError(_busy(path, holder))
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


def check_outputs(
    paths: Iterable[str | Path | None],
    *,
    force: bool = False,
    inputs: Iterable[str | Path | None] = (),
) -> list[Path]:
    """``check_output`` for each path given (None entries are skipped); no path twice."""
    out: list[Path] = []
    inputs = list(inputs)
    for p in paths:
        if p is None:
            continue
        p = Path(p)
        if any(os.path.abspath(p) == os.path.abspath(q) for q in out):
            raise OutputError(f"{p} is given for two outputs; give each its own file")
        out.append(check_output(p, force=force, inputs=inputs))
    return out


def plain_file_mode() -> int:
    """The mode ``open(path, "w")`` gives a new file: ``0o666`` less the process's umask."""
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("Umask:"):
                    return 0o666 & ~int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    with _UMASK_LOCK:  # no /proc: read the umask by setting it (and back at once)
        umask = os.umask(0o022)
        os.umask(umask)
    return 0o666 & ~umask


_UMASK_LOCK = threading.Lock()

# --- one writer per output ------------------------------------------------------------------
#: Outputs this process holds: absolute path -> [lock file descriptor, holders].
_CLAIMS: dict[str, list[int]] = {}


def _lock_path(path: Path) -> Path:
    return path.with_name(f".{path.name}.lock")


def _busy(path: Path, holder: str) -> str:
    return (
        f"{path} is being written by another command ({holder}); wait for it to "
        "finish, or choose another name"
    )


def _claim_holder(path: Path) -> str | None:
    """Who holds ``path`` (``pid N``), when another process does; None when nobody does."""
    try:
        import fcntl
    except ImportError:  # not POSIX: no locks
        return None
    if os.path.abspath(path) in _CLAIMS:
        return None
    try:
        fd = os.open(_lock_path(path), os.O_RDONLY)
    except OSError:
        return None
    try:
        fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
    except BlockingIOError:
        text = os.pread(fd, 32, 0).decode(errors="replace").strip()
        return f"pid {text}" if text.isdigit() else "another process"
    except OSError:
        return None
    finally:
        os.close(fd)
    return None


def _acquire(path: Path) -> None:
    key = os.path.abspath(path)
    if key in _CLAIMS:
        _CLAIMS[key][1] += 1
        return
    try:
        import fcntl
    except ImportError:
        _CLAIMS[key] = [-1, 1]
        return
    lock = _lock_path(Path(key))
    while True:
        try:
            fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o666)
        except OSError as err:
            raise OutputError(
                f"{path}: cannot write in {path.parent} ({err.strerror or err})"
            ) from None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.pread(fd, 32, 0).decode(errors="replace").strip()
            os.close(fd)
            raise OutputError(
                _busy(path, f"pid {holder}" if holder.isdigit() else "another process")
            ) from None
        try:  # its last holder may have removed it between our open and our lock
            if os.fstat(fd).st_ino == os.stat(lock).st_ino:
                break
        except FileNotFoundError:
            pass
        os.close(fd)
    os.ftruncate(fd, 0)
    os.pwrite(fd, str(os.getpid()).encode(), 0)
    _CLAIMS[key] = [fd, 1]


def _release(path: Path) -> None:
    key = os.path.abspath(path)
    claim = _CLAIMS.get(key)
    if claim is None:
        return
    claim[1] -= 1
    if claim[1] > 0:
        return
    del _CLAIMS[key]
    if claim[0] >= 0:
        try:
            os.unlink(_lock_path(Path(key)))  # while locked: nobody else removes it
        except OSError:
            pass
        os.close(claim[0])


@contextmanager
def claim_output(path: str | Path) -> Iterator[Path]:
    """Hold ``path`` as this command's output for the block: another command that writes it
    meanwhile is refused (``check_output`` and ``PendingOutput`` see the claim). For a command
    that waits before it writes (``mimic record --server``). Creates the parent folders.

    Raises:
        OutputError: another command holds ``path``, or its folder cannot be written.
    """
    path = Path(path)
    _make_parent(path)
    _acquire(path)
    try:
        yield path
    finally:
        _release(path)


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
        _acquire(self.path)
        try:
            fd, tmp = tempfile.mkstemp(
                dir=self.path.parent, suffix=self.path.suffix, prefix=self.path.stem + PARTIAL_MARK
            )
        except OSError as err:
            _release(self.path)
            raise OutputError(
                f"{self.path}: cannot write in {self.path.parent} ({err.strerror or err})"
            ) from None
        try:
            os.fchmod(fd, plain_file_mode())  # mkstemp makes it 0o600
        finally:
            os.close(fd)
        self.tmp = Path(tmp)
        self.done = False

    def commit(self) -> Path:
        """Move the written file to its name; returns the name."""
        if self.done:
            return self.path
        try:
            return self._commit()
        finally:
            if self.done:
                _release(self.path)

    def _commit(self) -> Path:
        if self.overwrite:
            os.replace(self.tmp, self.path)
        else:
            try:
                os.link(self.tmp, self.path)  # fails if the name exists: never replaces
            except FileExistsError:
                self.done = True  # the temporary file stays, under its name in the message
                raise OutputError(
                    f"{self.path} appeared while this command ran; kept the new "
                    f"file as {self.tmp}; pass --force to replace"
                ) from None
            except OSError:  # no hard links here: check, then move
                if self.path.exists():
                    self.done = True
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
            finally:
                _release(self.path)


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
