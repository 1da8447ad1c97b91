"""Checks of option values shared by the library and the CLI: finite numbers in range, seeds,
counts. Each error names the CLI flag, the value and the range, in one line."""

from __future__ import annotations

import math

from mimic.errors import MimicError

__all__ = ["OptionError", "finite", "seed", "count", "workers", "MAX_SEED"]

#: Largest seed numpy's generators and ``np.random.seed`` accept.
MAX_SEED = 2**32 - 1


class OptionError(MimicError):
    """An option value out of its range (NaN, infinite, negative, zero where it may not be)."""


def finite(
    value: float | None,
    flag: str,
    *,
    above: float | None = None,
    at_least: float | None = None,
    at_most: float | None = None,
) -> float | None:
    """``value`` if it is a finite number in range (None passes through).

    Args:
        above: exclusive lower bound; at_least: inclusive lower bound; at_most: inclusive
            upper bound.

    Raises:
        OptionError: NaN, infinite, or out of range.
    """
    if value is None:
        return None
    parts = (
        ([f"> {above:g}"] if above is not None else [])
        + ([f">= {at_least:g}"] if at_least is not None else [])
        + ([f"<= {at_most:g}"] if at_most is not None else [])
    )
    want = "a finite number" + (f" {' and '.join(parts)}" if parts else "")
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise OptionError(f"{flag} must be {want}, got {value!r}") from None
    if (
        not math.isfinite(v)
        or (above is not None and not v > above)
        or (at_least is not None and not v >= at_least)
        or (at_most is not None and not v <= at_most)
    ):
        raise OptionError(f"{flag} must be {want}, got {value}")
    return v


def seed(value: int, flag: str = "--seed") -> int:
    """A seed in 0 .. 2**32 - 1 (what numpy's generators accept)."""
    if not isinstance(value, int) or isinstance(value, bool) or not 0 <= value <= MAX_SEED:
        raise OptionError(f"{flag} must be a whole number from 0 to {MAX_SEED}, got {value}")
    return value


def count(value: int | None, flag: str, *, at_least: int = 1) -> int | None:
    """A whole number >= ``at_least`` (None passes through)."""
    if value is None:
        return None
    if not isinstance(value, int) or isinstance(value, bool) or value < at_least:
        raise OptionError(f"{flag} must be a whole number >= {at_least}, got {value}")
    return value


def workers(value: int | None) -> int | None:
    """Worker processes: None (all cores) or at least 1."""
    return count(value, "--workers")
