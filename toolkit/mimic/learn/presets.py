"""Training presets: the study's faithful setup (``paper``) and a faster, better one (``fast``).

Both use the same network (Dense 75 -> LeakyReLU(0.3) -> Dense 50 -> LeakyReLU(0.3) ->
Dense N + 1 for a robot's N joints and the ended flag; for our NAO 5123 parameters with the time
input, 5198 with a cyclic motion's phase input (sin, cos)), full-batch Adam (0.9, 0.999, 1e-8)
on the mean squared error.

``paper`` (the study): raw time [s] in, raw radians out, Keras-default init (glorot_uniform,
zero biases), 30000 epochs at 1e-3 then 5000 each at 8e-4, 6e-4, 4e-4, 2e-4, Adam state reset
at every phase (50000 epochs).

``fast`` (default): time scaled to [-1, 1] over the motion, he_uniform init, learning rate
1e-2 decayed in phases to 1e-4 (Adam reset per phase, as in the study), 25000 epochs; raw
radians out. Why each of these, measured one at a time against the study's setup:
``docs/tuning-notes.md`` ("Training presets").
"""

from __future__ import annotations

from dataclasses import dataclass, replace

__all__ = ["Phase", "Preset", "PAPER", "FAST", "PRESETS", "get_preset"]


@dataclass(frozen=True)
class Phase:
    """A run of full-batch epochs at one learning rate (Adam restarts at each phase)."""

    # Number of epochs.
    epochs: int
    # Adam learning rate.
    lr: float


@dataclass(frozen=True)
class Preset:
    """How a motion network is trained."""

    # Name (stored in the model file).
    name: str
    # Learning-rate phases in order.
    phases: tuple[Phase, ...]
    # Map time to [-1, 1] over the motion (False: raw seconds, as in the study).
    scale_input: bool
    # Standardise each output (False: raw radians and flag, as in the study).
    standardise_output: bool
    # Weight init: ``glorot_uniform`` (Keras default) or ``he_uniform``.
    init: str
    # Half width of the scaled time input: time maps to [-r, r] (with ``scale_input``).
    input_half_range: float = 1.0
    # Smallest std used when standardising an output [rad]: a still joint stays unscaled-ish.
    min_output_std: float = 0.05
    # Adam betas and epsilon.
    betas: tuple[float, float] = (0.9, 0.999)
    eps: float = 1e-8

    @property
    def epochs(self) -> int:
        return sum(p.epochs for p in self.phases)

    def with_epochs(self, epochs: int) -> Preset:
        """The same schedule stretched or shrunk to ``epochs`` in total (phase shares kept)."""
        if epochs < len(self.phases):
            return replace(self, phases=(Phase(max(1, epochs), self.phases[0].lr),))
        total = self.epochs
        counts = [max(1, round(p.epochs * epochs / total)) for p in self.phases]
        counts[0] += epochs - sum(counts)
        return replace(self, phases=tuple(Phase(c, p.lr) for c, p in zip(counts, self.phases)))


PAPER = Preset(
    name="paper",
    phases=(
        Phase(30000, 1e-3),
        Phase(5000, 8e-4),
        Phase(5000, 6e-4),
        Phase(5000, 4e-4),
        Phase(5000, 2e-4),
    ),
    scale_input=False,
    standardise_output=False,
    init="glorot_uniform",
)

FAST = Preset(
    name="fast",
    phases=(Phase(15000, 1e-2), Phase(5000, 3e-3), Phase(3000, 1e-3), Phase(2000, 1e-4)),
    scale_input=True,
    standardise_output=False,
    init="he_uniform",
)

PRESETS = {p.name: p for p in (PAPER, FAST)}


def get_preset(name: str) -> Preset:
    """The preset called ``name``.

    Raises:
        ValueError: unknown name (the message lists the known ones).
    """
    try:
        return PRESETS[name]
    except KeyError:
        raise ValueError(f"unknown preset {name!r}; known: {', '.join(PRESETS)}") from None
