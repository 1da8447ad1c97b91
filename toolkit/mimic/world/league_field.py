"""The league's field, ball and air, read from the installed RCSSServerMJ (``rcsssmj``).

Nothing here is a number of ours: the field is the one the server plays on by default (its
default rule book's field version, ``soccer_fields.py``), the ball, the pitch and the
physics options come from its soccer world (``resources/environments/soccer/world.xml``).
Our MuJoCo world uses them for league robots, so motions authored there meet the league's
ball: radius, mass, friction, solver reference and contact dimensionality, and the air it
rolls through (the world's density and viscosity drag a 0.11 m ball noticeably).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from importlib import resources
from pathlib import Path

import mujoco

from mimic.errors import MimicError
from mimic.world.field import Contact, Field

__all__ = ["league_field", "league_air", "LeagueAir", "league_world_xml"]


@dataclass(frozen=True)
class LeagueAir:
    """The league world's physics options that act on everything.

    Attributes:
        timestep_s: its physics step [s].
        density_kg_m3: air density (MuJoCo's fluid forces) [kg/m^3].
        viscosity_pa_s: air viscosity [Pa s].
    """

    timestep_s: float
    density_kg_m3: float
    viscosity_pa_s: float


def league_world_xml() -> Path:
    """The soccer world MJCF of the installed league server."""
    try:
        package = resources.files("rcsssmj")
    except ModuleNotFoundError:
        raise MimicError(
            "the league field comes with the league simulator: pip install rcsssmj"
        ) from None
    path = Path(str(package / "resources" / "environments" / "soccer" / "world.xml"))
    if not path.is_file():
        raise MimicError(f"rcsssmj has no {path}; pip install --upgrade rcsssmj")
    return path


@cache
def _world_spec() -> mujoco.MjSpec:
    return mujoco.MjSpec.from_file(str(league_world_xml()))


def _contact(geom) -> Contact:
    return Contact(
        friction=tuple(float(f) for f in geom.friction),
        condim=int(geom.condim),
        solref=tuple(float(r) for r in geom.solref),
        priority=int(geom.priority),
    )


@cache
def league_field() -> Field:
    """The field, goals and ball the league server plays with by default."""
    from rcsssmj.games.soccer.soccer_fields import create_soccer_field
    from rcsssmj.games.soccer.soccer_rules import SoccerRuleBooks, create_soccer_rule_book

    # The server's default: ``python -m rcsssmj`` without --rules / --field.
    rules = create_soccer_rule_book(SoccerRuleBooks.SSIM.value)
    field = create_soccer_field(rules.default_field_version.value)
    spec = _world_spec()
    ball, pitch = spec.geom("ball"), spec.geom("pitch")
    length, width, _ = field.field_dim
    goal_depth, goal_width, goal_height = field.goal_dim
    penalty_depth, penalty_width = field.penalty_area_dim or field.goalie_area_dim
    return Field(
        length_m=float(length),
        width_m=float(width),
        goal_width_m=float(goal_width),
        goal_height_m=float(goal_height),
        goal_depth_m=float(goal_depth),
        ball_radius_m=float(ball.size[0]),
        ball_mass_kg=float(ball.mass),
        penalty_depth_m=float(penalty_depth),
        penalty_width_m=float(penalty_width),
        centre_circle_radius_m=float(field.center_circle_radius),
        line_width_m=float(field.line_width),
        goal_post_radius_m=float(field.goal_post_radius),
        ball_contact=_contact(ball),
        ground_contact=_contact(pitch),
    )


@cache
def league_air() -> LeagueAir:
    """The league world's step and air."""
    opt = _world_spec().option
    return LeagueAir(float(opt.timestep), float(opt.density), float(opt.viscosity))
