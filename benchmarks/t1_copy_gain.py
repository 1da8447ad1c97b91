"""Copies of a T1 motion from its 25 Hz angles and torso pose, with the compensation scaled.

    python benchmarks/t1_copy_gain.py [--motion kick|walk] [--world league|mujoco]
        [--gains 0 1 1.25 1.5] [--seeds 6] [--first-seed 1] [--table] [--seconds 6]
        [--balance PITCH ROLL PITCH_RATE_S ROLL_RATE_S LIMIT_RAD]

The original (our ``kick_right`` placed behind the ball, or the other team's T1 walk from a
stand) plays once (seed 0); its joint angles and torso pose are taken every second cycle,
as the league's monitor gives them. The copy's targets are the reached angles plus ``a``
times the PD compensation (``learn.pd_compensate``, sent (delay + 0.5) cycles early as
``mimic train`` does): ``a`` = 0 is the study's method, 1 the compensated target. Each is
learned as a one-shot model (fast preset, seed 0) or, with ``--table``, tracked straight from
the table without a network, and played from the original's start over ``--seeds`` seeds
from ``--first-seed`` (1 deg start-pose noise); with ``--balance`` inside the balance layer
with those tilt gains. A kick counts as standing when the robot has not fallen by 2 s after
the motion, holding its stand pose; a walk plays ``--seconds``.
"""

from __future__ import annotations

import argparse

import numpy as np
from rich.console import Console
from rich.table import Table
from shared import T1 as ROBOT
from shared import monitor_view, per_cycle, play_t1

from mimic.agents.balance import BalancedAgent, BalanceGains
from mimic.agents.neural_player import NeuralPlayer
from mimic.agents.registry import agent_spec
from mimic.agents.table_player import TablePlayer
from mimic.learn.dataset import Dataset
from mimic.learn.presets import get_preset
from mimic.learn.train import TrainConfig, train_model
from mimic.robot.registry import get_robot


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--motion", choices=("kick", "walk"), default="kick")
    parser.add_argument("--world", choices=("league", "mujoco"), default="league")
    parser.add_argument("--gains", type=float, nargs="+", default=[0.0, 1.0, 1.25, 1.5])
    parser.add_argument("--seeds", type=int, default=6)
    parser.add_argument("--first-seed", type=int, default=1, help="seed 0 records the original")
    parser.add_argument("--table", action="store_true", help="track the targets, no network")
    parser.add_argument("--seconds", type=float, default=6.0, help="walk: how long to play")
    parser.add_argument(
        "--balance",
        type=float,
        nargs=5,
        metavar=("PITCH", "ROLL", "PITCH_RATE_S", "ROLL_RATE_S", "LIMIT_RAD"),
        help="play the learned copies inside the balance layer with these tilt gains",
    )
    args = parser.parse_args()

    robot = get_robot(ROBOT)
    spec = agent_spec("kick_right" if args.motion == "kick" else "other-team-walk", robot=ROBOT)
    offset = spec.ball_offset_m() if args.motion == "kick" else (3.0, 3.0)
    seconds = 8.0 if args.motion == "kick" else args.seconds
    seen, distance, standing = play_t1(spec.build(), args.motion, args.world, offset, 0, seconds)
    t, q, comp = monitor_view(seen, robot, args.world)

    table = Table(
        title=f"T1 {args.motion} copies, {args.world} world, seeds "
        f"{args.first_seed}-{args.first_seed + args.seeds - 1}"
        + (" (reference table, no network)" if args.table else "")
        + (" + balance layer" if args.balance and not args.table else "")
    )
    for column in ("target", "distance m", "standing", "fell after s"):
        table.add_column(column, justify="right")
    table.add_row("original (seed 0)", f"{distance:.2f}", "yes" if standing else "no", "")
    for gain in args.gains:
        targets = q + gain * (comp - q)
        flags = np.zeros((len(t), 1))
        flags[-1] = 1.0
        dataset = Dataset(
            t, np.hstack([targets, flags]), ROBOT, robot.joint_names,
            metadata={"motion": f"{args.motion} copy", "ball_offset_m": list(offset)},
        )  # fmt: skip
        if args.table:
            rows = per_cycle(t, targets)
        else:
            model = train_model(dataset, TrainConfig(get_preset("fast"), seed=0))
        outcomes = []
        for seed in range(args.first_seed, args.first_seed + args.seeds):
            agent = TablePlayer(rows) if args.table else NeuralPlayer(model)
            if args.balance and not args.table:
                pitch, roll, pitch_rate_s, roll_rate_s, limit_rad = args.balance
                gains = BalanceGains(pitch, roll, pitch_rate_s, roll_rate_s, limit_rad=limit_rad)
                agent = BalancedAgent(agent, gains=gains)
            agent.robot = ROBOT
            outcomes.append(play_t1(agent, args.motion, args.world, offset, seed, seconds))
        distances = np.array([o[1] for o in outcomes])
        fell = [o[0].fell_s for o in outcomes if o[0].fell_s is not None]
        table.add_row(
            f"reached + {gain:g} x compensation",
            f"{distances.mean():.2f} +- {distances.std():.2f}",
            f"{sum(o[2] for o in outcomes)}/{len(outcomes)}",
            f"{np.mean(fell):.1f}" if fell else "-",
        )
    Console(width=80).print(table)


if __name__ == "__main__":
    main()
