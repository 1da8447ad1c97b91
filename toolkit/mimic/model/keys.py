"""What a model file's ``metadata`` (``meta.json``) may carry besides its training: one key
per fact, each with who writes and who reads it. One place knows them all."""

from __future__ import annotations

__all__ = [
    "FOOT_TRACK_KEY",
    "BALANCE_GAINS_KEY",
    "WALK_SPEED_KEY",
    "SIM_FIT_KEY",
    "CORRECTION_KEY",
]

#: A cyclic model's foot track from its recording (``model.foot_track.FootTrack``; written
#: by ``mimic train`` from a recording with body poses, read by the balance layer's foot
#: placement).
FOOT_TRACK_KEY = "foot_track"
#: The model's own balance gains: the ``agents.balance.BalanceGains`` fields it sets, the
#: rest its robot's defaults (written by ``mimic improve M.mimic+balance``).
BALANCE_GAINS_KEY = "balance_gains"
#: The speed a cyclic model learned step by step walked in its recording [m/s] (written by
#: ``mimic train``, read by the neural player to hold a commanded speed).
WALK_SPEED_KEY = "walk_speed_m_s"
#: How a model trained on references fitted in simulation was fitted (``improve.sim_fit``,
#: ``mimic train --fit-in-sim``).
SIM_FIT_KEY = "sim_fit"
#: A correction of the model's references found by ``mimic improve`` (``improve.correction``).
CORRECTION_KEY = "correction"
