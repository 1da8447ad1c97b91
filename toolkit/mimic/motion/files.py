"""Readable text files for keyframe motions, and the library of our own team's motions.

Format (angles in degrees, simulator convention; ``#`` starts a comment)::

    motion kick_right
    speed_rate 1.0
    step 0.5                 # time to reach this keyframe from the previous one [s]
    both_hip_pitch 19        # left = 19, right = the mirrored value
    both_knee_pitch -40
    left_shoulder_roll 10    # any canonical or simulator joint name
    step 0.2
    right_hip_pitch 40       # unlisted joints keep the previous keyframe's angle

A kick may say where the ball must lie before it starts: ``ball_offset 0.17 -0.07`` puts the
ball centre 0.17 m ahead of and 0.07 m right of the torso centre (robot frame: x forward, y left,
metres; the ball rests on the ground).

A get-up says how it starts: ``start lying_front`` (or ``lying_back``; default ``standing``);
recorders and checks lay the robot down that way first.

A motion for a robot other than our NAO says so first: ``robot t1`` (joint names are then
that robot's, e.g. ``Left_Knee_Pitch``; ``both_Knee_Pitch`` sets both sides). Shipped motions
of another robot live in ``motions/<robot>/``. The ``stand`` motion of every robot is its
description's stand pose, reached in 0.6 s.

A file may instead say ``mirror_of kick_right``: the motion is the sagittal mirror of that one
(its ball offset too, with y negated).
Joints unlisted in the first keyframe are 0; the player starts the first step from the robot's
current pose.
"""

from __future__ import annotations

import math
from importlib import resources
from pathlib import Path

import numpy as np

from mimic.errors import MotionFileError
from mimic.motion.keyframe import START_POSTURES, KeyframeStep, Movement
from mimic.robot.model import RobotDescription, UnknownJointError
from mimic.robot.registry import DEFAULT_ROBOT, UnknownRobotError, get_robot

__all__ = [
    "parse_motion",
    "format_motion",
    "load_motion",
    "list_motions",
    "stand_motion",
    "MOTIONS_DIR",
]

MOTIONS_DIR = resources.files("mimic.motion") / "motions"
#: Time the ``stand`` motion takes to reach the stand pose [s].
STAND_STEP_S = 0.6


def _set(robot: RobotDescription, angles: np.ndarray, name: str, degrees: float) -> None:
    if name.startswith("both_"):
        part = name.removeprefix("both_").lower()
        left = [i for i, j in enumerate(robot.joints) if j.name.lower() == f"left_{part}"]
        if not left:
            raise UnknownJointError(
                f"{robot.name} has no joints {name!r} (left_{part} and "
                f"its mirror); its joints: {', '.join(robot.joint_names)}"
            )
        angles[left[0]] = math.radians(degrees)
        right = robot.mirror_permutation[left[0]]
        angles[right] = math.radians(degrees) * robot.joints[right].mirror_sign
        return
    angles[robot.joint_index(name)] = math.radians(degrees)


def _motions_dir(robot: str):
    return MOTIONS_DIR if robot == DEFAULT_ROBOT else MOTIONS_DIR / robot


def stand_motion(robot: str | RobotDescription = DEFAULT_ROBOT) -> Movement:
    """The ``stand`` motion: the robot's stand pose, reached in ``STAND_STEP_S``."""
    robot = get_robot(robot)
    return Movement("stand", (KeyframeStep(robot.stand_pose(), STAND_STEP_S),), robot=robot.name)


