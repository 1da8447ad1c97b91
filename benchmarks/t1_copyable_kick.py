"""Search for a T1 kick whose black-box copy also kicks: CMA-ES over ``kick_right``'s keyframes
with the copy in the loop.

    python benchmarks/t1_copyable_kick.py [--world league|mujoco] [--generations 40]
        [--population 10] [--seeds 3] [--sigma 0.5] [--cap 5] [--start z.json] [--out DIR]
    python benchmarks/t1_copyable_kick.py --validate DIR/best.json [--seeds 10]
        [--black-box [--recordings 3] [--epochs 100000]]

A candidate is ``kick_right`` with 26 changes (``PARAMETERS``): the roll and pitch angles of the
weight shift, the wind-up, the swing and the return, in units of 3 deg, and five keyframe
durations, in units of 20 %. Each candidate kicks from behind the ball over ``--seeds`` seeded
starts (1 deg start-pose noise); its first kick is seen as the league's monitor gives it (joint
angles and torso pose every second cycle), turned into compensated references
(``learn.train.pd_compensated_targets``, what ``mimic train`` learns by default) and tracked
straight from that table inside the T1's balance layer (default gains) from the same starts,
the ball where the recording shows it (the first start's noise included, as ``mimic train``
reads it).
Score: the original's distance (at most ``--cap``, 5 m) if it stands, else -3 m, plus 3x the copy's
distance (at most the original's) if it stands, else 0.4x that less 1.5 m (plus 0.2 m per
second it stayed up). A kick stands when the robot is up 2 s after the motion, holding its
stand pose. ``--validate`` replays a result (and writes its motion file to ``--out``): the
original over seed 0 and seeds 301 on (``--seeds`` in all), and the copy made from its seed-0
kick over the same seeds. With ``--black-box`` it takes the study's path instead, as a user
would: the candidate kicks (seed 0, and with ``--recordings K`` seeds 1 to K-1 as well, each
0-3 cycles after the robot is set down) in a hosted league server while ``mimic record
--server`` records it from the monitor stream; ``mimic train seen0.mcap [seen1.mcap ...
--merge] --end E --epochs 100000`` learns the copy (E: the motion's length and 0.35 s, 3.6 s
for the kicks here; compensated, the default; the ball offset read from the recordings); the
original and the model, with and without the balance layer, then kick over seeds 301 on
(``--seeds`` of them), each placed where its own motion wants the ball, and once each through
``mimic play`` on a server of its own. ``benchmarks/data/t1_copyable_kick.json`` holds the best
candidate found so far (its provenance inside); it is shipped as the T1's
``kick_right_copyable``.
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import time
from pathlib import Path

import numpy as np
from shared import MIMIC, mimic, monitor_view, per_cycle, play_t1, record_black_box, t1_scene

from mimic.agents.balance import BalancedAgent
from mimic.agents.keyframe_player import KeyframePlayer
from mimic.agents.registry import agent_spec
from mimic.agents.table_player import TablePlayer
from mimic.motion.files import format_motion, load_motion
from mimic.motion.keyframe import KeyframeStep, Movement
from mimic.robot.registry import get_robot
from mimic.trials.executors import make_executor

#: kick_right's keyframes (0-based, inclusive) that move together: the weight shift, its
#: forward lean, the wind-up, the swing, the foot back (``motion/motions/t1/kick_right.txt``).
GROUPS = {"shift": (0, 5), "lean": (3, 5), "windup": (6, 7), "swing": (8, 11), "back": (12, 17)}
PARAMETERS = (
    ("shift", "Left_Hip_Roll"),
    ("shift", "Right_Hip_Roll"),
    ("shift", "Left_Ankle_Roll"),
    ("shift", "Right_Ankle_Roll"),
    ("shift", "Left_Ankle_Pitch"),
    ("lean", "Left_Ankle_Pitch"),
    ("windup", "Left_Ankle_Roll"),
    ("windup", "Left_Ankle_Pitch"),
    ("windup", "Left_Hip_Roll"),
    ("windup", "Right_Hip_Pitch"),
    ("windup", "Right_Knee_Pitch"),
    ("windup", "Right_Ankle_Pitch"),
    ("swing", "Left_Ankle_Roll"),
    ("swing", "Left_Hip_Roll"),
    ("swing", "Right_Hip_Pitch"),
    ("swing", "Right_Knee_Pitch"),
    ("swing", "Right_Ankle_Pitch"),
    ("back", "Left_Ankle_Roll"),
    ("back", "Right_Ankle_Roll"),
    ("back", "Left_Hip_Roll"),
    ("back", "Right_Hip_Roll"),
)
#: Keyframes whose duration is searched: the weight shift, wind-up, swing, foot back, hold.
TIMED_STEPS = (0, 6, 8, 12, 15)
ANGLE_UNIT_DEG, TIME_UNIT = 3.0, 0.2
DIMENSIONS = len(PARAMETERS) + len(TIMED_STEPS)


def movement(z: np.ndarray):
    """``kick_right`` changed by ``z`` (``DIMENSIONS`` numbers in the units above)."""
    robot, base = get_robot("t1"), load_motion("kick_right", "t1")
    steps = [np.array(s.angles_rad, dtype=float) for s in base.steps]
    times = [s.time_s for s in base.steps]
    for (group, name), dz in zip(PARAMETERS, z[: len(PARAMETERS)]):
        j = robot.joint_names.index(name)
        first, last = GROUPS[group]
        for k in range(first, last + 1):
            steps[k][j] = np.clip(
                steps[k][j] + math.radians(ANGLE_UNIT_DEG * dz),
                robot.joints[j].lower_rad,
                robot.joints[j].upper_rad,
            )
    for k, dz in zip(TIMED_STEPS, z[len(PARAMETERS) :]):
        times[k] = max(0.02, times[k] * (1 + TIME_UNIT * dz))
    return Movement(
        base.name,
        tuple(KeyframeStep(s, t) for s, t in zip(steps, times)),
        base.speed_rate,
        base.ball_offset_m,
        base.start_posture,
        base.robot,
    )


def _copy_agent(rows: np.ndarray):
    """The compensated table tracked inside the T1's balance layer (default gains)."""
    inner = TablePlayer(rows)
    inner.robot = "t1"
    agent = BalancedAgent(inner)
    agent.robot = "t1"
    return agent


