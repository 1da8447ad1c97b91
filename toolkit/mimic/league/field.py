"""The installed league server's soccer world, read from RCSSServerMJ (``rcsssmj``): its MJCF,
its physics step and its air.

Nothing here is a number of ours: the ball, the pitch and the physics options come from the
server's soccer world (``resources/environments/soccer/world.xml``). The wire needs the step
(``decode``: a monitor frame shows the poses one step before its cycle's end); the worlds
above read the ball, the pitch and the air from the same file (``world/league_field.py``), so
motions authored in ours meet the league's ball and the air it rolls through (the world's
density and viscosity drag a 0.11 m ball noticeably).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from importlib import resources
from pathlib import Path

import mujoco

from mimic.errors import MimicError

__all__ = ["league_world_xml", "league_world_spec", "league_air", "LeagueAir"]


@dataclass(frozen=True)
class LeagueAir:
    """The league world's physics options that act on everything.

    Attributes:
        timestep_s: its physics step [s].
        density_kg_m3: air density (MuJoCo's fluid forces) [kg/m^3].
        viscosity_pa_s: air viscosity [Pa s].
    """

    timestep_s: float
    density_kg_m3: float
    viscosity_pa_s: float


def league_world_xml() -> Path:
    """The soccer world MJCF of the installed league server."""
    try:
        package = resources.files("rcsssmj")
    except ModuleNotFoundError:
        raise MimicError(
            "the league field comes with the league simulator: pip install rcsssmj"
        ) from None
    path = Path(str(package / "resources" / "environments" / "soccer" / "world.xml"))
    if not path.is_file():
        raise MimicError(f"rcsssmj has no {path}; pip install --upgrade rcsssmj")
    return path


@cache
def league_world_spec() -> mujoco.MjSpec:
    """The installed server's soccer world as a MuJoCo spec (read once; do not edit it)."""
    return mujoco.MjSpec.from_file(str(league_world_xml()))


@cache
def league_air() -> LeagueAir:
    """The league world's step and air."""
    opt = league_world_spec().option
    return LeagueAir(float(opt.timestep), float(opt.density), float(opt.viscosity))
