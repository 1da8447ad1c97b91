"""Walk robustness under model perturbations: our walk and the other team's walk, 15 m each.

    python benchmarks/perturbation.py [--runs 10] [--noise 0.05] [--workers 2] [--corners]
                                      [--out perturbation.parquet]

Every case perturbs the compiled MuJoCo model of a fresh ``MujocoWorld`` before the walks:
sliding friction of the grass and of every robot geom (MuJoCo takes the larger of the two
geoms' coefficients, so both are scaled) and the mass (with the rotational inertia, as for a
uniformly denser body) of every robot body. The default cases are the nominal model and
friction -10 % / +10 % and masses -10 % / +10 % one at a time; ``--corners`` adds the four
combinations (friction and masses both off by 10 %).

Each case walks ``--runs`` seeded 15 m walks per agent from the own goal line
(``mimic.checks.walking.straight_walk``), with Gaussian noise on the speed commands
(``--noise`` rad/s, seeded; the seed is what makes the walks of one case differ). Reported per
agent and case: falls, mean and lowest speed after the first metre [m/s], mean and largest
lateral drift (largest |y| of a walk) [m]. The weakest case of each agent is the one with the
most falls, then the slowest mean speed.
"""

from __future__ import annotations

import argparse
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import polars as pl
from rich.console import Console
from rich.table import Table

from mimic.agents.registry import make_agent
from mimic.checks.walking import straight_walk
from mimic.world.mujoco_world import MujocoWorld

AGENTS = ("walk", "other-team-walk")


@dataclass(frozen=True)
class Case:
    """A model perturbation: scale factors of friction and robot masses."""

    name: str
    friction: float = 1.0
    mass: float = 1.0


SINGLE_CASES = (
    Case("nominal"),
    Case("friction -10%", friction=0.9),
    Case("friction +10%", friction=1.1),
    Case("masses -10%", mass=0.9),
    Case("masses +10%", mass=1.1),
)
CORNER_CASES = tuple(
    Case(f"friction {f:+.0%}, masses {m:+.0%}", friction=1 + f, mass=1 + m)
    for f in (-0.1, 0.1)
    for m in (-0.1, 0.1)
)


def robot_body_ids(world: MujocoWorld) -> np.ndarray:
    """Ids of the torso and every body below it (the robot, not the ball or goals)."""
    m = world.model
    root = world.torso_body_id
    ids = [b for b in range(m.nbody) if b == root or _below(m.body_parentid, b, root)]
    return np.array(ids)


def _below(parent: np.ndarray, body: int, root: int) -> bool:
    while body != 0:
        body = int(parent[body])
        if body == root:
            return True
    return False


def perturbed_world(case: Case) -> MujocoWorld:
    """A fresh world whose compiled model has ``case``'s friction and masses."""
    world = MujocoWorld()
    m = world.model
    robot = robot_body_ids(world)
    ground = m.geom("ground").id
    geoms = [g for g in range(m.ngeom) if g == ground or m.geom_bodyid[g] in set(robot)]
    m.geom_friction[geoms, 0] *= case.friction
    m.body_mass[robot] *= case.mass
    m.body_inertia[robot] *= case.mass
    return world


def run_case(job: tuple[Case, str, int, float]) -> list[dict]:
    """All walks of one agent in one case (one process, one world)."""
    case, agent, runs, noise = job
    world = perturbed_world(case)
    rows = []
    for seed in range(runs):
        r = straight_walk(
            lambda: make_agent(agent), 15.0, seed=seed, speed_noise_rad_s=noise, world=world
        )
        rows.append(
            dict(
                agent=agent,
                case=case.name,
                friction=case.friction,
                mass=case.mass,
                seed=seed,
                fell=r.fell,
                distance_m=r.distance_m,
                speed_m_s=r.speed_m_s,
                max_drift_m=r.max_drift_m,
                time_s=r.time_s,
            )
        )
    return rows


def summarise(rows: pl.DataFrame) -> pl.DataFrame:
    """Per agent and case: walks, falls, speed (mean, lowest), drift (mean, largest).

    Speeds are over the walks that covered at least two metres (a fall at the start has
    no speed)."""
    walked = pl.col("distance_m") >= 2.0
    return rows.group_by(["agent", "case"], maintain_order=True).agg(
        pl.len().alias("runs"),
        pl.col("fell").sum().alias("falls"),
        pl.col("speed_m_s").filter(walked).mean().alias("mean_speed_m_s"),
        pl.col("speed_m_s").filter(walked).min().alias("min_speed_m_s"),
        pl.col("max_drift_m").mean().alias("mean_drift_m"),
        pl.col("max_drift_m").max().alias("max_drift_m"),
    )


def weakest(summary: pl.DataFrame, agent: str) -> dict:
    """The case with the most falls, then the lowest mean speed."""
    rows = summary.filter(pl.col("agent") == agent).sort(
        [pl.col("falls"), pl.col("mean_speed_m_s")], descending=[True, False]
    )
    return rows.row(0, named=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=10, help="seeded walks per agent and case")
    ap.add_argument("--noise", type=float, default=0.05, help="speed-command noise [rad/s]")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument(
        "--corners",
        action="store_true",
        help="also friction and masses off together (4 more cases)",
    )
    ap.add_argument("--agents", nargs="+", default=list(AGENTS), choices=AGENTS)
    ap.add_argument("--out", type=Path, default=None, help="write every walk to this parquet")
    args = ap.parse_args()
    console = Console(width=110)
    cases = SINGLE_CASES + (CORNER_CASES if args.corners else ())
    jobs = [(case, agent, args.runs, args.noise) for agent in args.agents for case in cases]
    start = time.perf_counter()
    if args.workers > 1:
        with ProcessPoolExecutor(args.workers) as pool:
            results = list(pool.map(run_case, jobs))
    else:
        results = [run_case(job) for job in jobs]
    rows = pl.DataFrame([r for batch in results for r in batch])
    summary = summarise(rows)
    wall = time.perf_counter() - start

    table = Table(
        title=f"15 m walks under perturbed friction / masses, {args.runs} seeds "
        f"each, command noise {args.noise} rad/s"
    )
    for c in ("agent", "case", "falls", "speed m/s", "lowest", "drift m", "largest"):
        table.add_column(c, justify="left" if c in ("agent", "case") else "right", no_wrap=True)
    for r in summary.iter_rows(named=True):
        table.add_row(
            r["agent"],
            r["case"],
            f"{r['falls']}/{r['runs']}",
            _num(r["mean_speed_m_s"]),
            _num(r["min_speed_m_s"]),
            f"{r['mean_drift_m']:.2f}",
            f"{r['max_drift_m']:.2f}",
        )
    console.print(table)
    for agent in args.agents:
        w = weakest(summary, agent)
        console.print(
            f"weakest case for {agent}: {w['case']} ({w['falls']}/{w['runs']} "
            f"falls, {_num(w['mean_speed_m_s'])} m/s, drift up to "
            f"{w['max_drift_m']:.2f} m)"
        )
    console.print(
        f"{len(rows)} walks, {rows['time_s'].sum():.0f} s simulated, {wall:.0f} s "
        f"wall ({args.workers} workers)"
    )
    if args.out:
        rows.write_parquet(args.out)
        console.print(f"wrote {args.out}")


def _num(x: float | None) -> str:
    return "-" if x is None else f"{x:.3f}"


if __name__ == "__main__":
    main()
