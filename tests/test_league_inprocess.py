"""``LeagueInProcessWorld``: rcsssmj's soccer simulation stepped in mimic's process, checked
against the real thing, a hosted server, on the same seeded episodes.

Every perception the player gets is the server's, bit for bit. The true state (the ball's and
the joints' qpos at every monitor frame, written by a monitor inside the server,
``league_truth_server.py``) agrees to about 1e-13 m and 1e-14 rad over 3 s (measured
2026-12: kick, ball 3e-13 m, joints 1e-14 rad; walk, joints 1e-14 rad), which is how far two
runs on fresh servers differ from each other too: a server runs its simulation freely until
the player joins, so the ball lies in another phase of its jitter on the ground (a few 1e-4
m) when it is placed, and MuJoCo's warm start carries that into the last bits of the next
solves. The tests allow 1e-9. What each world shows of the ball differs more: here its qpos,
there the monitor stream's view (``xpos``, one physics step old, every second cycle, to 4
decimals, moved only once it moved more than 5 mm).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from _league_helpers import truth_server_config
from rcsssmj.games.soccer.sim.soccer_referee import SoccerReferee
from typer.testing import CliRunner

from mimic.agents.registry import agent_spec
from mimic.cli.main import app
from mimic.episode import Scene
from mimic.episode.scene import SETTLE_S
from mimic.league.client import format_command, parse_perception, wire_targets_rad
from mimic.league.names import wire_names
from mimic.robot.actuators import JointCommand
from mimic.robot.registry import get_robot
from mimic.world import league_simulation
from mimic.world.base import CYCLE_S
from mimic.world.league_inprocess import LeagueInProcessWorld
from mimic.world.league_server import LeagueWorld
from mimic.world.registry import (
    LEAGUE,
    LEAGUE_SERVER,
    check_world,
    default_robot,
    open_world,
    world_kind,
)

T1 = get_robot("t1")


def _perceived(world) -> np.ndarray:
    """Everything the player perceives this cycle, and the world's clock, as one vector."""
    p = world.perception()
    return np.concatenate(
        [
            [world.time_s],
            p.joint_angles_rad,
            p.joint_speeds_rad_s,
            p.gyro_rad_s,
            p.accelerometer_m_s2,
            p.torso_quat_wxyz,
            p.torso_pos_m,
        ]
    )


def _true_state(world: LeagueInProcessWorld) -> np.ndarray:
    """The ball's qpos (7) and every hinge's qpos in the robot's joint order."""
    m, d = world.simulation.mj_model, world.simulation.mj_data
    prefix = "r-0-1-"
    ball = m.joint("ball-root").qposadr[0]
    joints = [m.joint(prefix + name).qposadr[0] for name in T1.joint_names]
    return np.concatenate([d.qpos[ball : ball + 7], d.qpos[joints]])


def _play(world, behaviour: str, scene: Scene, seconds: float, seed: int):
    """Set up ``scene``, then play ``behaviour`` for ``seconds``: (perceptions per cycle, the
    ball as the world shows it at the start and the end, true states by cycle (in-process))."""
    spec = agent_spec(behaviour, robot="t1")
    scene.setup(world, np.random.default_rng(seed))
    agent = spec.build()
    agent.check_robot(world.robot)
    agent.reset(world.observe())
    seen, truth = [], {}
    ball_start = world.ball_pos_m()
    for _ in range(round(seconds / CYCLE_S)):
        obs = world.observe()
        seen.append(_perceived(world))
        if isinstance(world, LeagueInProcessWorld):
            truth[round(world.time_s / CYCLE_S)] = _true_state(world)
        world.step(agent.act(obs))
    return np.array(seen), (ball_start, world.ball_pos_m()), truth


