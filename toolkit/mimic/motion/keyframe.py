"""Keyframe motions as the study defines them.

A keyframe is one angle per joint of the robot; a keyframe step is (keyframe, time); a movement is a list of
steps plus a speed rate r that divides every step time. References between steps come from a
C2 natural cubic spline through the keyframes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mimic.motion.spline import NaturalCubicSpline
from mimic.robot.registry import get_robot
from mimic.world.base import POSTURES

__all__ = ["KeyframeStep", "Movement"]


@dataclass(frozen=True)
class KeyframeStep:
    """A keyframe and the time to reach it from the previous step.

    Attributes:
        angles_rad: (N,) joint angles [rad], the robot's joint order.
        time_s: time from the previous keyframe (or from the start) to this one [s].
    """

    angles_rad: np.ndarray
    time_s: float

    def __post_init__(self) -> None:
        if np.ndim(self.angles_rad) != 1:
            raise ValueError(
                f"a keyframe is a vector of angles, got shape {np.shape(self.angles_rad)}"
            )
        if self.time_s < 0:
            raise ValueError(f"step time must be >= 0 s, got {self.time_s}")

    def __eq__(self, other: object) -> bool:
        # Angles compare to 1e-9 rad: a text round trip goes through degrees and may move
        # the last bit, which no sensor or servo could ever tell apart.
        if not isinstance(other, KeyframeStep):
            return NotImplemented
        return abs(self.time_s - other.time_s) <= 1e-9 and bool(
            np.allclose(self.angles_rad, other.angles_rad, rtol=0.0, atol=1e-9)
        )


#: How a motion may start: on the feet, or lying on the front or the back.
START_POSTURES = POSTURES


@dataclass(frozen=True)
class Movement:
    """Keyframe steps played at a speed rate.

    Attributes:
        name: motion name, e.g. ``kick_right``.
        steps: the keyframe steps in order.
        speed_rate: r; every step time is divided by it (r = 2 plays twice as fast).
        ball_offset_m: for a kick, where the ball centre should lie relative to the torso
            before the motion starts: (x forward, y left) in the robot frame [m], ball on the
            ground; None for motions that do not touch the ball.
        start_posture: how the robot lies or stands when the motion starts: ``standing``,
            ``lying_front`` or ``lying_back`` (the get-ups); recorders and checks set the
            robot up this way.
        robot: the robot whose joints the keyframes hold (``mimic robots``).
    """

    name: str
    steps: tuple[KeyframeStep, ...]
    speed_rate: float = 1.0
    ball_offset_m: tuple[float, float] | None = None
    start_posture: str = "standing"
    robot: str = "nao"

    def __post_init__(self) -> None:
        if not self.steps:
            raise ValueError(f"motion {self.name!r} has no steps")
        n = get_robot(self.robot).num_joints
        for step in self.steps:
            if np.shape(step.angles_rad) != (n,):
                raise ValueError(
                    f"a {self.robot} keyframe has {n} angles, got {np.shape(step.angles_rad)[0]}"
                )
        if self.start_posture not in START_POSTURES:
            raise ValueError(
                f"start posture must be one of {', '.join(START_POSTURES)}, "
                f"got {self.start_posture!r}"
            )
        if self.speed_rate <= 0:
            raise ValueError(f"speed rate must be > 0, got {self.speed_rate}")

    @property
    def duration_s(self) -> float:
        """Time from the start to the last keyframe [s]."""
        return sum(s.time_s for s in self.steps) / self.speed_rate

    def knot_times_s(self) -> np.ndarray:
        """(n,) time of each keyframe from the motion start [s]."""
        return np.cumsum([s.time_s for s in self.steps]) / self.speed_rate

    def spline(self, start_angles_rad: np.ndarray | None = None) -> NaturalCubicSpline:
        """The reference trajectory; starts from ``start_angles_rad`` at t = 0 when the first
        step takes time (a step with time 0 is itself the start)."""
        times = self.knot_times_s()
        keys = np.stack([s.angles_rad for s in self.steps])
        if times[0] > 0:
            start = keys[0] if start_angles_rad is None else np.asarray(start_angles_rad)
            times = np.concatenate([[0.0], times])
            keys = np.vstack([start, keys])
        # Zero-duration steps after the first would be duplicate knots: keep the last one.
        keep = np.concatenate([np.diff(times) > 1e-9, [True]])
        times, keys = times[keep], keys[keep]
        if len(times) == 1:
            times, keys = np.array([0.0, 1e-3]), np.vstack([keys, keys])
        return NaturalCubicSpline(times, keys)

    def with_speed_rate(self, speed_rate: float) -> Movement:
        return Movement(
            self.name, self.steps, speed_rate, self.ball_offset_m, self.start_posture, self.robot
        )