def parse_motion(text: str, source: str = "<text>") -> Movement:
    """Parse a motion file's text; ``source`` names it in error messages."""
    name, rate, mirror_of, posture = Path(source).stem, 1.0, None, "standing"
    ball_offset: tuple[float, float] | None = None
    steps: list[KeyframeStep] = []
    robot = get_robot(DEFAULT_ROBOT)
    angles, time_s = robot.zeros(), None

    def close_step():
        if time_s is not None:
            steps.append(KeyframeStep(angles.copy(), time_s))

    for lineno, raw in enumerate(text.splitlines(), 1):
        words = raw.split("#", 1)[0].split()
        if not words:
            continue
        where = f"{source}:{lineno}"
        key, args = words[0], words[1:]
        try:
            if key == "motion" and len(args) == 1:
                name = args[0]
            elif key == "robot" and len(args) == 1:
                if steps or time_s is not None:
                    raise MotionFileError(f"{where}: 'robot' must come before the first step")
                robot = get_robot(args[0])
                angles = robot.zeros()
            elif key == "speed_rate" and len(args) == 1:
                rate = float(args[0])
            elif key == "ball_offset" and len(args) == 2:
                ball_offset = (float(args[0]), float(args[1]))
            elif key == "start" and len(args) == 1:
                if args[0] not in START_POSTURES:
                    raise MotionFileError(
                        f"{where}: start must be one of "
                        f"{', '.join(START_POSTURES)}, got {args[0]!r}"
                    )
                posture = args[0]
            elif key == "mirror_of" and len(args) == 1:
                mirror_of = args[0]
            elif key == "step" and len(args) == 1:
                close_step()
                time_s = float(args[0])
                if not time_s >= 0:  # also refuses nan
                    raise MotionFileError(f"{where}: step time must be >= 0 s, got {args[0]}")
            elif len(args) == 1 and time_s is not None:
                _set(robot, angles, key, float(args[0]))
            else:
                raise MotionFileError(
                    f"{where}: cannot read {raw.strip()!r}; expected "
                    "'step SECONDS', 'JOINT DEGREES', 'ball_offset X_M Y_M' or "
                    "'start POSTURE' "
                    "(see mimic.motion.files)"
                )
        except (UnknownJointError, UnknownRobotError) as err:
            raise MotionFileError(f"{where}: {err}") from None
        except ValueError:
            raise MotionFileError(f"{where}: {raw.strip()!r} needs a number") from None
    close_step()
    if mirror_of is not None:
        base = load_motion(mirror_of, robot.name)
        mirrored = tuple(
            KeyframeStep(robot.mirror_angles(s.angles_rad), s.time_s) for s in base.steps
        )
        offset = base.ball_offset_m
        return Movement(
            name,
            mirrored,
            base.speed_rate,
            None if offset is None else (offset[0], -offset[1]),
            base.start_posture,
            robot.name,
        )
    if not steps:
        raise MotionFileError(f"{source}: no 'step' in the file; a motion needs at least one")
    try:
        return Movement(name, tuple(steps), rate, ball_offset, posture, robot.name)
    except ValueError as err:
        raise MotionFileError(f"{source}: {err}") from None


def format_motion(movement: Movement) -> str:
    """Text of a motion file that parses back to ``movement`` (every joint of every step)."""
    # repr() of a float reads back exactly; angles go through degrees, so 12 significant
    # digits (back to within 1e-9 rad) keep them readable.
    robot = get_robot(movement.robot)
    lines = [f"motion {movement.name}"]
    if robot.name != DEFAULT_ROBOT:
        lines.append(f"robot {robot.name}")
    lines.append(f"speed_rate {float(movement.speed_rate)!r}")
    if movement.ball_offset_m is not None:
        x, y = movement.ball_offset_m
        lines.append(f"ball_offset {float(x)!r} {float(y)!r}")
    if movement.start_posture != "standing":
        lines.append(f"start {movement.start_posture}")
    for step in movement.steps:
        lines.append(f"step {float(step.time_s)!r}")
        lines += [f"{j.name} {math.degrees(a):.12g}" for j, a in zip(robot.joints, step.angles_rad)]
    return "\n".join(lines) + "\n"


def list_motions(robot: str = DEFAULT_ROBOT) -> list[str]:
    """Names of our own team's motions shipped for ``robot`` (``stand`` for every robot)."""
    folder = _motions_dir(robot)
    names = {"stand"}
    if folder.is_dir():
        names |= {p.name.removesuffix(".txt") for p in folder.iterdir() if p.name.endswith(".txt")}
    return sorted(names)


def load_motion(name_or_path: str | Path, robot: str = DEFAULT_ROBOT) -> Movement:
    """A shipped motion of ``robot`` by name (``kick_right``) or a motion file by path."""
    path = Path(name_or_path)
    if path.suffix == ".txt" and path.exists():
        return parse_motion(path.read_text(), str(path))
    shipped = _motions_dir(robot) / f"{name_or_path}.txt"
    if shipped.is_file():
        return parse_motion(shipped.read_text(), f"{name_or_path}.txt")
    if str(name_or_path) == "stand":
        return stand_motion(robot)
    raise MotionFileError(
        f"unknown {robot} motion {str(name_or_path)!r}; shipped motions: "
        f"{', '.join(list_motions(robot))} (or give a path to a .txt file)"
    )
