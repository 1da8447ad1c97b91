"""How closely the learned copies of ``kick_right`` follow the original, played from a stand.

    python benchmarks/kick_copies.py [--seeds 8] [--out out/kick_copies] [--reuse]

Records ``kick_right``, trains three copies with the default (fast) preset and seed 0, as
``mimic train`` does: from its references, from ``/joint_states`` with the ``reached`` target
(the study's method) and with the ``compensated`` target. Then, from standing behind the ball
(the scene of ``tests/test_learned_kick.py``), it prints:

- the copy learned from references: mean |reached angle - original's| [rad];
- the reached copy: when the kicking leg's hip and knee pitch reach their back-swing and
  forward-swing extremes, against the original (how late its swing is) [s];
- the compensated copy: how long its reached angles stay within 0.03 rad (largest joint) of
  the observed angles it learned from [s];
- the compensated reference table itself, tracked directly without a network: falls in
  ``--seeds`` seeded kicks (0.01 rad start-pose noise, 2 s standing after the motion), and,
  played without noise, how far the support leg's hip roll and ankle roll sag below the
  observed angles before the swing [rad].
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from mimic.agents.base import Agent
from mimic.agents.keyframe_player import KeyframePlayer
from mimic.agents.neural_player import NeuralPlayer
from mimic.agents.table_player import TablePlayer
from mimic.episode import Observer, PoseNoise
from mimic.learn.train import TARGET_REACHED, TrainConfig, train_model, training_dataset
from mimic.model.model_file import load_model, save_model
from mimic.motion.files import load_motion
from mimic.recording.layout import JOINT_STATES
from mimic.recording.recorder import record
from mimic.robot.nao import nao
from mimic.tasks import kick_from_stand
from mimic.tasks.kick_from_stand import After, KickFromStandConfig
from mimic.world.base import CYCLE_S
from mimic.world.registry import MUJOCO, open_world

MOTION, KICKING, SUPPORT = "kick_right", "right", "left"
CLOSE_RAD = 0.03


class _Reached(Observer):
    """The joint angles seen every cycle."""

    def __init__(self) -> None:
        self.angles: list[np.ndarray] = []

    def before_step(self, world, obs, agent, command) -> None:
        self.angles.append(obs.joint_angles_rad)


def play(agent: Agent, offset_m, seed: int | None = None) -> tuple[np.ndarray, float, int]:
    """(reached angles per cycle, ball distance [m], falls) of one kick from standing behind
    the ball (the ``kick-from-stand`` task at the centre spot, the ball placed after 0.5 s of
    settling, followed for 6 s); with ``seed``: 0.01 rad start-pose noise and 2 s standing
    after the motion."""
    config = KickFromStandConfig(
        robot_xy_m=(0.0, 0.0),
        ball_offset_m=tuple(offset_m),
        noise=PoseNoise(joint_rad=0.01 if seed is not None else 0.0),
        settle_s=0.5,
        ball_after_settle=True,
        kick_max_s=6.0,
        after=After.STAND,
        after_s=2.0 if seed is not None else 0.0,
        roll_max_s=None,
    )
    reached = _Reached()
    with open_world(MUJOCO, "nao") as world:
        outcome = kick_from_stand.play(world, agent, seed or 0, config, observers=(reached,))
    moved = np.subtract(outcome.ball_end_m, outcome.ball_start_m)
    return np.array(reached.angles), float(np.linalg.norm(moved)), outcome.falls


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=8, help="seeded kicks of the table")
    ap.add_argument("--out", type=Path, default=Path("out/kick_copies"))
    ap.add_argument("--reuse", action="store_true", help="reuse the recording and models")
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    mcap = args.out / f"{MOTION}.mcap"
    sources = {
        "references": (None, None),
        "reached": (JOINT_STATES, TARGET_REACHED),
        "compensated": (JOINT_STATES, "compensated"),
    }
    paths = {k: args.out / f"{k}.mimic" for k in sources}
    if not (args.reuse and mcap.exists() and all(p.exists() for p in paths.values())):
        record(MOTION, mcap)
        for key, (topic, target) in sources.items():
            kwargs = {k: v for k, v in (("topic", topic), ("target", target)) if v}
            save_model(
                train_model(training_dataset(mcap, **kwargs), TrainConfig(seed=0)), paths[key]
            )
    models = {k: load_model(p) for k, p in paths.items()}
    movement = load_motion(MOTION)
    offset = movement.ball_offset_m
    robot = nao()
    original, ball, _ = play(KeyframePlayer(movement), offset)
    print(f"original {MOTION}: {len(original)} cycles, ball {ball:.2f} m")

    copy, ball, _ = play(NeuralPlayer(models["references"]), offset)
    n = min(len(copy), len(original))
    print(
        f"copy learned from references: {len(copy)} cycles, mean |angle - original's| "
        f"{np.abs(copy[:n] - original[:n]).mean():.4f} rad, ball {ball:.2f} m"
    )

    reached, ball, _ = play(NeuralPlayer(models["reached"]), offset)
    for part in ("hip_pitch", "knee_pitch"):
        j = robot.joint_index(f"{KICKING}_{part}")
        times = [
            (int(np.argmin(a[:, j])) * CYCLE_S, int(np.argmax(a[:, j])) * CYCLE_S)
            for a in (original, reached)
        ]
        print(
            f"reached copy, {KICKING}_{part}: extremes at {times[1][0]:.2f} / "
            f"{times[1][1]:.2f} s against the original's {times[0][0]:.2f} / "
            f"{times[0][1]:.2f} s (later by {times[1][0] - times[0][0]:+.2f} / "
            f"{times[1][1] - times[0][1]:+.2f} s)"
        )
    # The swing starts at the kicking hip pitch's back-swing extreme of the original.
    swing_i = int(np.argmin(original[:, robot.joint_index(f"{KICKING}_hip_pitch")]))

    observed = training_dataset(mcap, JOINT_STATES, TARGET_REACHED).targets[:, :-1]
    comp, ball, _ = play(NeuralPlayer(models["compensated"]), offset)
    n = min(len(comp), len(observed))
    worst = np.abs(comp[:n] - observed[:n]).max(axis=1)
    off = np.flatnonzero(worst > CLOSE_RAD)
    until = (off[0] if len(off) else n) * CYCLE_S
    print(
        f"compensated copy: within {CLOSE_RAD} rad of the observed angles until "
        f"{until:.2f} s (swing from {swing_i * CYCLE_S:.2f} s), ball {ball:.2f} m"
    )

    table = training_dataset(mcap, JOINT_STATES, "compensated").targets[:, :-1]
    fell = [play(TablePlayer(table), offset, seed)[2] > 0 for seed in range(args.seeds)]
    print(
        f"compensated reference table, tracked directly: fell in {sum(fell)} of "
        f"{args.seeds} seeded kicks"
    )
    tracked, _, _ = play(TablePlayer(table), offset)
    n = min(len(tracked), len(observed), swing_i)
    for part in ("hip_roll", "ankle_roll"):
        j = robot.joint_index(f"{SUPPORT}_{part}")
        sag = np.abs(tracked[:n, j] - observed[:n, j])
        print(
            f"  support {SUPPORT}_{part}: up to {sag.max():.3f} rad off the observed "
            f"angle before the swing (at {int(np.argmax(sag)) * CYCLE_S:.2f} s)"
        )


if __name__ == "__main__":
    main()
