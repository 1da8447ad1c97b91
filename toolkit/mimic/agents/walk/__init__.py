"""Our team's walk: LIPM gait + leg IK + IMU feedback (``WalkEngine``), go-to-pose on top."""

from __future__ import annotations

from mimic.agents.walk.engine import WalkEngine
from mimic.agents.walk.gait import WalkConfig

__all__ = ["WalkEngine", "WalkConfig", "make_walk_agent"]


def make_walk_agent(
    vx_m_s: float = 0.45,
    vy_m_s: float = 0.0,
    yaw_rate_rad_s: float = 0.0,
    config: WalkConfig | None = None,
) -> WalkEngine:
    """A walk engine already commanded to walk at (vx, vy, yaw rate) [m/s, m/s, rad/s]."""
    engine = WalkEngine(config or WalkConfig())
    engine.set_velocity(vx_m_s, vy_m_s, yaw_rate_rad_s)
    return engine
