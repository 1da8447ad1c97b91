"""Benchmark the other team's walk (15 m, own goal line to centre line) and kick.

    python benchmarks/other_team_walk.py [--walk-runs 3] [--kick-runs 5]

Walk: 3 seeded runs (speed-command noise 0.05 rad/s, the first noise-free): speed after the
first metre, largest lateral drift, falls, and how much the last two gait periods' joint
angles differ (mean absolute difference). Kick: 5 seeded runs with small perturbations of the
start pose, ball position and commands: ball distance and whether the robot stands 2 s later.
"""

from __future__ import annotations

import argparse

import numpy as np
from rich.console import Console
from rich.table import Table

from mimic.agents.other_team import make_kick, make_walk
from mimic.checks.walking import kick_from_stand, straight_walk
from mimic.world.base import CYCLE_S
from mimic.world.mujoco_world import MujocoWorld


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--walk-runs", type=int, default=3)
    ap.add_argument("--kick-runs", type=int, default=5)
    args = ap.parse_args()
    world, console = MujocoWorld(), Console()
    walk = make_walk()
    console.print(
        f"walk period {walk.period_s:.3f} s, step {walk.period_s / 2:.3f} s "
        f"({round(walk.period_s / 2 / CYCLE_S)} cycles)"
    )
    runs = [
        straight_walk(make_walk, 15.0, seed=s, speed_noise_rad_s=0.05 if s else 0.0, world=world)
        for s in range(args.walk_runs)
    ]
    period = round(walk.period_s / CYCLE_S)
    t = Table(title="other team walk, 15 m")
    for c in (
        "seed",
        "fell",
        "distance m",
        "speed m/s",
        "max drift m",
        "time s",
        "last 2 periods differ deg",
    ):
        t.add_column(c)
    for s, r in enumerate(runs):
        last = r.angles_rad[-2 * period :]
        diff = np.degrees(np.abs(last[:period] - last[period:]).mean())
        t.add_row(
            str(s),
            str(r.fell),
            f"{r.distance_m:.2f}",
            f"{r.speed_m_s:.3f}",
            f"{r.max_drift_m:.3f}",
            f"{r.time_s:.1f}",
            f"{diff:.2f}",
        )
    sp = np.array([r.speed_m_s for r in runs])
    t.add_row(
        "all",
        f"{sum(r.fell for r in runs)}/{len(runs)}",
        f"{np.mean([r.distance_m for r in runs]):.2f}",
        f"{sp.mean():.3f} ± {sp.std():.3f}",
        f"{max(r.max_drift_m for r in runs):.3f}",
        "",
    )
    console.print(t)
    kicks = [
        kick_from_stand(
            make_kick,
            seed=s,
            pose_noise_rad=0.01,
            ball_noise_m=0.01,
            speed_noise_rad_s=0.05,
            world=world,
        )
        for s in range(args.kick_runs)
    ]
    t = Table(title="other team kick")
    for c in ("seed", "distance m", "lateral m", "standing"):
        t.add_column(c)
    for s, r in enumerate(kicks):
        t.add_row(str(s), f"{r.distance_m:.2f}", f"{r.lateral_m:+.2f}", str(r.standing))
    d = np.array([r.distance_m for r in kicks])
    t.add_row(
        "all",
        f"{d.mean():.2f} ± {d.std():.2f}",
        "",
        f"{sum(r.standing for r in kicks)}/{len(kicks)}",
    )
    console.print(t)


if __name__ == "__main__":
    main()
