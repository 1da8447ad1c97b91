"""Field, goal and ball dimensions: the one place that knows them.

Field frame: origin at the centre spot, x toward the opponent goal, y to the left, z up [m].
The constants are the study's field (SimSpark's); ``Field`` holds a field as data, so a
world can carry its own (``NAO_FIELD`` here, the league's read from RCSSServerMJ in
``world/league_field.py``; ``field_for_robot`` picks a robot's).
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = [
    "Field",
    "Contact",
    "NAO_FIELD",
    "field_for_robot",
    "FIELD_LENGTH_M",
    "FIELD_WIDTH_M",
    "GOAL_WIDTH_M",
    "GOAL_HEIGHT_M",
    "GOAL_DEPTH_M",
    "PENALTY_DEPTH_M",
    "PENALTY_WIDTH_M",
    "CENTRE_CIRCLE_RADIUS_M",
    "LINE_WIDTH_M",
    "BALL_RADIUS_M",
    "BALL_MASS_KG",
    "OPPONENT_GOAL_X_M",
    "OWN_GOAL_X_M",
]

FIELD_LENGTH_M = 30.0
FIELD_WIDTH_M = 20.0
GOAL_WIDTH_M = 2.1
GOAL_HEIGHT_M = 0.8
GOAL_DEPTH_M = 0.6
PENALTY_DEPTH_M = 1.8
PENALTY_WIDTH_M = 3.9
CENTRE_CIRCLE_RADIUS_M = 2.0
LINE_WIDTH_M = 0.05
BALL_RADIUS_M = 0.042
BALL_MASS_KG = 0.026
#: x of the goal line the robot attacks.
OPPONENT_GOAL_X_M = FIELD_LENGTH_M / 2
#: x of the goal line the robot defends.
OWN_GOAL_X_M = -FIELD_LENGTH_M / 2


@dataclass(frozen=True)
class Contact:
    """How a geom touches others, in MuJoCo's terms (its ``geom`` attributes).

    Attributes:
        friction: (sliding, torsional [m], rolling [m]) friction.
        condim: contact dimensionality (3: sliding; 6: also torsional and rolling).
        solref: (2,) solver reference: (time constant [s], damping ratio), or negative
            (-stiffness, -damping).
        priority: the geom with the higher priority sets the contact's parameters.
    """

    friction: tuple[float, float, float]
    condim: int
    solref: tuple[float, float]
    priority: int = 0


@dataclass(frozen=True)
class Field:
    """A soccer field and its ball [m, kg]; goals centred on the x axis at +-length/2.

    ``ball_contact`` and ``ground_contact`` None: our own grass and ball (``PhysicsConfig``).
    """

    length_m: float
    width_m: float
    goal_width_m: float
    goal_height_m: float
    goal_depth_m: float
    ball_radius_m: float
    ball_mass_kg: float
    penalty_depth_m: float = PENALTY_DEPTH_M
    penalty_width_m: float = PENALTY_WIDTH_M
    centre_circle_radius_m: float = CENTRE_CIRCLE_RADIUS_M
    line_width_m: float = LINE_WIDTH_M
    goal_post_radius_m: float = 0.05
    ball_contact: Contact | None = None
    ground_contact: Contact | None = None

    @property
    def opponent_goal_x_m(self) -> float:
        """x of the goal line the robot attacks."""
        return self.length_m / 2

    @property
    def own_goal_x_m(self) -> float:
        """x of the goal line the robot defends."""
        return -self.length_m / 2

    def goal(self, ball_pos_m) -> bool:
        """Ball wholly behind the opponent goal line, between the posts, under the bar."""
        x, y, z = ball_pos_m
        return (
            x > self.opponent_goal_x_m + self.ball_radius_m
            and abs(y) < self.goal_width_m / 2
            and z < self.goal_height_m
        )

    def out(self, ball_pos_m) -> bool:
        """Ball wholly outside the field lines (and not a goal)."""
        x, y, _ = ball_pos_m
        r = self.ball_radius_m
        return (abs(x) > self.length_m / 2 + r or abs(y) > self.width_m / 2 + r) and not self.goal(
            ball_pos_m
        )


#: The study's field (the RoboCup Soccer 3D league's SimSpark field) and ball.
NAO_FIELD = Field(
    FIELD_LENGTH_M,
    FIELD_WIDTH_M,
    GOAL_WIDTH_M,
    GOAL_HEIGHT_M,
    GOAL_DEPTH_M,
    BALL_RADIUS_M,
    BALL_MASS_KG,
)


def field_for_robot(world: str) -> Field:
    """The field a robot plays on by default, from its ``RobotDescription.world``: the
    league's (RCSSServerMJ's field and ball) for ``league``, the study's otherwise."""
    if world == "league":
        from mimic.world.league_field import league_field

        return league_field()
    return NAO_FIELD
