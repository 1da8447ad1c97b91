"""Trial statistics in the study's table layout, ratios against the original, and files.

Every mean and rate comes with its 95 % confidence interval (``<column>_ci_low`` and
``<column>_ci_high``; Wilson for rates, t for means, see ``mimic.stats``).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import polars as pl
import pyarrow.parquet as pq

from mimic import __version__
from mimic.files import atomic_output
from mimic.stats import ratio_interval
from mimic.tasks.base import CI_SUFFIXES, EpisodeBatch, TrialTask, ci_columns

__all__ = [
    "with_ratios",
    "ratio_intervals",
    "STUDY_KICK",
    "STUDY_WALK",
    "write_rows",
    "write_summary",
    "summary_files",
    "progress_status",
    "CI_SUFFIXES",
]

#: The study's kick table (30 simulated minutes in the RoboCup 3D simulator).
STUDY_KICK = pl.DataFrame(
    {
        "variant": ["study: original keyframe", "study: learned"],
        "attempts": [726, 844],
        "successful": [468, 444],
        "accuracy_pct": [64.5, 52.6],
        "mean_distance_m": [8.92, 7.16],
        "std_distance_m": [3.82, 4.06],
        "goals": [178, 120],
        "falls": [None, None],
    },
    schema_overrides={"falls": pl.Int64},
)
#: The study's forward walk table.
STUDY_WALK = pl.DataFrame(
    {
        "variant": ["study: original (UT Austin walk)", "study: learned"],
        "runs": [None, None],
        "mean_speed_m_s": [0.87, 0.23],
        "std_speed_m_s": [0.01, 0.01],
        "mean_y_error_m": [None, 0.96],
        "std_y_error_m": [None, 2.63],
        "falls": [None, None],
    },
    schema_overrides={
        "runs": pl.Int64,
        "mean_y_error_m": pl.Float64,
        "std_y_error_m": pl.Float64,
        "falls": pl.Int64,
    },
)


def ratio_intervals(task: type[TrialTask], first: list[dict], rows: list[dict]) -> dict:
    """``<column>_ratio_ci_low/high``: the 95 % interval of a variant's ratio to the first
    variant (``first``: its per-event rows), for the columns the task's ``ratio_sources``
    names; events pair by episode where the task says so (``paired``)."""
    out = {}
    for column, source in task.ratio_sources.items():
        if task.paired:
            by_episode = {r["episode"]: r[source] for r in first}
            pairs = [
                (r[source], by_episode[r["episode"]]) for r in rows if r["episode"] in by_episode
            ]
            values = [float(v) for v, _ in pairs]
            base = [float(b) for _, b in pairs]
        else:
            values = [float(r[source]) for r in rows if r.get(source) is not None]
            base = [float(r[source]) for r in first if r.get(source) is not None]
        out.update(ci_columns(f"{column}_ratio", ratio_interval(values, base, paired=task.paired)))
    return out


def with_ratios(summary: pl.DataFrame, columns: tuple[str, ...]) -> pl.DataFrame:
    """Adds ``<column>_ratio`` = value / the first row's value (learned / original) for each
    of ``columns`` (a task's ``ratio_columns``) in the summary."""
    base = summary.row(0, named=True)
    exprs = []
    for col in summary.columns:
        if col in columns and base[col]:
            exprs.append((pl.col(col) / base[col]).alias(f"{col}_ratio"))
    return summary.with_columns(exprs)


def _plain(value):
    """JSON-safe: NaN and infinities become None."""
    return None if isinstance(value, float) and not math.isfinite(value) else value


def write_rows(
    rows: pl.DataFrame,
    path: Path,
    config: dict,
    *,
    summary: pl.DataFrame | None = None,
    overwrite: bool = True,
) -> None:
    """Parquet with the configuration, toolkit version and (when given) the summary table
    with its confidence intervals in the file's metadata (key ``mimic``, JSON)."""
    table = rows.to_arrow()
    meta = dict(table.schema.metadata or {})
    extra = (
        {}
        if summary is None
        else {
            "summary": [{k: _plain(v) for k, v in r.items()} for r in summary.to_dicts()],
            "confidence": "95 %: Wilson score interval for rates, Student t for means",
        }
    )
    meta[b"mimic"] = json.dumps({"toolkit_version": __version__, **config, **extra}).encode()
    with atomic_output(path, overwrite=overwrite) as tmp:
        pq.write_table(table.replace_schema_metadata(meta), tmp)


def summary_files(path: Path) -> list[Path]:
    """The summary files written beside a trial's parquet ``path``: CSV and Markdown."""
    stem = path.with_name(path.stem + "_summary")
    return [stem.with_suffix(".csv"), stem.with_suffix(".md")]


def write_summary(summary: pl.DataFrame, path_stem: Path, *, overwrite: bool = True) -> list[Path]:
    """The summary table as CSV and Markdown beside the parquet file."""
    csv, md = path_stem.with_suffix(".csv"), path_stem.with_suffix(".md")
    with atomic_output(csv, overwrite=overwrite) as tmp:
        summary.write_csv(tmp)
    with atomic_output(md, overwrite=overwrite) as tmp:
        tmp.write_text(to_markdown(summary))
    return [csv, md]


def to_markdown(table: pl.DataFrame) -> str:
    def fmt(v):
        if isinstance(v, float):
            return f"{v:.3g}" if abs(v) < 100 else f"{v:.0f}"
        return "" if v is None else str(v)

    lines = ["| " + " | ".join(table.columns) + " |", "|" + "---|" * len(table.columns)]
    lines += ["| " + " | ".join(fmt(v) for v in row) + " |" for row in table.iter_rows()]
    return "\n".join(lines) + "\n"


def progress_status(
    task: type[TrialTask], batch: EpisodeBatch, minutes: float | None, runs: int | None
) -> str:
    """A short progress line of one variant's batch: ``3.2/30 min 41 kicks 9 goals 1 fall``
    or ``4/10 runs 1 fall`` (the counts are the task's: ``TrialTask.counts``); a first
    episode longer than the budget (it counts: a variant has at least one) shows as ``2.3
    min (one episode; 2 asked)``, never as more than the budget."""
    eps = batch.episodes
    falls = sum(e.get("falls", 0) for e in eps)
    fall_text = f"{falls} fall" + ("" if falls == 1 else "s")
    if minutes and batch.simulated_s > minutes * 60:  # one episode longer than the budget
        done = f"{batch.simulated_s / 60:.1f} min (one episode; {minutes:g} asked)"
    elif minutes:
        done = f"{batch.simulated_s / 60:.1f}/{minutes:g} min"
    else:
        done = f"{len(eps)}/{runs} runs"
    return " ".join(part for part in (done, task.counts(batch, minutes), fall_text) if part)
