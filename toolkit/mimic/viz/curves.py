"""Joint-angle curves: one plot per group (head, arms, legs), series overlaid per joint.

Joint names come from the tables themselves (every column but time and the ended flag), so a
table of any robot plots; the robot only says which group a joint belongs to.
"""

from __future__ import annotations

import numpy as np
import polars as pl
import rerun as rr
import rerun.blueprint as rrb

from mimic.recording.layout import ENDED_COLUMN, TIME_COLUMN
from mimic.robot.model import RobotDescription
from mimic.robot.registry import get_robot
from mimic.viz.paths import GROUPS, JOINTS_ROOT, joint_path, time_column

__all__ = ["log_joint_table", "SERIES_STYLE", "curves_blueprint", "joint_columns", "joint_error"]

#: Colour and width of each series kind, so "reached" and "reference" read the same everywhere.
SERIES_STYLE = {
    "reached": ((40, 120, 230), 2.0),
    "reference": ((230, 120, 40), 1.0),
    "learned": ((40, 180, 80), 2.0),
    "learned_reached": ((160, 60, 200), 2.0),
    "compensated": ((200, 40, 40), 1.0),
}


def joint_columns(table: pl.DataFrame) -> list[str]:
    """The joint columns of a joint table, in its order."""
    return [c for c in table.columns if c not in (TIME_COLUMN, ENDED_COLUMN)]


def log_joint_table(
    rec: rr.RecordingStream, table: pl.DataFrame, series: str, robot: str | RobotDescription
) -> None:
    """Every joint of ``table`` (``time_s`` + joint columns of ``robot``) as one series [rad]."""
    robot = get_robot(robot)
    times = table[TIME_COLUMN].to_numpy()
    colour, width = SERIES_STYLE.get(series, ((128, 128, 128), 1.0))
    for name in joint_columns(table):
        path = joint_path(robot, name, series)
        rec.log(
            path,
            rr.SeriesLines(colors=[colour], widths=[width], names=[f"{name} {series}"]),
            static=True,
        )
        rec.send_columns(
            path,
            indexes=[time_column(times)],
            columns=rr.Scalars.columns(scalars=table[name].to_numpy()),
        )


def curves_blueprint() -> list[rrb.TimeSeriesView]:
    """One time-series view per joint group."""
    return [
        rrb.TimeSeriesView(origin=f"{JOINTS_ROOT}/{group}", name=f"{group} [rad]")
        for group in GROUPS
    ]


def joint_error(table_a: pl.DataFrame, table_b: pl.DataFrame) -> np.ndarray:
    """(N,) mean absolute difference [rad] of two tables on the same times, for the joint
    columns of ``table_a`` (its order; ``table_b`` must have them too)."""
    names = joint_columns(table_a)
    a = table_a.select(names).to_numpy()
    b = table_b.select(names).to_numpy()
    n = min(len(a), len(b))
    return np.abs(a[:n] - b[:n]).mean(axis=0)
