"""Benchmark the T1 team's walk (10 m straight), its stop and its kick, in three worlds.

    python benchmarks/other_team_t1.py [--worlds mujoco,league-like,league] [--walk-runs 10]
                                       [--kick-runs 10] [--first-seed 0]

Worlds:

* ``mujoco``: our MuJoCo world (``MujocoWorld("t1")``: the league's field, ball and robot MJCF).
* ``league-like``: the same world with what the league server does differently: its solver
  options (Euler integrator, pyramidal friction cones, 100 solver iterations; ours are
  implicitfast, elliptic, 20) and its one-cycle command latency (the server's parallel loop
  applies the answer to a perception one 20 ms cycle later than our world does). The team's
  parameters were tuned here; it needs no server.
* ``league``: RCSSServerMJ itself, hosted (``LeagueWorld``).

Walk: seeded start-pose noise (every joint, normal, 0.03 rad), from the own goal line: speed
after the first metre, largest sideways drift, falls. Stop: 4 s of walking, then ``stop()``:
distance and time to standing, upright 1 s later. Kick: ``kick_from_stand`` with start-pose
noise 0.02 rad: ball travel (forward, sideways) and whether the robot stands 2 s later.
"""

from __future__ import annotations

import argparse
import time

import mujoco
import numpy as np
from rich.console import Console
from rich.table import Table

from mimic.agents.base import Agent, JointCommand
from mimic.agents.other_team_t1 import make_kick, make_walk
from mimic.checks.walking import kick_from_stand, straight_walk
from mimic.episode import Scene, run
from mimic.world.base import Observation
from mimic.world.mujoco_world import MujocoWorld

WALK_POSE_NOISE_RAD = 0.03
KICK_POSE_NOISE_RAD = 0.02


class OneCycleLate(Agent):
    """Plays an agent's commands one cycle late (the league server's latency); the first
    cycle holds the angles reached."""

    def __init__(self, inner: Agent) -> None:
        super().__init__()
        self.inner = inner
        for name in ("name", "team", "robot", "robot_only", "period_s"):
            setattr(self, name, getattr(inner, name))
        self.ball_offset_m = getattr(inner, "ball_offset_m", None)
        self._last: JointCommand | None = None

    def reset(self, obs: Observation) -> None:
        self.inner.reset(obs)
        self._last, self.done = None, False

    def act(self, obs: Observation) -> JointCommand:
        command = self.inner.act(obs)
        self.done = self.inner.done
        late = self._last or JointCommand.references(obs.joint_angles_rad)
        self._last = command
        return late


def league_like_world() -> MujocoWorld:
    """Our MuJoCo world with the league server's solver options."""
    world = MujocoWorld("t1")
    opt = world.model.opt
    opt.integrator = mujoco.mjtIntegrator.mjINT_EULER
    opt.cone = mujoco.mjtCone.mjCONE_PYRAMIDAL
    opt.iterations, opt.ls_iterations = 100, 50
    opt.disableflags &= ~int(mujoco.mjtDisableBit.mjDSBL_EULERDAMP)
    return world


def _world(name: str):
    """(world, agent wrapper) for a world name."""
    if name == "mujoco":
        return MujocoWorld("t1"), lambda agent: agent
    if name == "league-like":
        return league_like_world(), OneCycleLate
    if name == "league":
        from mimic.world.league_server import LeagueWorld, LeagueWorldConfig

        return LeagueWorld(
            "t1", config=LeagueWorldConfig(team="Others", player=2)
        ), lambda agent: agent
    raise SystemExit(f"unknown world {name!r}: mujoco, league-like or league")


def _walks(world, wrap, seeds, console: Console, label: str) -> None:
    t = Table(title=f"T1 other team walk, 10 m, {label}")
    for c in ("seed", "fell", "distance m", "speed m/s", "max drift m", "time s", "wall s"):
        t.add_column(c)
    runs = []
    for s in seeds:
        t0 = time.perf_counter()
        r = straight_walk(
            lambda: wrap(make_walk()),
            10.0,
            seed=s,
            world=world,
            pose_noise_rad=WALK_POSE_NOISE_RAD,
            max_time_s=40.0,
        )
        runs.append(r)
        t.add_row(
            str(s),
            str(r.fell),
            f"{r.distance_m:.2f}",
            f"{r.speed_m_s:.3f}",
            f"{r.max_drift_m:.3f}",
            f"{r.time_s:.1f}",
            f"{time.perf_counter() - t0:.1f}",
        )
    sp = np.array([r.speed_m_s for r in runs if not r.fell] or [0.0])
    t.add_row(
        "all",
        f"{sum(r.fell for r in runs)}/{len(runs)}",
        "",
        f"{sp.mean():.3f} ± {sp.std():.3f}",
        f"{max(r.max_drift_m for r in runs):.3f}",
        "",
        "",
    )
    console.print(t)


def _stop(world, wrap, console: Console, label: str) -> None:
    Scene(robot_xy_m=(-15.0, 0.0), settle_s=0.3).setup(world, np.random.default_rng(0))
    walk = make_walk()
    agent = wrap(walk)
    walking = run(world, agent, max_s=4.0, abort_on_fall=True).end == "timeout"
    walk.stop()
    x0, t0 = world.torso_pos_m()[0], world.time_s
    end = run(world, agent, max_s=8.0, reset=False, abort_on_fall=True).end
    x1, t1 = world.torso_pos_m()[0], world.time_s
    run(world, agent, max_s=1.0, reset=False, stop_when_done=False)
    console.print(
        f"stop, {label}: walking {walking}, then {end} ({walk.state}) after "
        f"{x1 - x0:.2f} m and {t1 - t0:.2f} s; 1 s later moved "
        f"{world.torso_pos_m()[0] - x1:+.3f} m, upright {world.upright()}"
    )


def _kicks(world, wrap, seeds, console: Console, label: str) -> None:
    t = Table(title=f"T1 other team kick, {label}")
    for c in ("seed", "distance m", "lateral m", "standing"):
        t.add_column(c)
    kicks = [
        kick_from_stand(
            lambda: wrap(make_kick()), seed=s, world=world, pose_noise_rad=KICK_POSE_NOISE_RAD
        )
        for s in seeds
    ]
    for s, r in zip(seeds, kicks):
        t.add_row(str(s), f"{r.distance_m:.2f}", f"{r.lateral_m:+.2f}", str(r.standing))
    d = np.array([r.distance_m for r in kicks])
    t.add_row(
        "all",
        f"{d.mean():.2f} ± {d.std():.2f} (min {d.min():.2f})",
        "",
        f"{sum(r.standing for r in kicks)}/{len(kicks)}",
    )
    console.print(t)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--worlds", default="mujoco,league-like,league")
    ap.add_argument("--walk-runs", type=int, default=10)
    ap.add_argument("--kick-runs", type=int, default=10)
    ap.add_argument("--first-seed", type=int, default=0)
    args = ap.parse_args()
    console = Console()
    for name in args.worlds.split(","):
        world, wrap = _world(name)
        try:
            seeds = range(args.first_seed, args.first_seed + args.walk_runs)
            if args.walk_runs:
                _walks(world, wrap, seeds, console, name)
                _stop(world, wrap, console, name)
            if args.kick_runs:
                _kicks(
                    world,
                    wrap,
                    range(args.first_seed, args.first_seed + args.kick_runs),
                    console,
                    name,
                )
        finally:
            if hasattr(world, "close"):
                world.close()


if __name__ == "__main__":
    main()
