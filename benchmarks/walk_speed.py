"""Walk benchmark: 15 m forward from our goal line (x = -15) to the centre line (x = 0).

Per run (seeded: the seed jitters the start pose by a few mm / a degree): speed [m/s] over the
15 m, lateral drift [m], falls, simulated and wall time, real-time factor, and the walk
agent's own cost per cycle (act) next to the world step's cost measured in the same process.
With ``--stop-goto`` it also measures stopping (from full speed: time to rest, distance
travelled after the stop command, final pose error against the stand pose) and go-to-pose
accuracy (position [cm] and heading [deg] error on arrival, time, falls) for a few targets.

    python benchmarks/walk_speed.py [--runs 5] [--speed 0.45] [--stop-goto]
"""

from __future__ import annotations

import argparse
import inspect
import math
import time

import numpy as np

from mimic.agents.walk import WalkEngine, make_walk_agent
from mimic.agents.walk.goto import GoToPose, wrap_angle
from mimic.checks.ball_approach import go_to_pose
from mimic.robot.nao import nao
from mimic.world.base import CYCLE_S, World
from mimic.world.field import FIELD_LENGTH_M
from mimic.world.mujoco_world import MujocoWorld


def walk_15m(world: World, seed: int, speed_m_s: float, timeout_s: float = 90.0) -> dict:
    rng = np.random.default_rng(seed)
    start_x = -FIELD_LENGTH_M / 2
    world.reset()
    world.place_robot(
        start_x + rng.uniform(-0.005, 0.005),
        rng.uniform(-0.005, 0.005),
        math.radians(rng.uniform(-1, 1)),
        nao().stand_pose(),
    )
    agent = make_walk_agent(speed_m_s)
    agent.reset(world.observe())
    act_s = step_s = 0.0
    falls = 0
    t_cross = None
    max_drift = 0.0
    wall0 = time.perf_counter()
    for _ in range(int(timeout_s / CYCLE_S)):
        obs = world.observe()
        t0 = time.perf_counter()
        speeds = agent.act(obs)
        t1 = time.perf_counter()
        world.step(speeds)
        step_s += time.perf_counter() - t1
        act_s += t1 - t0
        max_drift = max(max_drift, abs(world.torso_pos_m()[1]))
        if world.fallen():
            falls += 1
            break
        if world.torso_pos_m()[0] >= 0.0:
            t_cross = world.time_s
            break
    wall = time.perf_counter() - wall0
    p = world.torso_pos_m()
    cycles = world.cycle
    return dict(
        seed=seed,
        reached=t_cross is not None,
        speed_m_s=(p[0] - start_x) / world.time_s,
        lateral_drift_m=float(p[1]),
        max_drift_m=max_drift,
        falls=falls,
        sim_s=world.time_s,
        wall_s=wall,
        real_time_factor=world.time_s / wall,
        act_us=act_s / cycles * 1e6,
        step_us=step_s / cycles * 1e6,
    )


def stop_from_speed(world: World, seed: int, speed_m_s: float, walk_s: float = 6.0) -> dict:
    """Walk ``walk_s`` at ``speed_m_s``, call stop(); time and distance until standing."""
    rng = np.random.default_rng(seed)
    world.reset()
    world.place_robot(
        -FIELD_LENGTH_M / 2, 0.0, math.radians(rng.uniform(-1, 1)), nao().stand_pose()
    )
    agent = make_walk_agent(speed_m_s)
    agent.reset(world.observe())
    fell = False
    for _ in range(int(walk_s / CYCLE_S)):
        world.step(agent.act(world.observe()))
        fell |= world.fallen()
    agent.stop()
    x0, t0 = world.torso_pos_m()[0], world.time_s
    t_rest = None
    for _ in range(int(5.0 / CYCLE_S)):
        world.step(agent.act(world.observe()))
        fell |= world.fallen()
        if agent.state == "standing" and t_rest is None:
            t_rest = world.time_s - t0
    obs = world.observe()
    return dict(
        seed=seed,
        fell=fell,
        standing=agent.state == "standing" and agent.done,
        time_to_rest_s=t_rest if t_rest is not None else float("nan"),
        distance_after_stop_m=world.torso_pos_m()[0] - x0,
        pose_error_deg=math.degrees(np.abs(obs.joint_angles_rad - nao().stand_pose()).max()),
    )