def _server_truth(path, world: LeagueWorld) -> dict[int, np.ndarray]:
    """The server's true states by cycle since the world's reset (``league_truth_server``)."""
    import json

    origin = round((world.server_time_s - world.time_s) / CYCLE_S)
    out = {}
    for line in path.read_text().splitlines():
        entry = json.loads(line)
        robot = entry["players"].get(f"{world.team} {world.player}")
        if robot is None:
            continue
        joints = [robot["qpos"][name] for name in T1.joint_names]
        out[round(entry["t"] / CYCLE_S) - origin] = np.array([*entry["ball"], *joints])
    return out


def _both(tmp_path, behaviour: str, scene: Scene, seconds: float, seed: int):
    truth_file = tmp_path / "truth.jsonl"
    with LeagueInProcessWorld("t1") as world:
        inproc = _play(world, behaviour, scene, seconds, seed)
    with LeagueWorld("t1", server_config=truth_server_config(truth_file)) as world:
        served = _play(world, behaviour, scene, seconds, seed)
        server_truth = _server_truth(truth_file, world)
    return inproc, served, server_truth


def _assert_the_same(inproc, served, server_truth) -> list[int]:
    np.testing.assert_array_equal(inproc[0], served[0])  # every perception, bit for bit
    frames = sorted(set(inproc[2]) & set(server_truth))
    assert len(frames) >= len(inproc[2]) // 2 - 1  # the server's truth at every second cycle
    for cycle in frames:  # the true state: as close as two fresh servers are (see above)
        np.testing.assert_allclose(
            inproc[2][cycle], server_truth[cycle], rtol=0, atol=1e-9, err_msg=f"cycle {cycle}"
        )
    return frames


def test_a_t1_kick_from_a_stand_plays_as_on_a_hosted_server(tmp_path):
    kick = agent_spec("kick_right", robot="t1")
    offset = kick.ball_offset_m()
    scene = Scene(
        robot_xy_m=(-offset[0], -offset[1]),
        ball_offset_m=tuple(offset),
        ball_after_settle=True,
        settle_s=0.5,
        settle_into_stand=True,
    )
    inproc, served, server_truth = _both(tmp_path, "kick_right", scene, 3.0, seed=3)
    frames = _assert_the_same(inproc, served, server_truth)
    # The kick took the ball metres away, in both worlds the same path (its true position).
    ball = {c: server_truth[c][:3] for c in frames}
    assert ball[frames[-1]][0] - ball[frames[0]][0] > 1.5
    # What each world shows of the ball: the truth here, the monitor's view there.
    (start_in, end_in), (start_sv, end_sv) = inproc[1], served[1]
    np.testing.assert_allclose(start_in, start_sv, atol=1e-4)  # at rest, placed: the same
    assert np.linalg.norm((end_in - start_in) - (end_sv - start_sv)) < 0.2  # rolling: a frame


def test_a_short_t1_walk_plays_as_on_a_hosted_server(tmp_path):
    scene = Scene(robot_xy_m=(-5.0, 0.0), settle_s=SETTLE_S, settle_into_stand=True)
    inproc, served, server_truth = _both(tmp_path, "other-team-walk", scene, 3.0, seed=5)
    _assert_the_same(inproc, served, server_truth)
    torso_x = inproc[0][:, -3]
    assert torso_x[-1] - torso_x[0] > 0.3 and inproc[0][-1, -1] > 0.5  # walked, upright


# --- pieces ---------------------------------------------------------------------------------


def test_perceptions_are_the_ones_rcsssmj_sends():
    """What the world reads from MjData equals rcsssmj's own perceptions, encoded as the server
    sends them and parsed as the client does, at every cycle of a placement and a motion."""
    from rcsssmj.server.perception_encoder import DefaultPerceptionEncoder

    encoder, names = DefaultPerceptionEncoder(), wire_names(T1)
    with LeagueInProcessWorld("t1") as world:
        sim = world.simulation
        world.place_robot(1.0, 2.0, 0.5, T1.stand_pose())
        bent = T1.stand_pose().copy()
        bent[T1.joint_index("Left_Knee_Pitch")] += 0.7
        for k in range(40):
            world.step(JointCommand.references(bent if k % 10 < 5 else T1.stand_pose()))
            sim.generate_perceptions(gen_vision=False)
            sent = encoder.encode(sim.get_players(0)[1].perceptions)
            theirs, ours = parse_perception(sent, T1, names), world.perception()
            for field in ("joint_angles_rad", "joint_speeds_rad_s", "gyro_rad_s"):
                np.testing.assert_array_equal(getattr(ours, field), getattr(theirs, field))
            for field in ("accelerometer_m_s2", "torso_quat_wxyz", "torso_pos_m"):
                np.testing.assert_array_equal(getattr(ours, field), getattr(theirs, field))
            assert (ours.time_s, ours.play_mode) == (theirs.time_s, theirs.play_mode)