def kick_and_copy(z, world: str, seeds: list[int]) -> dict:
    """The candidate's kicks and its copy's over ``seeds`` (the first seed's kick is copied)."""
    import torch

    torch.set_num_threads(1)
    kick = movement(np.asarray(z, dtype=float))
    offset = tuple(kick.ball_offset_m)
    originals = []
    for seed in seeds:
        agent = KeyframePlayer(kick)
        agent.robot = "t1"
        originals.append(play_t1(agent, "kick", world, offset, seed, 8.0))
    t, _, refs = monitor_view(originals[0][0], get_robot("t1"), world)
    rows = per_cycle(t, refs)
    # The copy stands where the recording shows the ball (as `mimic train` reads it), start
    # noise included, not where the original's motion file wants it.
    seen_offset = originals[0][0].ball_offset_m
    copies = [play_t1(_copy_agent(rows), "kick", world, seen_offset, seed, 8.0) for seed in seeds]

    def summary(runs):
        return dict(
            distance_m=[r[1] for r in runs],
            standing=[bool(r[2]) for r in runs],
            fell_s=[r[0].fell_s for r in runs],
        )

    return dict(original=summary(originals), copy=summary(copies))


def score(outcome: dict, cap_m: float = 5.0) -> float:
    """The search's score of one candidate (module docstring) [m]; ``cap_m``: the most the
    original's distance counts (a lower cap asks for a copy as long as the original)."""
    o, c = outcome["original"], outcome["copy"]
    reach = float(np.mean(o["distance_m"]))
    kick = np.mean([min(d, cap_m) if up else -3.0 for d, up in zip(o["distance_m"], o["standing"])])
    copy = np.mean(
        [
            min(d, reach) if up else 0.4 * min(d, reach) - 1.5 + 0.2 * min(fell or 8.0, 6.0)
            for d, up, fell in zip(c["distance_m"], c["standing"], c["fell_s"])
        ]
    )
    return float(kick + 3.0 * copy)


