"""The walk's per-cycle shortcuts give the numbers (or the answers) of what they replace: the
trial tables of every walk must not change with them."""

from __future__ import annotations

import math

import numpy as np

from mimic.agents.walk.engine import WalkEngine
from mimic.agents.walk.gait import (
    StepPlan,
    WalkConfig,
    foot_fractions,
    foot_rows,
    foot_rows_at,
    nominal_foot,
    plan_step,
)
from mimic.agents.walk.goto import _hypot_below, _segment_distance, _segment_distance_below
from mimic.agents.walk.lipm import lateral_fraction, pendulum_rate_per_s, sagittal_fraction


def _plan_step_on_arrays(cfg: WalkConfig, support: int, start, command) -> np.ndarray:
    """``plan_step``'s end feet as first written, on numpy arrays."""
    end = np.empty((2, 4))
    dx, dy, dyaw = np.asarray(command, dtype=float)
    for side in (0, 1):
        s = 1.0 if side == 0 else -1.0
        sign = -0.5 if side == support else 0.5
        bias = np.array([0.0, s * abs(dy) / 2, 0.0, s * abs(dyaw) / 2])
        end[side] = nominal_foot(cfg, side) + sign * np.array([dx, dy, 0.0, dyaw]) + bias
    return end


def _feet_as_first_written(cfg: WalkConfig, plan: StepPlan, phase: float) -> list[list[float]]:
    k = pendulum_rate_per_s(cfg.com_height_m)
    phase = min(max(phase, 0.0), 1.0)
    lipm = sagittal_fraction(phase, k, cfg.step_time_s) + 0.5
    support_f = cfg.lipm_blend * lipm + (1 - cfg.lipm_blend) * phase
    lift = cfg.lift_start_fraction
    swing = min(1.0, max(0.0, phase - lift) / max(cfg.swing_fraction - lift, 1e-6))
    swing_f = 0.5 * (1 - math.cos(math.pi * swing))
    sup, sw = plan.support, 1 - plan.support
    start, end = plan.start.tolist(), plan.end.tolist()
    feet = [[], []]
    feet[sup] = [a + support_f * (b - a) for a, b in zip(start[sup], end[sup])]
    feet[sw] = [a + swing_f * (b - a) for a, b in zip(start[sw], end[sw])]
    feet[sw][2] += cfg.step_height_m * 0.5 * (1 - math.cos(2 * math.pi * swing))
    toward = 1.0 if sup == 0 else -1.0
    sway = (
        1.0 * cfg.sway_gain * cfg.ankle_half_width_m * lateral_fraction(phase, k, cfg.step_time_s)
    )
    for foot in feet:
        foot[1] -= toward * sway
    return feet


def test_step_plans_and_feet_are_the_array_formulas() -> None:
    cfg = WalkConfig()
    rng = np.random.default_rng(12)
    start = np.array([nominal_foot(cfg, 0), nominal_foot(cfg, 1)])
    for k in range(300):
        command = rng.normal(0.0, (0.06, 0.02, 0.15)).tolist()
        if k % 10 == 0:
            command[k % 3] = (0.0, -0.0)[k % 2]
        support = k % 2
        plan = plan_step(cfg, support, start, command)
        expected = _plan_step_on_arrays(cfg, support, start, command)
        assert plan.end.tobytes() == expected.tobytes()
        for i in range(cfg.step_cycles + 1):
            phase = i / cfg.step_cycles
            got = foot_rows(plan, foot_fractions(cfg, phase))
            assert (
                np.array(got).tobytes()
                == np.array(_feet_as_first_written(cfg, plan, phase)).tobytes()
            )
            assert np.array(foot_rows_at(cfg, plan, phase)).tobytes() == np.array(got).tobytes()
        start = plan.end


def test_the_engine_works_out_each_cycles_fractions_once() -> None:
    cfg = WalkConfig(step_s=0.18)
    engine = WalkEngine(cfg)
    assert engine._fractions == [
        foot_fractions(cfg, i / cfg.step_cycles) for i in range(cfg.step_cycles + 1)
    ]


def test_distance_checks_give_np_hypots_answers() -> None:
    rng = np.random.default_rng(13)
    for bound in (0.03, 0.22, 0.3, 0.45, 1e-120, 0.0, -1.0):
        for k in range(2000):
            angle = rng.uniform(-math.pi, math.pi)
            # Mostly within a few ulp of the bound, where the shortcut must hand over.
            length = abs(bound) * (1 + rng.normal(0.0, (1e-15, 1e-10, 1e-3)[k % 3]))
            dx, dy = length * math.cos(angle), length * math.sin(angle)
            assert _hypot_below(dx, dy, bound) == (float(np.hypot(dx, dy)) < bound)
    for dx, dy in ((math.nan, 0.0), (math.inf, math.nan), (0.0, 0.0), (-0.0, 1e-200)):
        assert _hypot_below(dx, dy, 0.3) == (float(np.hypot(dx, dy)) < 0.3)


def test_segment_checks_give_the_numpy_distances_answers() -> None:
    rng = np.random.default_rng(14)
    for k in range(3000):
        ball = tuple(rng.normal(0.0, 0.2, 2).tolist())
        robot = tuple(rng.normal(0.0, 0.5, 2).tolist())
        stage = (-0.3, 0.0) if k % 4 else robot  # also a segment of length zero
        distance = _segment_distance(ball, robot, stage)
        for bound in (0.3, distance, np.nextafter(distance, 1.0), np.nextafter(distance, 0.0)):
            bound = float(bound)
            assert _segment_distance_below(ball, robot, stage, bound) == (distance < bound)