def test_targets_are_the_numbers_the_server_reads_from_the_text():
    names = wire_names(T1)
    rng = np.random.default_rng(0)
    ties = np.radians([0.03125, -0.03125, 1.00005, 12.34565, 180.0, -0.00001])
    for targets in [*rng.uniform(-3, 3, (200, T1.num_joints)), np.resize(ties, T1.num_joints)]:
        text = format_command(JointCommand.references(targets), T1, names).decode()
        sent = [math.radians(float(item.split()[1])) for item in text[1:-1].split(")(")]
        assert wire_targets_rad(targets).tolist() == sent


def test_a_command_acts_one_cycle_later_as_on_the_server():
    with LeagueInProcessWorld("t1") as world:
        world.reset()
        world.place_robot(0.0, 0.0, 0.0, T1.stand_pose())
        for _ in range(50):  # put down with straight joints: into the stand first
            world.step(JointCommand.references(T1.stand_pose()))
        knee = T1.joint_index("Left_Knee_Pitch")
        bent = T1.stand_pose().copy()
        bent[knee] += 0.5
        before = world.joint_angles_rad()[knee]
        world.step(JointCommand.references(bent))  # the cycle before's command acts
        assert abs(world.joint_angles_rad()[knee] - before) < 0.01
        world.step(JointCommand.references(bent))  # now this one
        assert world.joint_angles_rad()[knee] - before > 0.05
        assert world.command_delay_cycles == 1


@pytest.mark.parametrize("posture,side", [("lying_front", "front"), ("lying_back", "back")])
def test_the_robot_can_be_put_down_lying(posture, side):
    with LeagueInProcessWorld("t1") as world:
        world.reset()
        world.place_robot(2.0, -1.0, 0.3, posture=posture)
        for _ in range(25):
            world.step(JointCommand.references(T1.zeros()))
        assert world.fallen() and world.lying_side() == side
        assert np.hypot(*(world.torso_pos_m()[:2] - (2.0, -1.0))) < 0.3
        poses = world.body_poses()
        torso = poses.names.index(T1.root_link)
        np.testing.assert_allclose(poses.pos_m[torso], world.torso_pos_m(), atol=0.01)


def test_a_robot_put_where_it_stands_is_turned_once_the_placement_returns():
    # The position alone cannot tell a placement there from none: it used to return before
    # the server carried it out, and the robot turned in whatever ran next.
    with LeagueInProcessWorld("t1") as world:
        world.reset()
        stand = T1.stand_pose()
        world.place_robot(-4.0, 0.0, math.radians(40), stand)
        assert world.torso_yaw_rad() == pytest.approx(math.radians(40), abs=0.01)
        world.place_robot(-4.0, 0.0, math.radians(-70), stand)
        assert world.torso_yaw_rad() == pytest.approx(math.radians(-70), abs=0.01)


