"""Shared helpers for the league tests: a server with ground truth, T1 joint sweeps, the CLI."""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np

from mimic.agents.base import Agent, JointCommand
from mimic.league.server import ServerConfig
from mimic.robot.registry import get_robot

T1 = get_robot("t1")
TRUTH_SERVER = Path(__file__).with_name("league_truth_server.py")


def mimic_command() -> list[str]:
    """How to run the ``mimic`` command of this environment."""
    mimic = Path(sys.executable).with_name("mimic")
    return [str(mimic)] if mimic.exists() else [sys.executable, "-m", "mimic.cli.main"]


def truth_server_config(truth: Path, logfile: Path | None = None) -> ServerConfig:
    """A hosted server that also writes the true state at every monitor frame to ``truth``."""
    return ServerConfig(logfile=logfile, command=(sys.executable, str(TRUTH_SERVER), str(truth)))


def read_truth(path: Path, who: str) -> dict[float, dict]:
    """Server time (rounded to 0.01 s, as frames show it) -> that robot's true state."""
    out = {}
    for line in path.read_text().splitlines():
        entry = json.loads(line)
        if who in entry["players"]:
            out[round(entry["t"], 2)] = entry["players"][who]
    return out


class SweepAgent(Agent):
    """Plays keyframes of joint angles with smooth (cosine) blends; ``done`` after the last.

    ``keyframes``: (time from start [s], {joint: angle [rad]}), times increasing; joints not
    named keep their previous angle, starting from the stand pose.
    """

    robot = "t1"

    def __init__(self, name: str, keyframes: list[tuple[float, dict[str, float]]]) -> None:
        super().__init__()
        self.name = name
        pose = T1.stand_pose()
        self._times, self._poses = [0.0], [pose.copy()]
        for t, angles in keyframes:
            pose = pose.copy()
            for joint, q in angles.items():
                pose[T1.joint_index(joint)] = q
            self._times.append(t)
            self._poses.append(pose)
        self._start_s = 0.0

    @property
    def duration_s(self) -> float:
        return self._times[-1]

    def reset(self, obs) -> None:
        self._start_s, self.done = obs.time_s, False

    def references(self, t: float) -> np.ndarray:
        k = int(np.searchsorted(self._times, t, side="right"))
        if k >= len(self._times):
            return self._poses[-1]
        t0, t1 = self._times[k - 1], self._times[k]
        a = 0.5 - 0.5 * math.cos(math.pi * (t - t0) / (t1 - t0))
        return (1 - a) * self._poses[k - 1] + a * self._poses[k]

    def act(self, obs) -> JointCommand:
        t = obs.time_s - self._start_s
        self.reference_rad = self.references(t)
        self.done = t >= self.duration_s
        return JointCommand.references(self.reference_rad)


def both(kind: str, left: float, right: float | None = None) -> dict[str, float]:
    """``{Left_<kind>: left, Right_<kind>: right}`` (right: the mirror of left by default)."""
    i = T1.joint_index(f"Left_{kind}")
    mirror = T1.joints[T1.mirror_permutation[i]]
    return {
        f"Left_{kind}": left,
        f"Right_{kind}": left * mirror.mirror_sign if right is None else right,
    }


def getup_sweep() -> SweepAgent:
    """A get-up-like sweep from lying on the back: arms swing, hips and knees fold, the
    trunk twists, then back to the stand pose (2.4 s)."""
    return SweepAgent(
        "getup_sweep",
        [
            (
                0.6,
                {
                    **both("Shoulder_Pitch", -1.6),
                    **both("Elbow_Pitch", 1.2),
                    **both("Hip_Pitch", -1.3),
                    **both("Knee_Pitch", 1.9),
                    **both("Ankle_Pitch", -0.6),
                    "Waist": 0.5,
                    "AAHead_yaw": 0.8,
                },
            ),
            (
                1.2,
                {
                    **both("Shoulder_Roll", -0.6),
                    **both("Hip_Roll", 0.4),
                    **both("Hip_Yaw", 0.5),
                    **both("Ankle_Roll", 0.3),
                    "Waist": -0.5,
                    "Head_pitch": 0.9,
                    **both("Elbow_Yaw", -1.5),
                },
            ),
            (
                1.8,
                {
                    **both("Shoulder_Pitch", 0.8),
                    **both("Hip_Pitch", -0.4),
                    **both("Knee_Pitch", 0.6),
                    "AAHead_yaw": -0.8,
                },
            ),
            (2.4, dict(zip(T1.joint_names, T1.stand_pose()))),
        ],
    )


def kick_sweep() -> SweepAgent:
    """A kick-like sweep while standing: shift onto the left leg, draw the right leg back,
    swing it through fast (0.15 s), return (1.6 s)."""
    return SweepAgent(
        "kick_sweep",
        [
            (0.4, {**both("Hip_Roll", 0.12, 0.12), **both("Ankle_Roll", -0.1, -0.1)}),
            (
                0.7,
                {
                    "Right_Hip_Pitch": 0.35,
                    "Right_Knee_Pitch": 1.3,
                    "Right_Ankle_Pitch": -0.4,
                    **both("Shoulder_Pitch", -0.5, 0.9),
                },
            ),
            (
                0.85,
                {
                    "Right_Hip_Pitch": -0.9,
                    "Right_Knee_Pitch": 0.2,
                    "Right_Ankle_Pitch": 0.2,
                    **both("Shoulder_Pitch", 0.9, -0.5),
                },
            ),
            (1.6, dict(zip(T1.joint_names, T1.stand_pose()))),
        ],
    )


def errors_against_truth(
    times_s: np.ndarray,
    angles: np.ndarray,
    torso_m: np.ndarray | None,
    truth: dict[float, dict],
    lag_s: float,
) -> dict[str, np.ndarray]:
    """Absolute errors of decoded samples against the truth.

    ``times_s``: the samples' times, ``lag_s`` before the frames that carried them. Returns
    ``shown`` ((S, N) joint errors [rad] against the true state at each sample's time, which
    is the pose its frame shows), ``qpos`` (against the state at the frame's time stamp,
    ``lag_s`` later) and ``torso`` ((S,) [m]).
    """
    shown, qpos, torso = [], [], []
    for t, q, p in zip(times_s, angles, torso_m if torso_m is not None else [None] * len(times_s)):
        state = truth[round(float(t) + lag_s, 2)]
        shown.append(np.abs(q - [state["shown"][n] for n in T1.joint_names]))
        qpos.append(np.abs(q - [state["qpos"][n] for n in T1.joint_names]))
        if p is not None:
            torso.append(float(np.linalg.norm(np.asarray(p) - state["torso"][:3])))
    return {"shown": np.array(shown), "qpos": np.array(qpos), "torso": np.array(torso)}
