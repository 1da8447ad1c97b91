"""What a trial task is: one object that knows a scenario from its scene to its table.

A ``TrialTask`` (the kick, walk and get-up trials: ``tasks.registry``) is the one place that
knows, for its scenario:

* its settings: a frozen config class (``Config``), the world it plays in among them;
* how one episode plays: ``run_episode(spec, seed, config)`` sets up the scene in a fresh
  world, plays it and returns typed rows, one per event (a kick, a walk, a get-up), as dicts
  for the table, and the episode's summary row;
* what a variant's episodes add up to: ``summarise`` (means and rates with their 95 %
  confidence intervals), the columns whose ratio to the first variant gets an interval
  (``ratio_sources``);
* how ``mimic improve`` scores a candidate: ``Objective``;
* how a person reads it: the printed table's columns (``columns``), its legend, the
  progress line, and the dashboard's curves (``dashboard``).

The trial runner (``trials.api``), the search (``improve``), the CLI and the viewer take a
task by name and never ask which one it is.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, fields
from typing import Any, ClassVar

from mimic.agents.registry import AgentSpec
from mimic.tasks.budget import CHECKPOINTS

__all__ = [
    "TaskOption",
    "Column",
    "Dashboard",
    "EpisodeBatch",
    "TrialTask",
    "as_row",
    "ci_columns",
    "first_value",
    "CI_SUFFIXES",
]

#: Suffixes of the two columns holding a value's 95 % confidence interval.
CI_SUFFIXES = ("_ci_low", "_ci_high")


def ci_columns(name: str, interval: tuple[float, float], scale: float = 1.0) -> dict:
    """``{name}_ci_low`` and ``{name}_ci_high`` of ``interval``, times ``scale``."""
    return {name + CI_SUFFIXES[0]: interval[0] * scale, name + CI_SUFFIXES[1]: interval[1] * scale}


def first_value(rows: list[dict], column: str):
    """The column's value in the first row (the same in every episode of a variant: its
    world, its disturbance level), None if there is none."""
    return rows[0].get(column) if rows else None


def as_row(event) -> dict:
    """A typed row (a dataclass) as the table's dict, in field order; a field named
    ``disturbances`` (the episode's draw, ``EpisodeDisturbances.columns``) is spread in place."""
    out: dict[str, Any] = {}
    for f in fields(event):
        value = getattr(event, f.name)
        if f.name == "disturbances":
            out.update(value)
        else:
            out[f.name] = value
    return out


@dataclass
class EpisodeBatch:
    """Rows of every counted episode of one variant, tagged with the episode index."""

    rows: list[dict]
    episodes: list[dict]
    # Pose traces of the traced episodes, by episode index (see ``episode.PoseTrace``).
    traces: dict = field(default_factory=dict)
    # The name of the task these episodes play (``tasks.registry``), for whoever shows them.
    task: str | None = None

    def add(self, rows: list[dict], summary: dict) -> None:
        summary.pop(CHECKPOINTS, None)  # the trial's to read (``trials.parallel``), not a column
        trace = summary.pop("trace", None)
        if trace is not None:
            self.traces[summary["episode"]] = trace
        self.rows += rows
        self.episodes.append(summary)

    @property
    def simulated_s(self) -> float:
        return sum(e["duration_s"] for e in self.episodes)


@dataclass(frozen=True)
class Column:
    """A column of the printed table: the summary's ``key`` under a short ``header`` (a
    space breaks it onto two lines), and what goes under it in the 95 % CI line: the
    interval of ``ci`` (a summary column; None: nothing), as a ``range`` (``range %``: with a
    percent sign) or as ``half`` its width (+-)."""

    key: str
    header: str
    ci: str | None = None
    ci_how: str = "half"


@dataclass(frozen=True)
class Dashboard:
    """What a trial's Rerun dashboard draws from its rows: one curve per ``curves`` column
    over the events, a running rate of a boolean column (``running_rate``: (column, name of
    the curve)), a histogram of ``histogram`` with ``histogram_bins`` (start, stop, step),
    where the ball ended (``ball_ends``) and where each episode starts."""

    curves: tuple[str, ...]
    histogram: str
    histogram_bins: tuple[float, float, float]
    running_rate: tuple[str, str] | None = None
    ball_ends: bool = False
    episode_markers: bool = False

    @property
    def series(self) -> tuple[str, ...]:
        """Every curve's name, the running rate's included."""
        rate = (self.running_rate[1],) if self.running_rate else ()
        return (*self.curves, *rate)


@dataclass(frozen=True)
class TaskOption:
    """A setting of a task's config that its trial command offers: ``mimic trial NAME
    FLAG VALUE`` sets the config's ``field`` (a value of ``type``; not given: the config's
    default)."""

    field: str
    flag: str
    help: str
    type: type = float


class TrialTask:
    """A trial's scenario (module docstring). Subclasses set the class attributes and
    implement ``run_episode`` and ``summarise``; the rest has defaults."""

    #: The name trials, improve and the CLI know it by.
    name: ClassVar[str]
    #: What the trial does, in a sentence (its command's help).
    summary: ClassVar[str]
    #: Its budget: by simulated minutes (default ``minutes``), by runs (default ``runs``), or
    #: either (``minutes`` None and ``runs`` set: runs unless minutes are given).
    minutes: ClassVar[float | None] = None
    runs: ClassVar[int | None] = 10
    by_minutes: ClassVar[bool] = False
    #: The config's settings its command offers as options.
    options: ClassVar[tuple[TaskOption, ...]] = ()
    #: Its variants take a speed command (``--vx``) and a phase rate (``--speed-rate``).
    speed_command: ClassVar[bool] = False
    #: The frozen settings of one episode (with ``world``, ``disturb`` and ``trace`` fields).
    Config: ClassVar[type]
    #: The score ``mimic improve`` maximises (a frozen dataclass with ``trial_config``).
    Objective: ClassVar[type]
    #: What one row is, in the progress line and in messages: ``kick``, ``run``.
    event: ClassVar[str] = "run"
    #: Held-out validation episodes of ``mimic improve`` unless told.
    validation_episodes: ClassVar[int] = 20
    #: The printed table's columns, in order.
    columns: ClassVar[tuple[Column, ...]]
    #: The line under the printed table; ``{field}`` is the trial's setting of that name.
    legend: ClassVar[str]
    #: Summary columns that get a ratio to the first variant.
    ratio_columns: ClassVar[tuple[str, ...]] = ()
    #: Summary column -> the per-event column its ratio's interval comes from.
    ratio_sources: ClassVar[dict[str, str]] = {}
    #: Ratios pair events by episode (every variant plays the same seeds, one event each).
    paired: ClassVar[bool] = False
    #: The dashboard's curves.
    dashboard: ClassVar[Dashboard]
    #: How ``--keep-best`` ranks the variants: a summary row -> a key, the largest best
    #: (equal keys: the variant given first). None: the trial keeps no best.
    rank: ClassVar[Callable[[dict], tuple] | None] = None
    #: What ``rank`` prefers, in a few words (the option's help, the kept line).
    rank_says: ClassVar[str] = ""

    @staticmethod
    def run_episode(spec: AgentSpec, seed: int, config) -> tuple[list[dict], dict]:
        """One episode in ``config.world``: (one row per event, the episode's summary row).
        Module level (a static method): worker processes and Ray pickle it by name."""
        raise NotImplementedError

    @staticmethod
    def summarise(label: str, batch: EpisodeBatch) -> dict:
        """One row of the summary table: the variant ``label``'s episodes."""
        raise NotImplementedError

    @classmethod
    def check(cls, config, specs: list[AgentSpec]) -> None:
        """Before any episode: the settings and variants suit this task (raises
        ``MimicError``). The world and the variants' files are checked by the runner."""

    @classmethod
    def check_variant(cls, spec: AgentSpec) -> None:
        """Before any episode: this variant can play this task (raises ``MimicError``)."""

    @classmethod
    def counts(cls, batch: EpisodeBatch, minutes: float | None) -> str:
        """The progress line's counts after the time or runs done: ``4 runs`` (by minutes)
        or nothing (by runs: the runs done say it)."""
        return f"{len(batch.episodes)} runs" if minutes else ""

    @classmethod
    def for_original(cls, config, original: AgentSpec):
        """``config`` as a trial whose first variant is ``original`` plays every variant
        (default: as it is)."""
        return config

    @classmethod
    def default_variant(cls, robot: str, config) -> str:
        """The variant a trial plays when given none (an agent or motion name)."""
        raise NotImplementedError

    @classmethod
    def played(cls, summary_row: dict) -> str | None:
        """How a variant's episodes were played, for the table's title (None: nothing to
        say beyond the world)."""
        return None

    @classmethod
    def title(cls, config) -> str:
        """The table's title before its budget and seed: ``kick trial``."""
        return f"{cls.name} trial"