def test_a_placed_ball_lies_where_it_was_put_and_the_referee_returns_one_over_a_line():
    with LeagueInProcessWorld("t1") as world:
        world.reset()
        world.place_robot(0.0, 0.0, 0.0, T1.stand_pose())
        world.place_ball(1.0, 0.5)
        np.testing.assert_allclose(world.ball_pos_m(), (1.0, 0.5, 0.11))  # placed next cycle
        for _ in range(10):
            world.step(JointCommand.references(T1.stand_pose()))
        np.testing.assert_allclose(world.ball_pos_m()[:2], (1.0, 0.5), atol=1e-3)
        assert world.ball_speed_m_s() < 0.01 and world.play_mode() == "BeforeKickOff"
        beyond = world.field.width_m / 2 + 0.5
        world.place_ball(3.0, beyond)
        for _ in range(5):
            world.step(JointCommand.references(T1.stand_pose()))
        assert world.play_mode() != "BeforeKickOff"  # a throw-in
        assert abs(world.ball_pos_m()[1]) < beyond - 0.4  # put back on the line


def _referee_story(monkeypatch, referee) -> list:
    """Play modes, ball and torso positions, cycle by cycle, of a ball put over the touch
    line (a throw-in, left to time out) and then into the right goal (a goal, the pause, a
    kick-off, in which our robot on the centre spot is misplaced and moved off the field, left
    to time out), refereed by ``referee``."""
    monkeypatch.setattr(league_simulation, "_Referee", referee)
    story = []
    with LeagueInProcessWorld("t1") as world:
        world.reset()
        # Put down on the centre spot, the robot touches the ball: the referee then knows
        # whose throw-in it is.
        world.place_robot(0.0, 0.0, 0.0, T1.stand_pose())
        hold = JointCommand.references(T1.stand_pose())
        touch_line, goal = (3.0, world.field.width_m / 2 + 0.5), (world.field.length_m / 2 + 0.3, 0)
        for ball_xy, cycles in ((touch_line, 900), (goal, 1000)):
            world.place_ball(*ball_xy)
            for _ in range(cycles):
                world.step(hold)
                story.append(
                    (world.play_mode(), *world.ball_pos_m().tolist(), *world.torso_pos_m().tolist())
                )
    return story


def test_the_referees_shortcuts_referee_as_rcsssmj_does(monkeypatch):
    # league_simulation._Referee skips the timeouts where a play mode has none, the illegal
    # defence where no team can crowd its area, the placement rules outside set plays, the
    # location triggers while the ball is on the field and in no goal, and the contact
    # triggers outside set plays: the same play modes, ball and robot, cycle by cycle, as
    # rcsssmj's referee through a throw-in, a goal and a kick-off, each left to time out
    # (15 s; after a goal 3 s).
    ours = _referee_story(monkeypatch, league_simulation._Referee)
    theirs = _referee_story(monkeypatch, SoccerReferee)
    modes = {mode for mode, *_ in ours}
    assert {"Goal_Left", "KickOff_Right", "PlayOn", "KickIn_Right"} <= modes, modes
    assert max(abs(y) for *_, y, _ in ours[-100:]) > 20  # misplaced at the kick-off
    assert ours == theirs


def test_the_league_world_is_in_process_and_the_server_is_league_server():
    assert world_kind("league") == LEAGUE and world_kind("League-Server") == LEAGUE_SERVER
    assert default_robot(LEAGUE_SERVER) == default_robot(LEAGUE) == "t1"
    with pytest.raises(Exception, match="plays league robots.*--world league-server"):
        check_world(LEAGUE_SERVER, "nao")
    with open_world(LEAGUE, "t1") as world:
        assert isinstance(world, LeagueInProcessWorld) and world.robot.name == "t1"


def test_bench_league_reports_bare_stepping_and_every_world():
    result = CliRunner().invoke(app, ["bench", "league", "--seconds", "0.3"])
    assert result.exit_code == 0, result.output
    rows = {line.split()[0]: line.split() for line in result.output.splitlines()[1:7]}
    assert set(rows) == {"bare", "bare-same", "league", "league-server", "mujoco"}
    assert rows["bare"][-1] == "1.00" and float(rows["league"][-1]) > 0
    # The league world's ratio to MuJoCo taking its own physics steps, on a line of its own.
    same = next(line for line in result.output.splitlines() if line.startswith("league per"))
    assert 0 < float(same.split()[4]) < 1
