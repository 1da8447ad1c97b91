"""A search space: named parameters searched in units of their own scale.

CMA-ES works best when every coordinate moves on a similar scale. Each parameter has a base
value (the target as it is), a scale (the change worth one search unit) and bounds, and the
search sees z with value = base + scale * z; z = 0 is the target unchanged.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Space"]


@dataclass(frozen=True)
class Space:
    """Parameters as named (d,) arrays.

    Attributes:
        names: (d,) parameter names, e.g. ``offset.right_hip_roll``.
        base: (d,) values of the target as it is (z = 0), in the parameters' own units.
        scale: (d,) change per search unit, same units (> 0).
        lower, upper: (d,) bounds, same units; ``lower <= base <= upper``.
    """

    names: tuple[str, ...]
    base: np.ndarray
    scale: np.ndarray
    lower: np.ndarray
    upper: np.ndarray

    def __post_init__(self) -> None:
        d = len(self.names)
        for key in ("base", "scale", "lower", "upper"):
            value = np.asarray(getattr(self, key), dtype=float)
            if value.shape != (d,):
                raise ValueError(f"space {key} has shape {value.shape}, expected ({d},)")
            value.setflags(write=False)
            object.__setattr__(self, key, value)
        if d == 0:
            raise ValueError("a search space needs at least one parameter")
        if (self.scale <= 0).any():
            raise ValueError("every scale must be > 0")
        if not ((self.lower <= self.base) & (self.base <= self.upper)).all():
            bad = [
                n
                for n, lo, b, hi in zip(self.names, self.lower, self.base, self.upper)
                if not lo <= b <= hi
            ]
            raise ValueError(f"base values outside their bounds: {', '.join(bad)}")

    @property
    def dim(self) -> int:
        return len(self.names)

    def values(self, z: np.ndarray) -> np.ndarray:
        """(d,) parameter values for search point z (d,), clipped into the bounds."""
        return np.clip(self.base + self.scale * np.asarray(z, dtype=float), self.lower, self.upper)

    def bounds_z(self) -> np.ndarray:
        """(d, 2) bounds in search units, for the optimiser."""
        return np.stack(
            [(self.lower - self.base) / self.scale, (self.upper - self.base) / self.scale], axis=1
        )

    def describe(self, z: np.ndarray) -> dict[str, float]:
        """Parameter values by name (JSON-able)."""
        return {n: float(v) for n, v in zip(self.names, self.values(z))}