def _evaluate(args) -> tuple[float, dict]:
    z, world, seeds, cap_m = args
    outcome = kick_and_copy(z, world, seeds)
    return score(outcome, cap_m), outcome


def _line(label: str, runs: dict) -> str:
    d = np.array(runs["distance_m"])
    return f"{label}: {d.mean():.2f} +- {d.std():.2f} m, standing {sum(runs['standing'])}/{len(d)}"


def search(args) -> None:
    from cmaes import CMA

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    start = (
        np.array(json.loads(Path(args.start).read_text())["z"])
        if args.start
        else np.zeros(DIMENSIONS)
    )
    es = CMA(
        mean=start,
        sigma=args.sigma,
        bounds=np.tile([-6.0, 6.0], (DIMENSIONS, 1)),
        seed=args.seed,
        population_size=args.population,
    )
    best, t0 = -math.inf, time.time()
    # Two processes (capped at the cores there are); results come back in candidate order.
    with make_executor(workers=2) as pool:
        for gen in range(args.generations):
            zs = [es.ask() for _ in range(args.population)]
            if gen == 0:
                zs[0] = start.copy()
            seeds = list(range(1000 + 100 * gen, 1000 + 100 * gen + args.seeds))
            results = pool.map(_evaluate, [(list(z), args.world, seeds, args.cap) for z in zs])
            es.tell([(z, -s) for z, (s, _) in zip(zs, results)])
            i = int(np.argmax([s for s, _ in results]))
            if results[i][0] > best:
                best = results[i][0]
                record = dict(
                    z=list(map(float, zs[i])), score=best, generation=gen, **results[i][1]
                )
                (out / "best.json").write_text(json.dumps(record, indent=1))
            print(
                f"generation {gen} ({time.time() - t0:.0f} s): score {results[i][0]:.2f}; "
                + _line("original", results[i][1]["original"])
                + "; "
                + _line("copy", results[i][1]["copy"])
                + f" | best {best:.2f}",
                flush=True,
            )


def _candidate(args) -> tuple[np.ndarray, Path]:
    """(z, output folder) of the ``--validate`` file, its motion written to the folder."""
    z = np.array(json.loads(Path(args.validate).read_text())["z"])
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "kick_right.txt").write_text(format_motion(movement(z)))
    return z, out


def validate(args) -> None:
    z, _ = _candidate(args)
    outcome = kick_and_copy(z, args.world, [0] + list(range(301, 300 + args.seeds)))
    print(_line("original", outcome["original"]))
    print(_line("copy (compensated, balance layer)", outcome["copy"]))
    ratio = np.mean(outcome["copy"]["distance_m"]) / np.mean(outcome["original"]["distance_m"])
    print(f"copy / original distance: {ratio:.2f}")


