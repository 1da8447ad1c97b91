"""Walk benchmark: 15 m forward from our goal line (x = -15) to the centre line (x = 0).

Per run (seeded: the seed jitters the start pose by a few mm / a degree): speed [m/s] over the
15 m, lateral drift [m], falls, simulated and wall time, real-time factor, and the walk
agent's own cost per cycle (act) next to the world step's cost measured in the same process.

    /work/venv/bin/python benchmarks/walk_speed.py [--runs 3] [--speed 0.5]
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from mimic.agents.walk import make_walk_agent, stand_pose_rad
from mimic.world.field import FIELD_LENGTH_M
from mimic.world.world import CYCLE_S, World


def walk_15m(world: World, seed: int, speed_m_s: float, timeout_s: float = 90.0) -> dict:
    rng = np.random.default_rng(seed)
    start_x = -FIELD_LENGTH_M / 2
    world.reset()
    world.beam(start_x + rng.uniform(-0.005, 0.005), rng.uniform(-0.005, 0.005),
               math.radians(rng.uniform(-1, 1)), stand_pose_rad())
    agent = make_walk_agent(speed_m_s)
    agent.reset(world.observe())
    act_s = step_s = 0.0
    falls = 0
    t_cross = None
    wall0 = time.perf_counter()
    for _ in range(int(timeout_s / CYCLE_S)):
        obs = world.observe()
        t0 = time.perf_counter()
        speeds = agent.act(obs)
        t1 = time.perf_counter()
        world.step(speeds)
        step_s += time.perf_counter() - t1
        act_s += t1 - t0
        if world.fallen():
            falls += 1
            break
        if world.torso_pos_m()[0] >= 0.0:
            t_cross = world.time_s
            break
    wall = time.perf_counter() - wall0
    p = world.torso_pos_m()
    cycles = world.cycle
    return dict(seed=seed, reached=t_cross is not None,
                speed_m_s=(p[0] - start_x) / world.time_s,
                lateral_drift_m=float(p[1]), falls=falls, sim_s=world.time_s, wall_s=wall,
                real_time_factor=world.time_s / wall, act_us=act_s / cycles * 1e6,
                step_us=step_s / cycles * 1e6)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--speed", type=float, default=None, help="commanded speed [m/s]")
    args = parser.parse_args()
    from mimic.agents.walk import make_walk_agent as _m
    import inspect
    speed = args.speed or inspect.signature(_m).parameters["vx_m_s"].default
    world = World()
    print(f"commanded {speed:.2f} m/s; x = -15 -> 0 (15 m); speed = distance / time incl. start")
    print(f"{'seed':>4} {'reached':>7} {'speed':>7} {'drift_y':>8} {'falls':>5} {'sim_s':>6} "
          f"{'wall_s':>6} {'RTF':>6} {'act_us':>7} {'step_us':>7} {'act/step':>8}")
    rows = [walk_15m(world, seed, speed) for seed in range(args.runs)]
    for r in rows:
        print(f"{r['seed']:>4} {str(r['reached']):>7} {r['speed_m_s']:7.3f} "
              f"{r['lateral_drift_m']:8.3f} {r['falls']:>5} {r['sim_s']:6.1f} {r['wall_s']:6.2f} "
              f"{r['real_time_factor']:6.0f} {r['act_us']:7.0f} {r['step_us']:7.0f} "
              f"{r['act_us'] / r['step_us']:8.2f}")
    sp = np.array([r["speed_m_s"] for r in rows])
    print(f"speed {sp.mean():.3f} +- {sp.std():.3f} m/s, falls {sum(r['falls'] for r in rows)}"
          f" / {len(rows)} runs")


if __name__ == "__main__":
    main()
