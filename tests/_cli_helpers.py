"""What every CLI test of bad input checks: one ``error:`` line, its exit status, no traceback."""

from __future__ import annotations


def one_line_error(result, code: int, *fragments: str) -> str:
    """The single line of ``result`` (a ``CliRunner`` result): exit ``code``, no traceback, no
    blank line before it, starting ``error: `` and holding every fragment."""
    assert result.exit_code == code, result.output
    assert "Traceback" not in result.output
    lines = result.output.splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), lines
    for fragment in fragments:
        assert fragment in lines[0], lines[0]
    return lines[0]