GOTO_CASES = (  # (start x, y, yaw [deg]) -> target (x, y, heading [deg])
    ((-12.0, 0.0, 0.0), (-11.0, 0.3, 30.0)),
    ((-12.0, 0.0, 0.0), (-9.0, -1.0, -90.0)),
    ((-12.0, 0.0, 0.0), (-13.0, 0.5, 180.0)),
    ((-12.0, 0.0, 90.0), (-11.5, -0.2, 0.0)),
    ((-12.0, 0.0, 0.0), (-12.1, 0.15, -20.0)),
)


def go_to(world: World, start, target, timeout_s: float = 40.0) -> dict:
    world.reset()
    world.place_robot(start[0], start[1], math.radians(start[2]), nao().stand_pose())
    goal = (target[0], target[1], math.radians(target[2]))
    goto = GoToPose(WalkEngine())
    fell = go_to_pose(world, goto, goal, timeout_s)
    p = world.torso_pos_m()
    return dict(
        target=target,
        fell=fell,
        arrived=goto.arrived,
        time_s=world.time_s,
        error_cm=100 * math.hypot(p[0] - goal[0], p[1] - goal[1]),
        heading_error_deg=math.degrees(wrap_angle(world.torso_yaw_rad() - goal[2])),
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--speed", type=float, default=None, help="commanded speed [m/s]")
    parser.add_argument("--stop-goto", action="store_true", help="also measure stop / go-to")
    args = parser.parse_args()
    speed = args.speed or inspect.signature(make_walk_agent).parameters["vx_m_s"].default
    world = MujocoWorld()
    print(f"commanded {speed:.2f} m/s; x = -15 -> 0 (15 m); speed = distance / time incl. start")
    print(
        f"{'seed':>4} {'reached':>7} {'speed':>7} {'drift_y':>8} {'max|y|':>7} {'falls':>5} "
        f"{'sim_s':>6} {'wall_s':>6} {'RTF':>6} {'act_us':>7} {'step_us':>7} {'act/step':>8}"
    )
    rows = [walk_15m(world, seed, speed) for seed in range(args.runs)]
    for r in rows:
        print(
            f"{r['seed']:>4} {str(r['reached']):>7} {r['speed_m_s']:7.3f} "
            f"{r['lateral_drift_m']:8.3f} {r['max_drift_m']:7.3f} {r['falls']:>5} "
            f"{r['sim_s']:6.1f} {r['wall_s']:6.2f} {r['real_time_factor']:6.0f} "
            f"{r['act_us']:7.0f} {r['step_us']:7.0f} {r['act_us'] / r['step_us']:8.2f}"
        )
    sp = np.array([r["speed_m_s"] for r in rows])
    dr = np.array([abs(r["lateral_drift_m"]) for r in rows])
    print(
        f"speed {sp.mean():.3f} +- {sp.std():.3f} m/s, |drift| {dr.mean():.3f} m (max "
        f"{dr.max():.3f}), falls {sum(r['falls'] for r in rows)} / {len(rows)} runs"
    )
    if not args.stop_goto:
        return
    print(f"\nstop after 6 s at {speed:.2f} m/s")
    for r in (stop_from_speed(world, seed, speed) for seed in range(args.runs)):
        print(
            f"  seed {r['seed']}: fell {r['fell']}, standing {r['standing']}, rest after "
            f"{r['time_to_rest_s']:.2f} s, {r['distance_after_stop_m']:.2f} m, pose error "
            f"{r['pose_error_deg']:.1f} deg"
        )
    print("\ngo-to-pose")
    for start, target in GOTO_CASES:
        r = go_to(world, start, target)
        print(
            f"  {start} -> {target}: fell {r['fell']}, arrived {r['arrived']} after "
            f"{r['time_s']:.1f} s, error {r['error_cm']:.1f} cm, "
            f"{r['heading_error_deg']:.1f} deg"
        )


if __name__ == "__main__":
    main()
