"""Trial statistics in the study's table layout, ratios against the original, and files."""

from __future__ import annotations

import json
from pathlib import Path

import polars as pl
import pyarrow.parquet as pq

from mimic import __version__
from mimic.trials.kick import SUCCESS_DISTANCE_M
from mimic.trials.parallel import EpisodeBatch

__all__ = ["kick_summary", "walk_summary", "with_ratios", "STUDY_KICK", "STUDY_WALK",
           "write_rows", "write_summary"]

#: The study's kick table (30 simulated minutes in the RoboCup 3D simulator).
STUDY_KICK = pl.DataFrame({
    "variant": ["study: original keyframe", "study: learned"],
    "attempts": [726, 844], "successful": [468, 444], "accuracy_pct": [64.5, 52.6],
    "mean_distance_m": [8.92, 7.16], "std_distance_m": [3.82, 4.06], "goals": [178, 120],
})
#: The study's forward walk table.
STUDY_WALK = pl.DataFrame({
    "variant": ["study: original (UT Austin walk)", "study: learned"],
    "mean_speed_m_s": [0.87, 0.23], "std_speed_m_s": [0.01, 0.01],
    "mean_y_error_m": [None, 0.96], "std_y_error_m": [None, 2.63],
}, schema_overrides={"mean_y_error_m": pl.Float64, "std_y_error_m": pl.Float64})


def kick_summary(label: str, batch: EpisodeBatch) -> dict:
    """One row of the kick table."""
    kicks = pl.DataFrame(batch.rows) if batch.rows else pl.DataFrame(
        {"distance_m": [], "success": [], "direction_error_deg": []},
        schema={"distance_m": pl.Float64, "success": pl.Boolean, "direction_error_deg": pl.Float64})
    eps = pl.DataFrame(batch.episodes)
    n = kicks.height
    return dict(
        variant=label, attempts=n, successful=int(kicks["success"].sum()) if n else 0,
        accuracy_pct=100.0 * kicks["success"].mean() if n else 0.0,
        mean_distance_m=kicks["distance_m"].mean() if n else 0.0,
        std_distance_m=kicks["distance_m"].std() if n > 1 else 0.0,
        mean_direction_error_deg=kicks["direction_error_deg"].mean() if n else 0.0,
        goals=int(eps["goals"].sum()),
        goals_while_walking=int(eps["goals_while_walking"].sum()) if n else 0,
        falls=int(eps["falls"].sum()),
        getups=int(eps["getups"].sum()), stuck=int(eps["stuck"].sum()),
        episodes=eps.height, simulated_min=batch.simulated_s / 60,
    )


def walk_summary(label: str, batch: EpisodeBatch) -> dict:
    """One row of the walk table."""
    runs = pl.DataFrame(batch.rows)
    finished = runs.filter(pl.col("finished"))
    return dict(
        variant=label, runs=runs.height, finished=finished.height,
        mean_speed_m_s=runs["speed_m_s"].mean(),
        std_speed_m_s=runs["speed_m_s"].std() if runs.height > 1 else 0.0,
        mean_y_error_m=runs["y_error_m"].mean(),
        std_y_error_m=runs["y_error_m"].std() if runs.height > 1 else 0.0,
        falls=int(runs["falls"].sum()), simulated_min=batch.simulated_s / 60,
    )


_RATIO_COLUMNS = {"accuracy_pct", "mean_distance_m", "std_distance_m", "goals",
                  "mean_speed_m_s", "std_speed_m_s", "mean_y_error_m", "std_y_error_m"}


def with_ratios(summary: pl.DataFrame) -> pl.DataFrame:
    """Adds ``<column>_ratio`` = value / the first row's value (learned / original)."""
    base = summary.row(0, named=True)
    exprs = []
    for col in summary.columns:
        if col in _RATIO_COLUMNS and base[col]:
            exprs.append((pl.col(col) / base[col]).alias(f"{col}_ratio"))
    return summary.with_columns(exprs)


def write_rows(rows: pl.DataFrame, path: Path, config: dict) -> None:
    """Parquet with the configuration and toolkit version in the file's metadata."""
    path.parent.mkdir(parents=True, exist_ok=True)
    table = rows.to_arrow()
    meta = dict(table.schema.metadata or {})
    meta[b"mimic"] = json.dumps({"toolkit_version": __version__, **config}).encode()
    pq.write_table(table.replace_schema_metadata(meta), path)


def write_summary(summary: pl.DataFrame, path_stem: Path) -> list[Path]:
    """The summary table as CSV and Markdown beside the parquet file."""
    csv, md = path_stem.with_suffix(".csv"), path_stem.with_suffix(".md")
    summary.write_csv(csv)
    md.write_text(to_markdown(summary))
    return [csv, md]


def to_markdown(table: pl.DataFrame) -> str:
    def fmt(v):
        if isinstance(v, float):
            return f"{v:.3g}" if abs(v) < 100 else f"{v:.0f}"
        return "" if v is None else str(v)
    lines = ["| " + " | ".join(table.columns) + " |",
             "|" + "---|" * len(table.columns)]
    lines += ["| " + " | ".join(fmt(v) for v in row) + " |" for row in table.iter_rows()]
    return "\n".join(lines) + "\n"


SUCCESS_RULE = f"success: ball travels more than {SUCCESS_DISTANCE_M} m"
