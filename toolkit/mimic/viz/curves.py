"""Joint-angle curves: one plot per group (head, arms, legs), series overlaid per joint."""

from __future__ import annotations

import numpy as np
import polars as pl
import rerun as rr
import rerun.blueprint as rrb

from mimic.robot.joints import JOINT_NAMES
from mimic.viz.paths import GROUPS, JOINTS_ROOT, joint_path, time_column

__all__ = ["log_joint_table", "SERIES_STYLE", "curves_blueprint"]

#: Colour and width of each series kind, so "reached" and "reference" read the same everywhere.
SERIES_STYLE = {
    "reached": ((40, 120, 230), 2.0),
    "reference": ((230, 120, 40), 1.0),
    "learned": ((40, 180, 80), 2.0),
    "learned_reached": ((160, 60, 200), 2.0),
    "compensated": ((200, 40, 40), 1.0),
}


def log_joint_table(rec: rr.RecordingStream, table: pl.DataFrame, series: str) -> None:
    """Every joint of ``table`` (columns ``time_s`` + the 22 joint names) as one series [rad]."""
    times = table["time_s"].to_numpy()
    colour, width = SERIES_STYLE.get(series, ((128, 128, 128), 1.0))
    for i, name in enumerate(JOINT_NAMES):
        path = joint_path(i, series)
        rec.log(path, rr.SeriesLines(colors=[colour], widths=[width], names=[f"{name} {series}"]),
                static=True)
        rec.send_columns(path, indexes=[time_column(times)],
                         columns=rr.Scalars.columns(scalars=table[name].to_numpy()))


def curves_blueprint() -> list[rrb.TimeSeriesView]:
    """One time-series view per joint group."""
    return [rrb.TimeSeriesView(origin=f"{JOINTS_ROOT}/{group}", name=f"{group} [rad]")
            for group in GROUPS]


def joint_error(table_a: pl.DataFrame, table_b: pl.DataFrame) -> np.ndarray:
    """(22,) mean absolute difference [rad] of two tables on the same times."""
    a = table_a.select(JOINT_NAMES).to_numpy()
    b = table_b.select(JOINT_NAMES).to_numpy()
    n = min(len(a), len(b))
    return np.abs(a[:n] - b[:n]).mean(axis=0)
