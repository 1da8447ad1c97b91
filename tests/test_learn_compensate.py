"""Compensated references reproduce observed trajectories through the robot's speed servos."""

import numpy as np
import pytest

from mimic.errors import MimicError
from mimic.learn.compensate import (
    CompensationConfig,
    compensate_references,
    references_from_angles,
    simulate_tracking,
    speed_servos,
)
from mimic.robot.registry import get_robot

NAO = get_robot("nao")
SERVOS = speed_servos(NAO)


def _sine(freq_hz, amp, n=150, joints=3):
    t = np.arange(n) * 0.02
    ref = amp * np.sin(2 * np.pi * freq_hz * t[:, None] + np.arange(joints))
    return t, ref


def test_gain_and_cap_are_the_robots_servos():
    assert SERVOS is NAO.actuator
    assert SERVOS.max_speed_rad_s == pytest.approx(6.1395)
    assert SERVOS.tracking_gain_per_s == pytest.approx(25.0)


def test_unsaturated_compensation_recovers_the_reference():
    t, ref = _sine(0.8, 0.3)
    q = simulate_tracking(t, ref, ref[0], SERVOS)
    assert np.abs(q - ref).max() > 0.05  # tracking really attenuates/lags
    rec = references_from_angles(t, q, SERVOS)
    np.testing.assert_allclose(rec[:-1], ref[:-1], atol=0.01)
    replay = simulate_tracking(t, rec, q[0], SERVOS)
    np.testing.assert_allclose(replay, q, atol=1e-9)


def test_saturated_segments_keep_the_speed_cap():
    t, ref = _sine(2.0, 1.0)  # peak demand ~12.6 rad/s > 6.14 cap
    q = simulate_tracking(t, ref, ref[0], SERVOS)
    speed = np.diff(q, axis=0) / 0.02
    sat = np.abs(speed) >= SERVOS.max_speed_rad_s * 0.999
    assert sat.any()
    rec = references_from_angles(t, q, SERVOS)
    lead = rec[:-1] - q[:-1]
    bound = SERVOS.max_speed_rad_s / SERVOS.tracking_gain_per_s
    assert np.all(np.abs(lead[sat]) >= bound - 1e-9)
    assert np.all(np.sign(lead[sat]) == np.sign(speed[sat]))
    replay = simulate_tracking(t, rec, q[0], SERVOS)
    # Samples within saturation_tol (2 %) of the cap are pushed to the cap: tiny deviations.
    np.testing.assert_allclose(replay, q, atol=1e-3)
    unsat = ~sat
    unsat[1:] &= ~sat[:-1]  # away from segment edges
    np.testing.assert_allclose(
        rec[:-1][unsat], q[:-1][unsat] + speed[unsat] / SERVOS.tracking_gain_per_s, atol=1e-12
    )


def test_references_are_clipped_to_limits_plus_margin():
    t = np.arange(10) * 0.02
    q = np.tile(NAO.upper_limits_rad, (10, 1)) + np.linspace(0, 0.5, 10)[:, None]
    cfg = CompensationConfig(limit_margin_rad=0.1)
    rec = compensate_references(t, q, "nao", cfg)
    assert np.all(rec <= NAO.upper_limits_rad + 0.1 + 1e-12)
    assert np.all(rec >= NAO.lower_limits_rad - 0.1 - 1e-12)


def test_a_pd_motor_robot_is_refused_in_one_line():
    t1 = get_robot("t1")
    t, q = _sine(0.8, 0.3, n=20, joints=t1.num_joints)
    with pytest.raises(MimicError, match="t1 has PD motors") as err:
        compensate_references(t, q, t1)
    assert "\n" not in str(err.value)


def test_angles_of_another_robot_are_refused():
    t, q = _sine(0.8, 0.3, n=20, joints=NAO.num_joints + 1)
    with pytest.raises(MimicError, match="the nao has 22 joints"):
        compensate_references(t, q, NAO)
