"""Friction and masses of a compiled MuJoCo model, scaled from their values as built.

The worlds that step their own physics (ours, and the league's simulation in process) scale
them per episode for ``episode.disturbance``; every call starts from the nominal values, so
calls never compound.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

__all__ = ["NominalPhysics"]


@dataclass(frozen=True)
class NominalPhysics:
    """A model's sliding friction per geom, and mass and inertia per body, as built."""

    friction: np.ndarray
    mass_kg: np.ndarray
    inertia: np.ndarray

    @classmethod
    def of(cls, model) -> NominalPhysics:
        return cls(
            model.geom_friction[:, 0].copy(), model.body_mass.copy(), model.body_inertia.copy()
        )

    def apply(
        self, model, link_ids: np.ndarray, friction_scale: float, link_mass_scales: np.ndarray
    ) -> None:
        """Every geom's sliding friction times ``friction_scale``; the mass and inertia of the
        bodies ``link_ids`` times ``link_mass_scales`` ((L,), one per body); the rest nominal."""
        scales = np.asarray(link_mass_scales, dtype=float)
        if scales.shape != np.shape(link_ids):
            raise ValueError(f"{len(link_ids)} link mass scales expected, got {scales.shape}")
        model.geom_friction[:, 0] = self.friction * friction_scale
        model.body_mass[:], model.body_inertia[:] = self.mass_kg, self.inertia
        model.body_mass[link_ids] = self.mass_kg[link_ids] * scales
        model.body_inertia[link_ids] = self.inertia[link_ids] * scales[:, None]
        # Derived constants (subtree masses, the solver's inverse weights) as if compiled so,
        # worked out on scratch data (the world's own state is left as it is).
        mujoco.mj_setConst(model, mujoco.MjData(model))
