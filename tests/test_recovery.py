"""A fallen robot gets up with the get-up motions and walks on (the trials rely on it)."""

import numpy as np
import pytest

from mimic.agents.walk import make_walk_agent
from mimic.motion.files import stand_pose_rad
from mimic.trials.episode import FallCounter, get_up, lying_side, run_until
from mimic.world.world import World


@pytest.mark.parametrize("side", ["front", "back"])
def test_fallen_robot_gets_up_and_walks_on(side):
    world = World()
    world.reset()
    world.beam(-10.0, 0.0, 0.3, stand_pose_rad(), lying=side)
    world.place_ball(0.0, 5.0)
    falls = FallCounter()
    assert falls.update(world), "lying counts as fallen"
    assert lying_side(world) == side
    assert get_up(world, falls)
    assert falls.getups == 1 and world.upright()
    start = world.torso_pos_m()
    outcome = run_until(world, make_walk_agent(), max_s=6.0, falls=falls)
    assert outcome == "timeout", f"the walk ended with {outcome!r}"
    assert falls.falls == 1, "no fall after the get-up"
    walked = np.linalg.norm(world.torso_pos_m()[:2] - start[:2])
    assert walked > 1.5, f"walked only {walked:.2f} m in 6 s"
