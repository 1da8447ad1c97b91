"""Physical trials of the other team's walk and kick, through the ``Agent`` interface only.

Used by the tests and the benchmark; they see the agents exactly as the recorder does
(reset / act / done / period_s / ball_offset_m).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from mimic.agents.base import Agent
from mimic.motion.files import load_motion
from mimic.world import field as F
from mimic.world.world import CYCLE_S, World

__all__ = ["WalkResult", "KickResult", "stand_pose_rad", "walk_trial", "kick_trial"]


def stand_pose_rad() -> np.ndarray:
    """(22,) the project's ready pose (motion ``stand``) [rad]."""
    return load_motion("stand").steps[-1].angles_rad.copy()


@dataclass(frozen=True)
class WalkResult:
    """Outcome of one straight walk."""

    # Whether the robot fell before covering the distance.
    fell: bool
    # Distance covered along x [m].
    distance_m: float
    # Mean forward speed from the first crossing of ``start_after_m`` to the end [m/s].
    speed_m_s: float
    # Largest |y| reached [m].
    max_drift_m: float
    # Simulated time used [s].
    time_s: float
    # (cycles, 22) observed joint angles [rad], one row per 20 ms cycle.
    angles_rad: np.ndarray


@dataclass(frozen=True)
class KickResult:
    """Outcome of one kick from a stand."""

    # Ball travel along the robot's forward axis [m].
    distance_m: float
    # Ball sideways travel [m].
    lateral_m: float
    # Robot upright 2 s after the kick finished.
    standing: bool


def walk_trial(make_agent: Callable[[], Agent], distance_m: float = 15.0, *, seed: int = 0,
               speed_noise_rad_s: float = 0.0, start_after_m: float = 1.0,
               max_time_s: float = 60.0, world: World | None = None) -> WalkResult:
    """Beam the robot standing on its own goal line facing +x and let the agent walk.

    The speed is measured from the moment the torso has advanced ``start_after_m`` [m]
    (past the start-up) until it has covered ``distance_m`` [m]. ``speed_noise_rad_s``
    adds Gaussian noise [rad/s] to every speed command (a seeded perturbation).
    """
    w = world or World()
    rng = np.random.default_rng(seed)
    w.reset()
    x0 = F.OWN_GOAL_X_M
    w.beam(x0, 0.0, 0.0, stand_pose_rad())
    agent = make_agent()
    agent.reset(w.observe())
    angles, drift, t_start = [], 0.0, None
    for _ in range(int(round(max_time_s / CYCLE_S))):
        obs = w.observe()
        angles.append(obs.joint_angles_rad)
        speeds = agent.act(obs)
        if speed_noise_rad_s:
            speeds = speeds + rng.normal(0.0, speed_noise_rad_s, speeds.shape)
        w.step(speeds)
        x, y, _ = w.torso_pos_m()
        drift = max(drift, abs(y))
        if t_start is None and x - x0 >= start_after_m:
            t_start = w.time_s
        if w.fallen() or x - x0 >= distance_m:
            break
    x = w.torso_pos_m()[0]
    speed = ((x - x0 - start_after_m) / (w.time_s - t_start)
             if t_start is not None and w.time_s > t_start else 0.0)
    return WalkResult(w.fallen(), float(x - x0), float(speed), float(drift), w.time_s,
                      np.array(angles))


def kick_trial(make_agent: Callable[[], Agent], *, seed: int = 0, pose_noise_rad: float = 0.0,
               ball_noise_m: float = 0.0, speed_noise_rad_s: float = 0.0,
               world: World | None = None) -> KickResult:
    """Stand the robot at the centre spot, put the ball where the kick wants it, kick.

    After the agent reports done, the joints are held still (zero speeds) for 2 s and the
    ball is left to roll to rest. Seeded noise perturbs the start pose [rad], the ball
    position [m] and the speed commands [rad/s].
    """
    w = world or World()
    rng = np.random.default_rng(seed)
    w.reset()
    w.beam(0.0, 0.0, 0.0, stand_pose_rad() + rng.normal(0.0, pose_noise_rad, 22))
    agent = make_agent()
    bx, by = agent.ball_offset_m
    bx, by = bx + rng.uniform(-ball_noise_m, ball_noise_m), by + rng.uniform(-ball_noise_m,
                                                                             ball_noise_m)
    w.place_ball(bx, by)
    for _ in range(10):  # let the beamed robot settle on its feet
        w.step(np.zeros(22))
    agent.reset(w.observe())
    for _ in range(int(round(10.0 / CYCLE_S))):
        speeds = agent.act(w.observe())
        if agent.done:
            break
        w.step(speeds + rng.normal(0.0, speed_noise_rad_s, 22) if speed_noise_rad_s else speeds)
    for _ in range(int(round(2.0 / CYCLE_S))):
        w.step(np.zeros(22))
    standing = w.upright()
    for _ in range(int(round(20.0 / CYCLE_S))):
        if w.ball_speed_m_s() < 0.01:
            break
        w.step(np.zeros(22))
    b = w.ball_pos_m()
    return KickResult(float(b[0] - bx), float(b[1] - by), bool(standing and not math.isnan(b[0])))
