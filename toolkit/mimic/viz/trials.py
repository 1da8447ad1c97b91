"""Trial dashboards: each task's curves over its events, a running rate, a histogram, where
the ball ended up on the field and where episodes start, as its ``Dashboard`` asks (kicks:
distance, running accuracy; walks: speed and lateral error; get-ups: time to stand); and the
first episode of each variant replayed in 3D (robot and ball on the field, pushes as arrows),
one view per variant."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import polars as pl
import rerun as rr
import rerun.blueprint as rrb

from mimic.robot.registry import DEFAULT_ROBOT
from mimic.tasks.registry import get_task
from mimic.trials.report import to_markdown
from mimic.viz.paths import TIMELINE, WORLD
from mimic.viz.save import save_rrd
from mimic.viz.scene import (
    log_ball_poses,
    log_ball_shape,
    log_body_poses,
    log_field,
    log_robot_geometry,
)

__all__ = ["log_trial", "trial_blueprint", "save_trial_dashboard", "show_trial_dashboard"]

_EVENT = "event"
_REPLAY = f"{WORLD}/replay"


def _slug(label: str) -> str:
    return "".join(c if c.isalnum() else "_" for c in label).strip("_")


def _log_events(rec: rr.RecordingStream, name: str, events: pl.DataFrame, dashboard) -> None:
    """One variant's events as the task's dashboard draws them (``tasks.base.Dashboard``)."""
    index = [rr.TimeColumn(_EVENT, sequence=np.arange(events.height))]
    for column in dashboard.curves:
        rec.send_columns(
            f"trial/{column}/{name}",
            indexes=index,
            columns=rr.Scalars.columns(scalars=events[column].cast(pl.Float64).to_numpy()),
        )
    if dashboard.running_rate:
        column, curve = dashboard.running_rate
        hits = events[column].to_numpy().astype(float)
        running = np.cumsum(hits) / np.arange(1, len(hits) + 1) * 100
        rec.send_columns(
            f"trial/{curve}/{name}", indexes=index, columns=rr.Scalars.columns(scalars=running)
        )
    values = events[dashboard.histogram].cast(pl.Float64).to_numpy()
    counts, _ = np.histogram(values[np.isfinite(values)], bins=np.arange(*dashboard.histogram_bins))
    rec.log(f"histogram/{name}", rr.BarChart(counts), static=True)
    if dashboard.ball_ends:
        ends = events.select("ball_end_x_m", "ball_end_y_m").to_numpy()
        rec.log(
            f"world/ball_ends/{name}",
            rr.Points3D(np.c_[ends, np.full(len(ends), 0.05)], radii=0.06),
            static=True,
        )
    if dashboard.episode_markers:
        starts = events.with_row_index().group_by("episode").agg(pl.col("index").min())
        for episode, first in starts.sort("episode").iter_rows():
            rec.set_time(_EVENT, sequence=int(first))
            rec.log(f"episodes/{name}", rr.TextLog(f"episode {episode} starts"))


def _log_replay(rec: rr.RecordingStream, name: str, trace) -> None:
    """One traced episode (``episode.observers.EpisodeTrace``) on the ``sim_time`` timeline,
    drawn as the trace's robot (traces without one are of the default robot)."""
    root = f"{_REPLAY}/{name}"
    log_robot_geometry(rec, getattr(trace, "robot", DEFAULT_ROBOT), f"{root}/robot")
    log_body_poses(rec, trace.times_s, trace.poses(), f"{root}/robot")
    log_ball_shape(rec, f"{root}/ball")
    log_ball_poses(rec, trace.times_s, trace.ball_pos_m, f"{root}/ball")
    _log_pushes(rec, trace, f"{root}/push")


#: Arrow length per newton of a push, on the replay [m/N].
_PUSH_ARROW_M_PER_N = 0.02


def _log_pushes(rec: rr.RecordingStream, trace, path: str) -> None:
    """Each push on the torso as an arrow into it, shown while the push lasts."""
    pushes = getattr(trace, "pushes", ())
    if not pushes or not len(trace.times_s):
        return
    torso = trace.body_pos_m[:, 0]  # the robot's root link comes first
    for start_s, force_n, duration_s in pushes:
        at = torso[min(int(np.searchsorted(trace.times_s, start_s)), len(torso) - 1)]
        vector = np.asarray(force_n) * _PUSH_ARROW_M_PER_N
        rec.set_time(TIMELINE, duration=float(start_s))
        rec.log(path, rr.Arrows3D(origins=[at - vector], vectors=[vector], colors=[(230, 60, 40)]))
        rec.set_time(TIMELINE, duration=float(start_s + duration_s))
        rec.log(path, rr.Clear(recursive=False))


def log_trial(rec: rr.RecordingStream, result) -> None:
    """Everything of a ``TrialResult`` onto ``rec``."""
    log_field(rec)
    for label in result.rows["variant"].unique(maintain_order=True):
        part = result.rows.filter(pl.col("variant") == label)
        _log_events(rec, _slug(label), part, get_task(result.kind).dashboard)
    for label, trace in result.traces.items():
        _log_replay(rec, _slug(label), trace)
    rec.log(
        "summary",
        rr.TextDocument(to_markdown(result.summary), media_type="text/markdown"),
        static=True,
    )


def trial_blueprint(result) -> rrb.Blueprint:
    """Curves and the summary on the left; the field with where the balls ended, one 3D replay
    per traced variant, the distance or speed histogram and episode markers on the right."""
    views = [
        rrb.TimeSeriesView(origin=f"trial/{m}", name=m)
        for m in get_task(result.kind).dashboard.series
    ]
    field = [
        rrb.Spatial3DView(
            origin=WORLD, name="field", contents=[f"{WORLD}/field/**", f"{WORLD}/ball_ends/**"]
        )
    ]
    replays = [
        rrb.Spatial3DView(
            origin=WORLD,
            name=f"first episode: {label}",
            contents=[f"{WORLD}/field/**", f"{_REPLAY}/{_slug(label)}/**"],
        )
        for label in result.traces
    ]
    return rrb.Blueprint(
        rrb.Horizontal(
            rrb.Vertical(*views, rrb.TextDocumentView(origin="summary")),
            rrb.Vertical(
                rrb.Tabs(*field, *replays),
                rrb.BarChartView(origin="histogram", name="histogram"),
                rrb.TextLogView(origin="episodes"),
            ),
        )
    )


def save_trial_dashboard(result, path: Path, *, overwrite: bool = True) -> None:
    """Write the dashboard of a trial to an .rrd file with its blueprint (under a temporary
    name, moved into place when complete: ``mimic.files``)."""

    rec = rr.RecordingStream("mimic_trial")
    save_rrd(
        rec,
        path,
        lambda: log_trial(rec, result),
        blueprint=trial_blueprint(result),
        overwrite=overwrite,
    )


def show_trial_dashboard(result) -> None:
    """Open the dashboard in a Rerun viewer (spawned, or the one already running)."""
    rec = rr.RecordingStream("mimic_trial")
    rec.spawn(default_blueprint=trial_blueprint(result))
    log_trial(rec, result)
    rec.flush()
