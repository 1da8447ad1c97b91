"""The other team on the Booster T1: its walk and kick in our MuJoCo world (the league's field,
ball and PD motors), its IK against MuJoCo, its registry names, and the team process on a
hosted league server."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mimic.agents.other_team_t1 import OtherTeamT1Walk, make_kick, make_walk
from mimic.agents.other_team_t1.ik import leg_chains
from mimic.agents.registry import make_agent
from mimic.checks.walking import kick_from_stand, straight_walk
from mimic.episode import Scene, run
from mimic.errors import MimicError
from mimic.robot.registry import get_robot
from mimic.world.mujoco_world import MujocoWorld

pytest.importorskip("rcsssmj")

T1 = get_robot("t1")
#: Start-pose noise of the walk checks: every joint, normal, std [rad].
POSE_NOISE_RAD = 0.03
#: Walk targets: speed [m/s] and sideways drift [m] over a straight walk.
WALK_SPEED_M_S = 0.5
WALK_DRIFT_M = 0.3
#: Kick target: the league ball (r = 0.11 m) at least this far forward [m].
KICK_DISTANCE_M = 1.5


@pytest.fixture(scope="module")
def world() -> MujocoWorld:
    return MujocoWorld("t1")


def test_the_names_resolve_per_robot_and_the_nao_keeps_its_team():
    walk, kick = (
        make_agent("other-team-walk", robot="t1"),
        make_agent("other-team-kick", robot="t1"),
    )
    assert isinstance(walk, OtherTeamT1Walk)
    assert (walk.robot, kick.robot) == ("t1", "t1") and walk.robot_only and kick.robot_only
    assert walk.team == kick.team == "other_team"
    assert walk.period_s > 0 and kick.period_s is None
    assert len(kick.ball_offset_m) == 2 and kick.ball_offset_m[0] > 0
    nao_walk = make_agent("other-team-walk")
    assert nao_walk.robot == "nao" and not isinstance(nao_walk, OtherTeamT1Walk)
    with pytest.raises(MimicError, match="T1-only"):
        make_walk().check_robot(get_robot("nao"))


def test_agents_hide_their_references(world):
    Scene(settle_s=0.1).setup(world, np.random.default_rng(0))
    for agent in (make_walk(), make_kick()):
        run(world, agent, max_s=0.2)
        assert agent.reference_rad is None


@pytest.mark.parametrize("side", [1.0, -1.0])
def test_leg_ik_matches_mujoco_and_round_trips(world, side):
    chain = leg_chains(T1)[side]
    m, d = world.model, world.data
    torso, foot = m.body(T1.root_link).id, m.body(T1.foot_links[0 if side > 0 else 1]).id
    rng = np.random.default_rng(7)
    for _ in range(10):
        q = T1.clip(T1.stand_pose() + rng.uniform(-0.3, 0.3, T1.num_joints))
        world.place_robot(0.0, 0.0, 0.3, q)
        r_torso = d.xmat[torso].reshape(3, 3)
        pos_mj = r_torso.T @ (d.xpos[foot] - d.xpos[torso])
        rot_mj = r_torso.T @ d.xmat[foot].reshape(3, 3)
        pos, rot = chain.fk(q[chain.joints], q[chain.fixed])
        assert np.abs(pos - pos_mj).max() < 1e-6 and np.abs(rot - rot_mj).max() < 1e-6
        q_ik = chain.ik(
            pos_mj,
            rot_mj,
            T1.stand_pose()[chain.joints],
            fixed_rad=q[chain.fixed],
            iterations=30,
            tolerance_m=1e-9,
        )
        pos_ik, rot_ik = chain.fk(q_ik, q[chain.fixed])
        assert np.abs(pos_ik - pos_mj).max() < 1e-5 and np.abs(rot_ik - rot_mj).max() < 1e-4
        assert np.abs(q_ik - q[chain.joints]).max() < 1e-3


def test_walk_covers_3_m_fast_without_falling(world):
    r = straight_walk(
        make_walk,
        distance_m=3.0,
        seed=0,
        world=world,
        pose_noise_rad=POSE_NOISE_RAD,
        max_time_s=15.0,
    )
    assert not r.fell and r.distance_m >= 3.0
    assert r.speed_m_s >= WALK_SPEED_M_S
    assert r.max_drift_m < WALK_DRIFT_M


def test_walk_stops_on_command_and_stands(world):
    Scene(robot_xy_m=(-15.0, 0.0), settle_s=0.3).setup(world, np.random.default_rng(1))
    walk = make_walk()
    assert run(world, walk, max_s=4.0, abort_on_fall=True).end == "timeout"
    assert walk.state == "walking"
    walk.stop()
    x_stop = world.torso_pos_m()[0]
    outcome = run(world, walk, max_s=6.0, reset=False, abort_on_fall=True)
    assert outcome.end == "done" and walk.state == "standing"
    assert world.upright()
    obs = world.observe()
    assert np.abs(obs.joint_speeds_rad_s).max() < 0.5
    assert np.abs(obs.joint_angles_rad - T1.stand_pose()).max() < math.radians(8)
    assert world.torso_pos_m()[0] - x_stop < 2.0  # it stops within a few steps
    x_rest = world.torso_pos_m()[0]
    run(world, walk, max_s=1.0, reset=False, stop_when_done=False)  # and stays put
    assert abs(world.torso_pos_m()[0] - x_rest) < 0.02 and world.upright()


def test_kick_moves_the_ball_and_the_robot_stays_up(world):
    r = kick_from_stand(make_kick, seed=0, world=world, pose_noise_rad=0.02)
    assert r.distance_m >= KICK_DISTANCE_M
    assert abs(r.lateral_m) < 0.5 * r.distance_m
    assert r.standing


def test_the_team_process_walks_and_stops_on_a_hosted_server(capsys):
    from mimic.team.other_team_t1 import main

    assert main(["--walk-s", "2.5", "--team", "Others", "--player", "4"]) == 0
    assert "Others #4: done" in capsys.readouterr().out


@pytest.mark.slow
def test_walk_10_m_in_10_seeds_without_a_fall(world):
    results = [
        straight_walk(
            make_walk,
            distance_m=10.0,
            seed=seed,
            world=world,
            pose_noise_rad=POSE_NOISE_RAD,
            max_time_s=40.0,
        )
        for seed in range(10)
    ]
    assert not any(r.fell for r in results)
    assert min(r.speed_m_s for r in results) >= WALK_SPEED_M_S
    assert max(r.max_drift_m for r in results) < WALK_DRIFT_M


@pytest.mark.slow
def test_walk_10_m_in_the_league_without_a_fall():
    from mimic.world.league_server import LeagueWorld, LeagueWorldConfig

    with LeagueWorld("t1", config=LeagueWorldConfig(team="Others", player=2)) as league:
        results = [
            straight_walk(
                make_walk,
                distance_m=10.0,
                seed=seed,
                world=league,
                pose_noise_rad=POSE_NOISE_RAD,
                max_time_s=40.0,
            )
            for seed in range(3)
        ]
    assert not any(r.fell for r in results)
    assert min(r.speed_m_s for r in results) >= WALK_SPEED_M_S


@pytest.mark.slow
def test_kick_in_10_seeds(world):
    results = [
        kick_from_stand(make_kick, seed=seed, world=world, pose_noise_rad=0.02)
        for seed in range(10)
    ]
    assert all(r.standing for r in results)
    assert min(r.distance_m for r in results) >= KICK_DISTANCE_M
