"""Compensated references reproduce observed trajectories through the P speed controller."""

import numpy as np

from mimic.learn.compensate import CompensationConfig, compensate_references, simulate_tracking


def _sine(freq_hz, amp, n=150, joints=3):
    t = np.arange(n) * 0.02
    ref = amp * np.sin(2 * np.pi * freq_hz * t[:, None] + np.arange(joints))
    return t, ref


def test_unsaturated_compensation_recovers_the_reference():
    t, ref = _sine(0.8, 0.3)
    q = simulate_tracking(t, ref, ref[0])
    assert np.abs(q - ref).max() > 0.05          # tracking really attenuates/lags
    rec = compensate_references(t, q)
    np.testing.assert_allclose(rec[:-1], ref[:-1], atol=0.01)
    replay = simulate_tracking(t, rec, q[0])
    np.testing.assert_allclose(replay, q, atol=1e-9)


def test_saturated_segments_keep_the_speed_cap():
    cfg = CompensationConfig()
    t, ref = _sine(2.0, 1.0)                      # peak demand ~12.6 rad/s > 6.14 cap
    q = simulate_tracking(t, ref, ref[0])
    speed = np.diff(q, axis=0) / 0.02
    sat = np.abs(speed) >= cfg.max_speed_rad_s * 0.999
    assert sat.any()
    rec = compensate_references(t, q)
    lead = rec[:-1] - q[:-1]
    bound = cfg.max_speed_rad_s / cfg.gain_per_s
    assert np.all(np.abs(lead[sat]) >= bound - 1e-9)
    assert np.all(np.sign(lead[sat]) == np.sign(speed[sat]))
    replay = simulate_tracking(t, rec, q[0])
    # Samples within saturation_tol (2 %) of the cap are pushed to the cap: tiny deviations.
    np.testing.assert_allclose(replay, q, atol=1e-3)
    unsat = ~sat
    unsat[1:] &= ~sat[:-1]                        # away from segment edges
    np.testing.assert_allclose(rec[:-1][unsat], q[:-1][unsat] + speed[unsat] / cfg.gain_per_s,
                               atol=1e-12)


def test_references_are_clipped_to_limits_plus_margin():
    from mimic.robot.joints import lower_limits_rad, upper_limits_rad

    t = np.arange(10) * 0.02
    q = np.tile(upper_limits_rad(), (10, 1)) + np.linspace(0, 0.5, 10)[:, None]
    cfg = CompensationConfig(limit_margin_rad=0.1)
    rec = compensate_references(t, q, cfg)
    assert np.all(rec <= upper_limits_rad() + 0.1 + 1e-12)
    assert np.all(rec >= lower_limits_rad() - 0.1 - 1e-12)
