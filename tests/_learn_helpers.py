"""Shared helpers for the learn tests: small synthetic motions and the study's kick."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import polars as pl

from mimic.robot.registry import get_robot

#: The study's published tables: not in this repository (we may not copy them). Tests that need
#: them skip when the folder is absent, as on a fresh clone (see the README).
PAPER_DATA = Path(
    os.environ.get("MIMIC_PAPER_DATA")
    or Path(__file__).resolve().parents[2] / "shared" / "paper-data"
)
NAO = get_robot("nao")


def joint_frame(
    t: np.ndarray, q: np.ndarray, ended: np.ndarray | None = None, robot: str = "nao"
) -> pl.DataFrame:
    """A joint table of ``robot``: ``time_s``, its joints (q columns, its order), ``ended``."""
    cols = {"time_s": t, **{n: q[:, i] for i, n in enumerate(get_robot(robot).joint_names)}}
    if ended is not None:
        cols["ended"] = ended
    return pl.DataFrame(cols)


def smooth_motion(n: int = 40, seed: int = 0, robot: str = "nao") -> tuple[np.ndarray, np.ndarray]:
    """(t, q): n samples at 50 Hz of a smooth motion of every joint of ``robot`` (rad)."""
    joints = get_robot(robot).num_joints
    rng = np.random.default_rng(seed)
    t = np.arange(n) * 0.02
    amp, freq = rng.uniform(0.1, 0.5, joints), rng.uniform(0.5, 1.5, joints)
    ph = rng.uniform(0, 6, joints)
    return t, amp * np.sin(2 * np.pi * freq * t[:, None] + ph)
