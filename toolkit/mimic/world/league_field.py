"""The league's field and ball as a ``Field``, read from the installed RCSSServerMJ (``rcsssmj``).

Nothing here is a number of ours: the field is the one the server plays on by default (its
default rule book's field version, ``soccer_fields.py``), the ball and the pitch come from its
soccer world (``league.field``, which also reads its step and air). Our MuJoCo world uses
them for league robots, so motions authored there meet the league's ball: radius, mass,
friction, solver reference and contact dimensionality.
"""

from __future__ import annotations

from functools import cache

from mimic.league.field import league_world_spec
from mimic.world.field import Contact, Field

__all__ = ["league_field"]


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
    spec = league_world_spec()
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
