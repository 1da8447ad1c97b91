"""Trial statistics in the study's table layout, ratios against the original, and files.

Every mean and rate comes with its 95 % confidence interval (``<column>_ci_low`` and
``<column>_ci_high``; Wilson for rates, t for means, see ``mimic.trials.stats``).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import polars as pl
import pyarrow.parquet as pq

from mimic import __version__
from mimic.files import atomic_output
from mimic.trials.kick import SUCCESS_DISTANCE_M
from mimic.trials.parallel import EpisodeBatch
from mimic.trials.stats import mean_interval, ratio_interval, wilson_interval

__all__ = [
    "kick_summary",
    "walk_summary",
    "getup_summary",
    "with_ratios",
    "ratio_intervals",
    "STUDY_KICK",
    "STUDY_WALK",
    "write_rows",
    "write_summary",
    "summary_files",
    "progress_status",
    "CI_SUFFIXES",
    "STUCK_RULE",
    "SUCCESS_RULE",
]

#: Suffixes of the two columns holding a value's 95 % confidence interval.
CI_SUFFIXES = ("_ci_low", "_ci_high")

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


def _ci(name: str, interval: tuple[float, float], scale: float = 1.0) -> dict:
    return {name + CI_SUFFIXES[0]: interval[0] * scale, name + CI_SUFFIXES[1]: interval[1] * scale}


def kick_summary(label: str, batch: EpisodeBatch) -> dict:
    """One row of the kick table."""
    kicks = (
        pl.DataFrame(batch.rows)
        if batch.rows
        else pl.DataFrame(
            {"distance_m": [], "success": [], "direction_error_deg": []},
            schema={
                "distance_m": pl.Float64,
                "success": pl.Boolean,
                "direction_error_deg": pl.Float64,
            },
        )
    )
    eps = pl.DataFrame(batch.episodes)
    n = kicks.height
    ok = int(kicks["success"].sum()) if n else 0
    return dict(
        variant=label,
        attempts=n,
        successful=ok,
        accuracy_pct=100.0 * kicks["success"].mean() if n else 0.0,
        **_ci("accuracy_pct", wilson_interval(ok, n), 100.0),
        mean_distance_m=kicks["distance_m"].mean() if n else 0.0,
        **_ci("mean_distance_m", mean_interval(kicks["distance_m"].to_numpy())),
        std_distance_m=kicks["distance_m"].std() if n > 1 else 0.0,
        mean_direction_error_deg=kicks["direction_error_deg"].mean() if n else 0.0,
        goals=int(eps["goals"].sum()),
        goals_while_walking=int(eps["goals_while_walking"].sum()) if n else 0,
        falls=int(eps["falls"].sum()),
        getups=int(eps["getups"].sum()),
        stuck=int(eps["stuck"].sum()),
        episodes=eps.height,
        simulated_min=batch.simulated_s / 60,
        world=_first(eps, "world"),
        reach=_first(eps, "reach"),
        disturb=_first(eps, "disturb"),
    )


def _first(table: pl.DataFrame, column: str):
    """The column's first value (the same in every episode of a variant), None if absent."""
    return table[column][0] if column in table.columns and table.height else None


def walk_summary(label: str, batch: EpisodeBatch) -> dict:
    """One row of the walk table."""
    runs = pl.DataFrame(batch.rows)
    finished = runs.filter(pl.col("finished"))
    fell = int(runs["fell"].sum())
    return dict(
        variant=label,
        runs=runs.height,
        finished=finished.height,
        mean_speed_m_s=runs["speed_m_s"].mean(),
        **_ci("mean_speed_m_s", mean_interval(runs["speed_m_s"].to_numpy())),
        std_speed_m_s=runs["speed_m_s"].std() if runs.height > 1 else 0.0,
        mean_y_error_m=runs["y_error_m"].mean(),
        **_ci("mean_y_error_m", mean_interval(runs["y_error_m"].to_numpy())),
        std_y_error_m=runs["y_error_m"].std() if runs.height > 1 else 0.0,
        falls=int(runs["falls"].sum()),
        fall_rate_pct=100.0 * fell / runs.height,
        **_ci("fall_rate_pct", wilson_interval(fell, runs.height), 100.0),
        simulated_min=batch.simulated_s / 60,
        world=_first(runs, "world"),
        disturb=_first(runs, "disturb"),
    )


