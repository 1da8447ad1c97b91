"""Text and sizes from outside: a game log or a server is untrusted input.

Names a log or a server sends (team names, robot models) are shown with ``printable`` (control
characters escaped, so nothing reaches the terminal raw) and become file names only through
``safe_stem`` (never a path outside the output folder). A message or a log line is at most
``MAX_MESSAGE_BYTES`` long.
"""

from __future__ import annotations

import re
import unicodedata

__all__ = ["printable", "safe_stem", "text_of", "MAX_MESSAGE_BYTES", "MAX_STEM_CHARS"]

#: The longest monitor message or game-log line accepted [bytes]. A full frame of two full
#: teams of T1s is about 0.5 MB; anything near this is not a frame.
MAX_MESSAGE_BYTES = 64 * 1024 * 1024
#: The longest file-name stem made from a name [characters].
MAX_STEM_CHARS = 64

_UNSAFE_STEM = re.compile(r"[^\w.-]+")


def text_of(atom: bytes) -> str:
    """An s-expression atom as text: UTF-8, undecodable bytes kept as ``\\xNN``.

    Raises:
        ValueError: ``atom`` is not an atom (a list where a name belongs).
    """
    if not isinstance(atom, bytes):
        raise ValueError(f"expected a name, got a list: {atom!r:.40}")
    return atom.decode("utf-8", errors="backslashreplace")


def printable(text: str) -> str:
    """``text`` safe to print: control and other non-printing characters (ANSI escapes, new
    lines, bidi overrides) as ``\\xNN``/``\\uNNNN``; everything else as it is. Print the result
    as plain text (Rich: ``markup=False``), never as markup."""
    out = []
    for ch in text:
        if ch.isprintable() and unicodedata.category(ch) not in ("Cf", "Zl", "Zp"):
            out.append(ch)
        else:
            out.append(ch.encode("unicode_escape").decode("ascii"))
    return "".join(out)


def safe_stem(name: str) -> str:
    """A file-name stem made from ``name``: letters, digits, ``.``, ``_`` and ``-`` only
    (anything else, ``/`` included, becomes ``_``), no leading dot or dash, at most
    ``MAX_STEM_CHARS``; ``_`` when nothing is left. It never names a path outside its
    folder."""
    stem = _UNSAFE_STEM.sub("_", name).lstrip(".-")[:MAX_STEM_CHARS]
    return stem or "_"
