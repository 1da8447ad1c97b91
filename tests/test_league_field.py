"""The league's field and ball, read from RCSSServerMJ, in our MuJoCo world for league robots."""

import xml.etree.ElementTree as ET

import numpy as np
import pytest

from mimic.league.field import league_air, league_world_xml
from mimic.robot.actuators import JointCommand
from mimic.world.base import CYCLE_S
from mimic.world.field import NAO_FIELD, field_for_robot
from mimic.world.league_field import league_field
from mimic.world.mujoco_world import MujocoWorld
from mimic.world.scene import scene_xml

pytest.importorskip("rcsssmj")


def _league_xml_ball():
    root = ET.parse(league_world_xml()).getroot()
    return root.find(".//geom[@name='ball']"), root.find("option")


def test_league_ball_is_the_servers_ball():
    ball_xml, option_xml = _league_xml_ball()
    field = league_field()
    assert field.ball_radius_m == float(ball_xml.get("size"))
    assert field.ball_mass_kg == float(ball_xml.get("mass"))
    contact = field.ball_contact
    assert contact.friction == tuple(float(v) for v in ball_xml.get("friction").split())
    assert contact.solref == tuple(float(v) for v in ball_xml.get("solref").split())
    assert contact.condim == int(ball_xml.get("condim"))
    assert contact.priority == int(ball_xml.get("priority"))
    air = league_air()
    assert air.timestep_s == float(option_xml.get("timestep"))
    assert air.density_kg_m3 == float(option_xml.get("density"))
    assert air.viscosity_pa_s == float(option_xml.get("viscosity"))


def test_league_field_is_the_servers_default_field():
    from rcsssmj.games.soccer.soccer_fields import create_soccer_field
    from rcsssmj.games.soccer.soccer_rules import SoccerRuleBooks, create_soccer_rule_book

    rules = create_soccer_rule_book(SoccerRuleBooks.SSIM.value)
    server = create_soccer_field(rules.default_field_version.value)
    field = league_field()
    assert (field.length_m, field.width_m) == server.field_dim[:2]
    assert (field.goal_depth_m, field.goal_width_m, field.goal_height_m) == server.goal_dim
    assert field.centre_circle_radius_m == server.center_circle_radius


def test_league_robots_play_on_the_league_field_and_the_nao_on_its_own():
    assert field_for_robot("league") == league_field()
    assert field_for_robot("nao") is NAO_FIELD
    assert MujocoWorld().field is NAO_FIELD
    world = MujocoWorld("t1")
    assert world.field == league_field()
    m = world.model
    ball = m.geom("ball")
    contact = league_field().ball_contact
    assert ball.size[0] == pytest.approx(0.11) and m.body("ball").mass[0] == pytest.approx(0.41)
    assert tuple(ball.friction) == pytest.approx(contact.friction)
    assert tuple(ball.solref) == pytest.approx(contact.solref)
    assert ball.condim[0] == contact.condim and ball.priority[0] == contact.priority
    assert m.opt.density == pytest.approx(1.2) and m.opt.viscosity == pytest.approx(2e-5)
    # Goals on the league field's goal lines.
    assert m.geom("ground").size[0] == pytest.approx(league_field().length_m / 2 + 2)


def test_nao_scene_keeps_its_ball_and_no_air():
    xml = scene_xml()
    assert 'size="0.042" mass="0.026"' in xml
    assert "density=" not in xml and "priority=" not in xml


def test_league_ball_rolls_to_a_stop():
    # On the league's stiff ball contact the resting ball keeps bouncing a few cm/s up and
    # down: rest means no speed along the ground.
    world = MujocoWorld("t1")
    world.reset()
    world.place_robot(-5.0, 5.0, 0.0, world.robot.stand_pose())
    world.place_ball(0.0, 0.0)
    v = world.model.jnt_dofadr[world.model.joint("ball").id]
    world.data.qvel[v] = 2.0
    world.data.qvel[v + 4] = 2.0 / world.field.ball_radius_m  # rolling, not sliding
    hold = JointCommand.references(world.robot.stand_pose())

    def ground_speed():
        return float(np.hypot(*world.data.qvel[v : v + 2]))

    for _ in range(int(8 / CYCLE_S)):
        world.step(hold)
        if ground_speed() < 0.005:
            break
    assert ground_speed() < 0.005
    assert 1.5 < world.ball_pos_m()[0] < 6.0