def black_box(args) -> None:
    """The candidate learned through ``mimic record --server`` and ``mimic train`` (module
    docstring), then the original and the copies kick over held-out seeds."""
    z, out = _candidate(args)
    kick = movement(z)
    model, offset = out / "copy.mimic", tuple(kick.ball_offset_m)
    seen = [out / f"seen{k}.mcap" for k in range(args.recordings)]
    # The motion and 0.35 s for the robot to come to rest in its last keyframe (3.6 s for
    # the kicks in benchmarks/data).
    end_s = sum(step.time_s for step in kick.steps) + 0.35
    for k, path in enumerate(seen):
        # A team kicks whenever it is ready: after the first kick, 0-3 cycles after its robot
        # is set down, which decides which half of the cycles the 25 Hz monitor shows.
        wait_cycles = int(np.random.default_rng([k, 7]).integers(0, 4)) if k else 0
        agent = KeyframePlayer(kick)
        agent.robot = "t1"
        record_black_box(agent, t1_scene("kick", "league", offset), path, k, 8.0, wait_cycles)
        print(f"recorded seed {k}, kicking {wait_cycles} cycles after the set-down: {path}")
    merge = ["--merge"] if len(seen) > 1 else []
    said = mimic(
        "train", *map(str, seen), *merge, "--end", f"{end_s:.2f}", "--epochs",
        str(args.epochs), "-o", str(model), "--force",
    )  # fmt: skip
    print("\n".join(line for line in said if line.startswith(("aligned", "warning: left out"))))
    seeds = list(range(301, 301 + args.seeds))
    runs = {}
    for label, name in (
        ("original", str(out / "kick_right.txt")),
        ("copy +balance", f"{model}+balance"),
        ("copy", str(model)),
    ):
        spec = agent_spec(name, robot="t1")
        where = tuple(spec.ball_offset_m())
        outcomes = [play_t1(spec.build(), "kick", "league", where, seed, 8.0) for seed in seeds]
        runs[label] = dict(
            distance_m=[o[1] for o in outcomes], standing=[bool(o[2]) for o in outcomes]
        )
        print(_line(f"{label} (ball at {where[0]:.3f}, {where[1]:.3f} m)", runs[label]))
    for label in ("copy +balance", "copy"):
        ratio = np.mean(runs[label]["distance_m"]) / np.mean(runs["original"]["distance_m"])
        print(f"{label} / original distance: {ratio:.2f}")
    # And as a user replays them: `mimic play` on a server of its own (the ball placed where
    # each kick wants it, no start noise).
    for label, name in (("original", str(out / "kick_right.txt")), ("copy", f"{model}+balance")):
        played = subprocess.run([MIMIC, "play", name], capture_output=True, text=True)
        said = (played.stdout.strip() or played.stderr.strip()).splitlines()
        print(f"mimic play {label}: {said[-1] if said else played.returncode}")
        runs[f"mimic play {label}"] = said[-1] if said else ""
    (out / "black_box.json").write_text(json.dumps(dict(seeds=seeds, **runs), indent=1))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--world", choices=("league", "mujoco"), default="league")
    parser.add_argument("--generations", type=int, default=40)
    parser.add_argument("--population", type=int, default=10)
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--sigma", type=float, default=0.5)
    parser.add_argument("--cap", type=float, default=5.0, help="most the original scores [m]")
    parser.add_argument("--seed", type=int, default=12, help="seeds CMA-ES")
    parser.add_argument("--start", help="a best.json to start from (default: kick_right)")
    parser.add_argument("--out", default="out/t1_copyable_kick")
    parser.add_argument("--validate", help="a best.json to replay on held-out seeds")
    parser.add_argument(
        "--black-box",
        action="store_true",
        help="with --validate: learn the copy through mimic record --server and mimic train",
    )
    parser.add_argument(
        "--recordings",
        type=int,
        default=1,
        help="with --black-box: record the kick this many times (seeds 0 on) and learn one "
        "copy from them all (mimic train --merge)",
    )
    parser.add_argument(
        "--epochs",
        type=int,
        default=100_000,
        help="with --black-box: mimic train --epochs (pooled 50 Hz samples of several "
        "recordings fit closer with more than the default 25000)",
    )
    args = parser.parse_args()
    for given in (args.start, args.validate):
        if given and not Path(given).is_file():
            parser.error(f"{given}: no such file; give a best.json the search wrote")
    if args.black_box and not args.validate:
        parser.error("--black-box needs --validate FILE")
    if args.recordings < 1 or (args.recordings > 1 and not args.black_box):
        parser.error("--recordings: 1 or more, and only with --black-box")
    if args.validate:
        black_box(args) if args.black_box else validate(args)
    else:
        search(args)


if __name__ == "__main__":
    main()