def getup_summary(label: str, batch: EpisodeBatch) -> dict:
    """One row of the get-up table: how many runs stood up, and how fast."""
    runs = pl.DataFrame(batch.rows)
    stood = runs.filter(pl.col("stood"))
    times = stood["time_to_stand_s"].cast(pl.Float64).to_numpy()
    return dict(
        variant=label,
        runs=runs.height,
        stood=stood.height,
        success_pct=100.0 * stood.height / runs.height,
        **_ci("success_pct", wilson_interval(stood.height, runs.height), 100.0),
        mean_time_to_stand_s=float(times.mean()) if len(times) else None,
        **_ci("mean_time_to_stand_s", mean_interval(times)),
        std_time_to_stand_s=float(times.std(ddof=1)) if len(times) > 1 else 0.0,
        falls=runs.height - stood.height,
        simulated_min=batch.simulated_s / 60,
        world=_first(runs, "world"),
        side=_first(runs, "side"),
        disturb=_first(runs, "disturb"),
    )


_RATIO_COLUMNS = {
    "accuracy_pct",
    "mean_distance_m",
    "std_distance_m",
    "goals",
    "mean_speed_m_s",
    "std_speed_m_s",
    "mean_y_error_m",
    "std_y_error_m",
    "success_pct",
    "mean_time_to_stand_s",
}


#: Summary column -> the per-event column its ratio's interval comes from, per trial kind;
#: walk runs pair by episode (every variant plays the same seeds), kicks do not pair.
_RATIO_CI_SOURCES = {
    "walk": ({"mean_speed_m_s": "speed_m_s"}, True),
    "kick": ({"mean_distance_m": "distance_m", "accuracy_pct": "success"}, False),
    "getup": ({"mean_time_to_stand_s": "time_to_stand_s"}, False),
}


def ratio_intervals(kind: str, first: list[dict], rows: list[dict]) -> dict:
    """``<column>_ratio_ci_low/high``: the 95 % interval of a variant's ratio to the first
    variant (``first``: its per-event rows), for the columns ``_RATIO_CI_SOURCES`` names."""
    sources, paired = _RATIO_CI_SOURCES.get(kind, ({}, False))
    out = {}
    for column, source in sources.items():
        if paired:
            by_episode = {r["episode"]: r[source] for r in first}
            pairs = [
                (r[source], by_episode[r["episode"]]) for r in rows if r["episode"] in by_episode
            ]
            values = [float(v) for v, _ in pairs]
            base = [float(b) for _, b in pairs]
        else:
            values = [float(r[source]) for r in rows if r.get(source) is not None]
            base = [float(r[source]) for r in first if r.get(source) is not None]
        out.update(_ci(f"{column}_ratio", ratio_interval(values, base, paired=paired)))
    return out


def with_ratios(summary: pl.DataFrame) -> pl.DataFrame:
    """Adds ``<column>_ratio`` = value / the first row's value (learned / original)."""
    base = summary.row(0, named=True)
    exprs = []
    for col in summary.columns:
        if col in _RATIO_COLUMNS and base[col]:
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


SUCCESS_RULE = f"success: ball travels more than {SUCCESS_DISTANCE_M} m"
#: What the kick table's ``stuck`` column counts.
STUCK_RULE = (
    "stuck: episodes that ended because the robot could not reach the ball in time "
    "or could not line up with it"
)


def progress_status(batch: EpisodeBatch, minutes: float | None, runs: int | None) -> str:
    """A short progress line of one variant's batch (kick or walk, told by its episodes):
    ``3.2/30 min 41 kicks 9 goals 1 fall`` or ``4/10 runs 1 fall``; a first episode longer
    than the budget (it counts: a variant has at least one) shows as ``2.3 min (one episode;
    2 asked)``, never as more than the budget."""
    eps = batch.episodes
    falls = sum(e.get("falls", 0) for e in eps)
    fall_text = f"{falls} fall" + ("" if falls == 1 else "s")
    if minutes and batch.simulated_s > minutes * 60:  # one episode longer than the budget
        done = f"{batch.simulated_s / 60:.1f} min (one episode; {minutes:g} asked)"
    elif minutes:
        done = f"{batch.simulated_s / 60:.1f}/{minutes:g} min"
    else:
        done = f"{len(eps)}/{runs} runs"
    if eps and "kicks" in eps[0]:
        goals = sum(e.get("goals", 0) for e in eps)
        return f"{done} {len(batch.rows)} kicks {goals} goals {fall_text}"
    return f"{done} {len(eps)} runs {fall_text}" if minutes else f"{done} {fall_text}"
