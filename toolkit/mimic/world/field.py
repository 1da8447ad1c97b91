"""Field, goal and ball dimensions: the one place that knows them.

Field frame: origin at the centre spot, x toward the opponent goal, y to the left, z up [m].
"""

from __future__ import annotations

__all__ = [
    "FIELD_LENGTH_M", "FIELD_WIDTH_M", "GOAL_WIDTH_M", "GOAL_HEIGHT_M", "GOAL_DEPTH_M",
    "PENALTY_DEPTH_M", "PENALTY_WIDTH_M", "CENTRE_CIRCLE_RADIUS_M", "LINE_WIDTH_M",
    "BALL_RADIUS_M", "BALL_MASS_KG", "OPPONENT_GOAL_X_M", "OWN_GOAL_X_M",
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
