"""How much a get-up depends on its exact timing: success over seeded runs with its keyframe
times moved.

Run: python benchmarks/getup_timing.py [--robot t1] [--runs 10] [--motion FILE.txt ...]

Three rows per get-up (in our MuJoCo world, seeds 0..runs-1, the checks' usual start-pose
noise):

* ``as shipped``: the motion unchanged.
* ``sub-cycle offset``: run k starts every keyframe (k mod 10) * 2 ms later (the first step
  takes that much longer), so the 0.02 s control cycle samples the spline at other points.
* ``step jitter +-10 ms`` and ``+-20 ms``: every step longer than 0.05 s (the repeated 0.03 s
  pins are kept) takes a uniform random extra time in that range, drawn per run from
  ``np.random.default_rng(run)``.

A get-up that only works at one timing is tuned to the cycle grid, not to the robot.
``--motion`` checks motion files instead of the robot's shipped get-ups (their ``start`` line
says the side).
"""

from __future__ import annotations

import argparse
import dataclasses
from pathlib import Path

import numpy as np
from rich.console import Console
from rich.table import Table

from mimic.checks.motions import run_getup
from mimic.motion.files import load_motion, parse_motion
from mimic.motion.keyframe import Movement

#: Steps at most this long are the repeated pins of the natural spline; left alone [s].
PIN_S = 0.05


def offset(movement: Movement, extra_s: float) -> Movement:
    """The movement with its first step ``extra_s`` longer [s]."""
    first = dataclasses.replace(movement.steps[0], time_s=movement.steps[0].time_s + extra_s)
    return dataclasses.replace(movement, steps=(first, *movement.steps[1:]))


def jitter(movement: Movement, half_width_s: float, rng: np.random.Generator) -> Movement:
    """The movement with every step longer than ``PIN_S`` moved by uniform noise [s]."""
    steps = tuple(
        dataclasses.replace(s, time_s=s.time_s + rng.uniform(-half_width_s, half_width_s))
        if s.time_s > PIN_S
        else s
        for s in movement.steps
    )
    return dataclasses.replace(movement, steps=steps)


def rates(movement: Movement, runs: int) -> dict[str, int]:
    """Upright runs out of ``runs`` per timing change."""
    side = movement.start_posture.removeprefix("lying_")
    variants = {
        "as shipped": lambda k: movement,
        "sub-cycle offset": lambda k: offset(movement, 0.002 * (k % 10)),
        "step jitter +-10 ms": lambda k: jitter(movement, 0.010, np.random.default_rng(k)),
        "step jitter +-20 ms": lambda k: jitter(movement, 0.020, np.random.default_rng(k)),
    }
    return {
        name: sum(run_getup(make(k), side, seed=k).upright for k in range(runs))
        for name, make in variants.items()
    }


def main(robot: str = "t1", runs: int = 10, files: list[Path] | None = None) -> None:
    if files:
        movements = [parse_motion(f.read_text(), f.name) for f in files]
    else:
        movements = [load_motion(f"getup_{side}", robot) for side in ("front", "back")]
    table = Table(title=f"get-ups with their keyframe times moved, {runs} seeded runs each")
    table.add_column("motion")
    columns = None
    for movement in movements:
        result = rates(movement, runs)
        if columns is None:
            columns = list(result)
            for c in columns:
                table.add_column(c)
        table.add_row(movement.name, *(f"{result[c]}/{runs}" for c in columns))
    Console(width=120).print(table)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robot", default="t1")
    parser.add_argument("--runs", type=int, default=10)
    parser.add_argument("--motion", type=Path, nargs="*", help="motion files instead")
    args = parser.parse_args()
    main(args.robot, args.runs, args.motion)
