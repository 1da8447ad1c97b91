"""A learned policy's action jitter in the T1's policy-like walk (``PolicyWalkParams.action_noise_*``,
``other-team-jittery-walk``).

The walk is fed the same made-up observations (standing, upright) with and without jitter:
its own references do not depend on the jitter (the jitter has a stream of its own), so the
difference of the two is the jitter itself, and its statistics can be checked exactly.
"""

from dataclasses import replace

import numpy as np
import pytest

from mimic.agents.other_team_t1 import (
    OtherTeamT1PolicyWalk,
    PolicyWalkParams,
    WalkParams,
    make_jittery_walk,
    make_policy_walk,
)
from mimic.agents.other_team_t1.params import JITTERY_WALK
from mimic.robot.registry import get_robot
from mimic.world.base import Observation

ROBOT = get_robot("t1")
CYCLES = 1500


def _obs(time_s: float, q: np.ndarray) -> Observation:
    n = ROBOT.num_joints
    return Observation(
        time_s, q, np.zeros(n), np.zeros(3), np.zeros(3), np.array([1.0, 0, 0, 0]),
        np.zeros(2), np.array([-4.0, 0.0, 0.68]), np.zeros(3),
    )  # fmt: skip


def _references(agent, cycles: int = CYCLES, q0: np.ndarray | None = None) -> np.ndarray:
    """(cycles, N) the agent's references over the same made-up standing observations."""
    q = ROBOT.stand_pose() if q0 is None else q0
    agent.reset(_obs(0.0, q))
    return np.array([agent.act(_obs(0.02 * (k + 1), q)).reference_rad for k in range(cycles)])


def _walk(**noise) -> OtherTeamT1PolicyWalk:
    return OtherTeamT1PolicyWalk(WalkParams(), replace(PolicyWalkParams(), **noise))


def test_default_draws_no_jitter_and_leaves_the_walk_as_it_was():
    """Off by default: no draw from the jitter's stream, the references those of the walk
    with the jitter's other settings changed (which then do nothing)."""
    plain = make_policy_walk()
    assert plain.command.action_noise_rad == 0.0
    stand = ROBOT.stand_pose()
    plain.reset(_obs(0.0, stand))
    untouched = plain._action_rng.bit_generator.state
    for k in range(300):
        plain.act(_obs(0.02 * (k + 1), stand))
    assert plain._action_rng.bit_generator.state == untouched
    q = _references(plain, 300)
    other = _references(_walk(action_noise_keep=0.9, action_noise_arm_share=0.3), 300)
    np.testing.assert_array_equal(q, other)


def test_the_jitter_is_an_ar1_of_the_given_sd_and_carry_over_per_joint():
    sd, keep, arms, legs = 0.02, 0.6, 0.5, 0.25
    plain = _references(_walk(), CYCLES)
    jittery = _references(
        _walk(
            action_noise_rad=sd,
            action_noise_keep=keep,
            action_noise_arm_share=arms,
            action_noise_leg_share=legs,
        )
    )
    noise = jittery - plain  # the steering and timing draws are the same: a stream apart
    share = np.ones(ROBOT.num_joints)
    for i, name in enumerate(ROBOT.joint_names):
        if "Shoulder" in name or "Elbow" in name:
            share[i] = arms
        elif "Hip" in name or "Knee" in name or "Ankle" in name or name == "Waist":
            share[i] = legs
    assert set(share) == {1.0, arms, legs}
    scaled = noise / (sd * share)
    # Stationary from the first cycle: sd 1 on every joint, 0.6 of it kept cycle to cycle.
    assert scaled.std() == pytest.approx(1.0, rel=0.05)
    assert np.abs(scaled.mean()) < 0.05
    per_joint = scaled.std(axis=0)
    assert per_joint.min() > 0.8 and per_joint.max() < 1.2
    assert np.abs(scaled[:50]).std() == pytest.approx(np.abs(scaled).std(), rel=0.3)
    lag1 = np.mean(scaled[1:] * scaled[:-1]) / np.mean(scaled * scaled)
    assert lag1 == pytest.approx(keep, abs=0.03)
    # Independent joints.
    corr = np.corrcoef(scaled.T)
    assert np.abs(corr[np.triu_indices_from(corr, 1)]).max() < 0.2


def test_the_jitter_is_seeded_by_the_walks_seed_and_first_observation():
    noisy = dict(action_noise_rad=0.02, action_noise_keep=0.5)
    a = _references(_walk(**noisy), 100)
    np.testing.assert_array_equal(a, _references(_walk(**noisy), 100))
    assert not np.array_equal(a, _references(_walk(**noisy, seed=1), 100))
    q0 = ROBOT.stand_pose()
    q0[0] += 0.01  # another first observation: another episode's draws
    b, b_plain = _references(_walk(**noisy), 100, q0), _references(_walk(), 100, q0)
    assert not np.allclose(b - b_plain, a - _references(_walk(), 100))


def test_jitter_settings_are_checked():
    for bad in (
        dict(action_noise_rad=-0.1),
        dict(action_noise_keep=1.0),
        dict(action_noise_keep=-0.1),
        dict(action_noise_leg_share=-1.0),
    ):
        with pytest.raises(ValueError):
            PolicyWalkParams(**bad)


def test_the_jittery_walk_is_an_agent_by_name_and_takes_a_speed():
    from mimic.agents.registry import agent_spec

    agent = agent_spec("other-team-jittery-walk", robot="t1", speed_m_s=0.3).build()
    assert isinstance(agent, OtherTeamT1PolicyWalk)
    assert agent.command == replace(JITTERY_WALK, speed_m_s=0.3)
    assert make_jittery_walk().command.action_noise_rad > 0
