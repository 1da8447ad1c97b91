"""Worlds registered as data (``world/registry.py``): each world's facts come from its
``WorldSpec``, read by name, alias included; what the class says is not said twice."""

import pytest

from mimic.errors import MimicError
from mimic.world.field import NAO_FIELD
from mimic.world.league_field import league_field
from mimic.world.registry import (
    LEAGUE,
    LEAGUE_LIKE,
    LEAGUE_SERVER,
    LEAGUE_WORLDS,
    MUJOCO,
    WORLDS,
    check_world,
    default_robot,
    get_world,
    world_class,
    world_kind,
    world_owns_physics,
)


def test_every_world_is_registered_once_under_its_name():
    assert WORLDS == (MUJOCO, LEAGUE, LEAGUE_SERVER, LEAGUE_LIKE)
    assert [get_world(name).name for name in WORLDS] == list(WORLDS)
    assert get_world("nao") is get_world(MUJOCO) and world_kind("NAO") == MUJOCO
    with pytest.raises(MimicError, match="unknown world 'moon'"):
        get_world("moon")


def test_the_facts_code_used_to_read_from_names():
    ours, league, server, like = (get_world(name) for name in WORLDS)
    assert LEAGUE_WORLDS == (LEAGUE, LEAGUE_SERVER)
    assert [s.league_field for s in (ours, league, server, like)] == [False, True, True, False]
    assert [s.league_referee for s in (ours, league, server, like)] == [False, True, True, False]
    assert [s.owns_physics for s in (ours, league, server, like)] == [True, True, False, True]
    assert [s.command_delay_cycles for s in (ours, league, server, like)] == [0, 1, 1, 1]
    assert [s.default_robot for s in (ours, league, server, like)] == ["nao", "t1", "t1", "t1"]
    assert [s.twin for s in (ours, league, server, like)] == [
        MUJOCO,
        LEAGUE_LIKE,
        LEAGUE_LIKE,
        LEAGUE_LIKE,
    ]
    assert league.robots == server.robots == ("t1", "k1") and "nao" in ours.robots
    assert ours.field() is NAO_FIELD and league.field() == league_field()
    assert ours.title == "our MuJoCo world"
    assert server.title == "league world (RCSSServerMJ server)"


def test_the_class_says_physics_and_delay_the_spec_reads_them():
    for name in WORLDS:
        spec, cls = get_world(name), world_class(name)
        assert spec.world_class is cls
        assert world_owns_physics(name) == cls.can_disturb_physics == spec.owns_physics
        assert spec.command_delay_cycles == cls.command_delay_cycles
        assert default_robot(name) == spec.default_robot


def test_the_league_worlds_play_league_robots_only():
    check_world(MUJOCO, "nao")
    check_world(LEAGUE_LIKE, "t1")
    check_world(LEAGUE, "t1")
    with pytest.raises(MimicError, match=r"league robots \(t1, k1\), not the nao; pass --robot t1"):
        check_world(LEAGUE_SERVER, "nao")
