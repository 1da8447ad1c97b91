"""A fallen robot gets up with the get-up motions and walks on (the trials rely on it)."""

import numpy as np
import pytest

from mimic.agents.walk import make_walk_agent
from mimic.episode import Episode
from mimic.robot.nao import nao
from mimic.world.mujoco_world import MujocoWorld


@pytest.mark.parametrize("side", ["front", "back"])
def test_fallen_robot_gets_up_and_walks_on(side):
    world = MujocoWorld()
    world.reset()
    world.place_robot(-10.0, 0.0, 0.3, nao().stand_pose(), posture=f"lying_{side}")
    world.place_ball(0.0, 5.0)
    episode = Episode(world)
    falls = episode.falls
    assert falls.update(world), "lying counts as fallen"
    assert world.lying_side() == side
    assert episode.get_up()
    assert falls.getups == 1 and world.upright()
    start = world.torso_pos_m()
    outcome = episode.run(make_walk_agent(), max_s=6.0)
    assert outcome == "timeout", f"the walk ended with {outcome!r}"
    assert falls.falls == 1, "no fall after the get-up"
    walked = np.linalg.norm(world.torso_pos_m()[:2] - start[:2])
    assert walked > 1.5, f"walked only {walked:.2f} m in 6 s"
