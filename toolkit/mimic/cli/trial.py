"""`mimic trial kick|walk|getup`: the study's statistical trials, variants side by side."""

from __future__ import annotations

import inspect
import math
import time
from dataclasses import asdict, replace
from pathlib import Path
from typing import Annotated

import typer
from rich import box
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn
from rich.table import Column, Table

from mimic import options
from mimic.cli.common import (
    DISTURB,
    FORCE,
    ROBOT,
    SAVE_OLD,
    WORLD,
    OneLineUsageErrors,
    console,
    reports_errors,
    save_path,
)
from mimic.cli.executor_options import RAY, RAY_ADDRESS, WORKERS, open_executor
from mimic.errors import MimicError

trial_app = typer.Typer(
    cls=OneLineUsageErrors,
    help="Run the kick, walk and get-up trials (original and learned side by side).",
    no_args_is_help=True,
)

_VARIANTS = typer.Argument(
    help="Variants to try side by side (motion names, .mimic models, "
    "agent names; M.mimic+balance: that model inside the balance layer); "
    "the first is the baseline for ratios.",
    show_default=False,
)
_COMPARE = typer.Option(
    "--compare",
    "-c",
    help="Compare the variants given (the study's table "
    "with ratios); reads as: --compare kick_right models/kick_right.mimic.",
)
_MOTION = typer.Option("--motion", help="One keyframe motion or agent name to try.")
_MODEL = typer.Option("--model", help="One learned model (.mimic) to try.")
_RERUN = typer.Option("--rerun", help="Open the same dashboard in a Rerun viewer.")
_SAVE_HELP = (
    "Save a Rerun dashboard (.rrd): curves, histogram, episode markers, the first "
    "episode of each variant in 3D."
)
_SEED = typer.Option(help="Seed (0 .. 2**32-1); the same seed gives the same table.")

#: Without a terminal (a pipe, a log file), a progress line is printed at most this often [s].
PLAIN_PROGRESS_EVERY_S = 5.0


def _specs(
    variants, compare, motion, model, balance, speed_rate, default, robot="nao", vx_m_s=None
):
    """The variants as specs, each checked to drive ``robot`` (the trial's one robot)."""
    from mimic.agents.registry import agent_spec

    names = list(variants or []) + [n for n in (motion, model) if n]
    specs = [
        agent_spec(n, speed_rate=speed_rate, robot=robot, speed_m_s=vx_m_s)
        for n in names or [default]
    ]
    if compare and len(names) < 2:
        raise MimicError(
            "--compare needs at least two variants, e.g. "
            "--compare kick_right models/kick_right.mimic"
        )
    # --balance wraps every learned motion; keyframe motions and agents stay as they are.
    specs = [replace(s, balance=True) if balance and s.kind == "model" else s for s in specs]
    for spec in specs:  # every variant can run on the trial's robot, before the first one does
        if spec.robot != robot:  # a model file names its own robot
            raise MimicError(
                f"{spec.ref} was made for the {spec.robot.upper()}; this trial plays the "
                f"{robot.upper()} (--robot {robot}): compare variants of one robot"
            )
        spec.check(robot)
    return specs


def _trial_robot(robot: str | None, world: str, names: list[str]) -> str:
    """The trial's robot: ``--robot``, else the one robot its model variants were made for,
    else the world's default."""
    from mimic.agents.registry import BALANCE_SUFFIX
    from mimic.world.registry import default_robot

    if robot is not None:
        return robot
    models = [n.removesuffix(BALANCE_SUFFIX) for n in names if n]
    models = [n for n in models if n.endswith(".mimic") and Path(n).is_file()]
    if models:
        from mimic.model.model_file import load_model

        robots = {load_model(n).robot for n in models}
        if len(robots) == 1:
            return robots.pop()
    return default_robot(world)


class TrialProgress:
    """Progress of each variant: a live line per variant on a terminal; elsewhere (a pipe, a
    log) a plain line at most every ``PLAIN_PROGRESS_EVERY_S`` and the last one at the end.

    Call it as the trials' ``progress(label, batch)``; use it as a context manager.
    """

    def __init__(self, minutes: float | None, runs: int | None) -> None:
        self.minutes, self.runs = minutes, runs
        self.live = console.is_terminal
        self._tasks: dict[str, int] = {}
        self._last: dict[str, str] = {}
        self._printed: dict[str, str] = {}
        self._printed_at = -math.inf
        self._bar = Progress(
            TextColumn(
                "[bold]{task.description}", table_column=Column(overflow="fold", max_width=28)
            ),
            BarColumn(bar_width=8),
            TextColumn("{task.fields[status]}", table_column=Column(no_wrap=True)),
            TimeElapsedColumn(),
            console=console,
        )

    def __enter__(self) -> TrialProgress:
        return self

    def _finish(self, label: str) -> None:
        """Stop the variant's clock and bar where it ended (a walk trial's budget may end
        short of the bar's total: whole runs only)."""
        task = self._tasks.get(label)
        if task is not None:
            done = self._bar.tasks[task].completed
            self._bar.update(task, total=done, completed=done)

    def __exit__(self, *exc) -> None:
        if self.live:
            for label in self._tasks:
                self._finish(label)
            self._bar.stop()
        elif exc[0] is None:
            for label, line in self._last.items():
                if self._printed.get(label) != line:
                    console.print(f"{label}: {line}", highlight=False, soft_wrap=True)

    def __call__(self, label: str, batch) -> None:
        from mimic.tasks.registry import get_task
        from mimic.trials.report import progress_status

        status = progress_status(get_task(batch.task), batch, self.minutes, self.runs)
        self._last[label] = status
        if self.live:
            if not self._bar.live.is_started:
                self._bar.start()
            if label not in self._tasks:
                for previous in self._tasks:  # variants run one after another
                    self._finish(previous)
                self._tasks[label] = self._bar.add_task(
                    label, total=self.minutes or self.runs, status=""
                )
            done = batch.simulated_s / 60 if self.minutes else len(batch.episodes)
            self._bar.update(
                self._tasks[label], completed=min(done, self.minutes or self.runs), status=status
            )
            return
        now = time.monotonic()
        if not batch.episodes:  # a variant's start: nothing to say yet
            return
        if now - self._printed_at >= PLAIN_PROGRESS_EVERY_S:
            console.print(f"{label}: {status}", highlight=False, soft_wrap=True)
            self._printed[label], self._printed_at = status, now


def _disturb(level: str | None, world: str) -> str:
    """``--disturb``, or the default: ``game`` where mimic steps the physics itself, ``none``
    on a league server (its physics is in another process)."""
    from mimic.episode.disturbance import DEFAULT_DISTURB, disturb_level
    from mimic.world.registry import world_owns_physics

    if level is not None:
        disturb_level(level)  # an unknown level: one line before anything runs
        return level
    return DEFAULT_DISTURB if world_owns_physics(world) else "none"


def _ci_text(row: dict, column: str, how: str) -> str:
    low, high = row.get(column + "_ci_low"), row.get(column + "_ci_high")
    if low is None or high is None or not (math.isfinite(low) and math.isfinite(high)):
        return ""
    if how.startswith("range"):
        return f"{low:.0f}-{high:.0f}" + ("%" if how.endswith("%") else "")
    return f"±{_rounding_to_zero((high - low) / 2):.2g}"


#: Below this a printed spread or mean is floating-point rounding, not a measurement.
_ROUNDING = 1e-9


def _rounding_to_zero(value: float) -> float:
    """0 for a value within rounding of it: the spread of runs that all took the same time
    comes out of floating-point sums as about 1e-15, not 0."""
    return 0.0 if abs(value) < _ROUNDING else value


def _number(column: str, value) -> str:
    if not isinstance(value, float):
        return str(value)
    value = _rounding_to_zero(value)
    return f"{value:.2f}" if column.endswith("_ratio") else f"{value:.3g}"


def _world_text(result) -> str:
    """How the table's episodes were played, for its title: the world, what the task says of
    how it played (a kick: how the robot reached the ball) and the disturbances."""
    from mimic.world.registry import MUJOCO, get_world

    row = result.summary.row(0, named=True)
    world = get_world(row.get("world") or MUJOCO).title
    how = result.task.played(row)
    disturb = row.get("disturb")
    return world + (f", {how}" if how else "") + (f"; disturbances: {disturb}" if disturb else "")


def _minutes_text(result, minutes: float | None) -> str:
    """The simulated minutes each variant counted (a kick trial its budget; a walk trial its
    runs that ended within it, so less): ``1.26-1.9 simulated min per variant (2 asked)``."""
    ran = [v for v in result.summary.get_column("simulated_min").to_list() if v is not None]
    if not ran:
        return f"{minutes:g} simulated min asked per variant"
    low, high = min(ran), max(ran)
    span = f"{low:.3g}" if f"{low:.3g}" == f"{high:.3g}" else f"{low:.3g}-{high:.3g}"
    return f"{span} simulated min per variant ({minutes:g} asked)"


def _print(result, title: str, config=None) -> None:
    """The summary as the task shows it (``TrialTask.columns``), each mean and rate with its
    95 % interval on a dim line below, then the task's legend (filled in from ``config``,
    the trial's settings; None: the task's defaults) and the files written."""
    task = result.task
    shown = [c for c in task.columns if c.key in result.summary.columns]
    # Headers on two lines, no vertical rules, no edges: a whole kick table, confidence
    # intervals included, fits in 80 columns.
    table = Table(
        title=title, box=box.SIMPLE_HEAD, pad_edge=False, padding=(0, 1, 0, 0), show_edge=False
    )
    for c in shown:
        table.add_column(
            c.header.replace(" ", "\n"),
            justify="left" if c.key == "variant" else "right",
            overflow="fold" if c.key == "variant" else "ellipsis",
            no_wrap=c.key != "variant",
        )
    for row in result.summary.iter_rows(named=True):
        table.add_row(*[_number(c.key, row[c.key]) for c in shown])
        ci = [_ci_text(row, c.ci, c.ci_how) if c.ci else "" for c in shown]
        if any(ci):
            table.add_row(*(["  95% CI"] + ci[1:]), style="dim")
    console.print(table)
    legend = task.legend.format_map(asdict(task.Config() if config is None else config))
    console.print(legend, style="dim", highlight=False)
    for f in result.files:
        console.print(f"wrote {f}", highlight=False)


def _dashboard(result, save: Path | None, rerun: bool, force: bool) -> None:
    from mimic.viz.trials import save_trial_dashboard, show_trial_dashboard

    if save:
        save_trial_dashboard(result, save, overwrite=force)
        console.print(f"wrote {save}", highlight=False)
    if rerun:
        try:
            show_trial_dashboard(result)
        except Exception as exc:  # no viewer binary or no display: the tables stand anyway
            reason = (str(exc).strip().splitlines() or [type(exc).__name__])[0]
            raise MimicError(
                f"could not open a Rerun viewer ({reason}); use --save FILE and "
                "open it with `rerun FILE` where a display is available"
            ) from exc


def _check(
    task: str,
    specs,
    out: Path | None,
    save: Path | None,
    force: bool,
    rerun: bool = False,
    keep: Path | None = None,
    **trial_options,
) -> None:
    """Before the first episode: options, every variant, and the outputs (they can be
    written, and do not exist unless --force)."""
    from mimic.files import check_outputs, spec_files
    from mimic.model.model_file import SUFFIX
    from mimic.trials.api import check_trial, keep_candidates, trial_files

    check_trial(task, specs, **trial_options)
    if keep is not None:
        keep_candidates(task, specs)
        if keep.suffix != SUFFIX:
            raise MimicError(f"--keep-best {keep}: a model file's name ends in {SUFFIX}")
    check_outputs(
        [*trial_files(out), save, keep],
        force=force,
        inputs=spec_files(*(s.ref for s in specs)),
    )
    if rerun:
        from mimic.viz.display import require_viewer

        require_viewer("--save FILE.rrd")


#: The options every trial command has, in order (name -> annotated type, default).
_COMMON_OPTIONS = {
    "variants": (Annotated[list[str] | None, _VARIANTS], None),
    "compare": (Annotated[bool, _COMPARE], False),
    "motion": (Annotated[str | None, _MOTION], None),
    "model": (Annotated[str | None, _MODEL], None),
}
_RUN_OPTIONS = {
    "seed": (Annotated[int, _SEED], 0),
    "workers": (Annotated[int | None, WORKERS], None),
    "balance": (
        Annotated[bool, typer.Option(help="Wrap learned motions in balance feedback.")],
        False,
    ),
}
_SPEED_OPTIONS = {
    "speed_rate": (
        Annotated[
            float, typer.Option(help="Phase-rate multiplier for learned cyclic motions, > 0.")
        ],
        1.0,
    ),
    "vx": (
        Annotated[
            float | None,
            typer.Option(
                "--vx",
                help="Forward speed command \\[m/s] for every variant that takes one (learned "
                "walks, the other team's walks); default: each its own.",
                show_default=False,
            ),
        ],
        None,
    ),
}
_OUTPUT_OPTIONS = {
    "out": (
        Annotated[Path | None, typer.Option("--out", "-o", help="Parquet file of every event.")],
        None,
    ),
    "save": (Annotated[Path | None, typer.Option("--save", help=_SAVE_HELP)], None),
    "save_old": (Annotated[Path | None, SAVE_OLD], None),
    "rerun": (Annotated[bool, _RERUN], False),
    "force": (Annotated[bool, FORCE], False),
    "ray": (Annotated[bool, RAY], False),
    "ray_address": (Annotated[str | None, RAY_ADDRESS], None),
    "world": (Annotated[str, WORLD], "mujoco"),
    "robot": (Annotated[str | None, ROBOT], None),
    "disturb": (Annotated[str | None, DISTURB], None),
}


def _budget_options(task) -> dict:
    """``--minutes`` and/or ``--runs``, as the task counts its budget."""
    out = {}
    if task.by_minutes:
        default = task.minutes
        help_text = "Simulated minutes per variant, > 0."
        out["minutes"] = (
            Annotated[
                float | None,
                typer.Option(help=help_text, show_default=default is not None),
            ],
            default,
        )
    if task.runs is not None:
        help_text = "Runs per variant, >= 1" + (
            f" (instead of minutes; default {task.runs})." if task.by_minutes else "."
        )
        default = None if task.by_minutes else task.runs
        out["runs"] = (
            Annotated[int | None, typer.Option(help=help_text, show_default=default is not None)],
            default,
        )
    return out


def _task_options(task) -> dict:
    """The options of the task's own settings (``TrialTask.options``)."""
    return {
        o.field: (
            Annotated[o.type | None, typer.Option(o.flag, help=o.help, show_default=False)],
            None,
        )
        for o in task.options
    }


def _keep_options(task) -> dict:
    """``--keep-best`` for a trial that ranks its variants (``TrialTask.rank``)."""
    if task.rank is None:
        return {}
    help_text = (
        f"Copy the best learned model (.mimic) of the variants to this file ({task.rank_says}; "
        "a tie: the one given first)."
    )
    return {
        "keep_best": (
            Annotated[Path | None, typer.Option("--keep-best", help=help_text, show_default=False)],
            None,
        )
    }


def _trial_command(task):
    """``mimic trial NAME`` for a task: its options are the ones every trial has, its budget
    (``--minutes``/``--runs``) and its own settings (``TrialTask.options``)."""
    params = {
        **_COMMON_OPTIONS,
        **_budget_options(task),
        **_RUN_OPTIONS,
        **(_SPEED_OPTIONS if task.speed_command else {}),
        **_OUTPUT_OPTIONS,
        **_keep_options(task),
        **_task_options(task),
    }

    def command(**given) -> None:
        _play_trial(task, given)

    command.__signature__ = inspect.Signature(
        [
            inspect.Parameter(name, inspect.Parameter.KEYWORD_ONLY, default=d, annotation=a)
            for name, (a, d) in params.items()
        ]
    )
    command.__annotations__ = {name: a for name, (a, _) in params.items()}
    command.__doc__ = task.summary
    command.__name__ = task.name
    return reports_errors(command)


def _play_trial(task, given: dict) -> None:
    """One trial command: the variants, the task's config from the options, every check
    before the first episode, the episodes with a progress bar, the table and the files."""
    from mimic.trials.api import run_trial
    from mimic.world.registry import world_kind

    save = save_path(given["save"], given["save_old"])
    minutes, runs = given.get("minutes"), given.get("runs")
    if minutes is not None and runs is not None:
        raise MimicError("give --minutes or --runs, not both")
    if minutes is None and runs is None:
        runs = task.runs
    world = world_kind(given["world"])
    names = [*(given["variants"] or []), given["motion"], given["model"]]
    robot = _trial_robot(given["robot"], world, names)
    settings = {o.field: given[o.field] for o in task.options if given[o.field] is not None}
    config = task.Config(world=world, disturb=_disturb(given["disturb"], world), **settings)
    vx = given.get("vx")
    specs = _specs(
        given["variants"],
        given["compare"],
        given["motion"],
        given["model"],
        given["balance"],
        given.get("speed_rate", 1.0),
        task.default_variant(robot, config),
        robot,
        None if vx is None else options.finite(vx, "--vx", above=0),
    )
    seed, workers, force = given["seed"], given["workers"], given["force"]
    keep = given.get("keep_best")
    _check(
        task.name,
        specs,
        given["out"],
        save,
        force,
        given["rerun"],
        keep,
        minutes=minutes,
        runs=runs,
        seed=seed,
        workers=workers,
        config=config,
    )
    with (
        open_executor(workers, given["ray"], given["ray_address"]) as executor,
        TrialProgress(minutes, runs) as progress,
    ):
        result = run_trial(
            task,
            specs,
            minutes=minutes,
            runs=runs,
            seed=seed,
            executor=executor,
            out=given["out"],
            progress=progress,
            trace=bool(save or given["rerun"]),
            overwrite=force,
            config=config,
        )
    budget = _minutes_text(result, minutes) if minutes else f"{runs} runs per variant"
    _print(result, f"{task.title(config)}, {budget}, seed {seed}; {_world_text(result)}", config)
    _dashboard(result, save, given["rerun"], force)
    if keep is not None:
        _keep_best(result, specs, keep, force)


def _keep_best(result, specs, path: Path, force: bool) -> None:
    """``--keep-best``: the best learned model copied to ``path``, and one line on why."""
    from mimic.trials.api import keep_best, keep_candidates

    best, _ = keep_best(result, specs, path, overwrite=force)
    played = ", played inside the balance layer" if best.balance else ""
    console.print(
        f"kept {best.ref} as {path}{played}: the best of "
        f"{len(keep_candidates(result.kind, specs))} learned models ({result.task.rank_says})",
        highlight=False,
        markup=False,
        soft_wrap=True,  # one line, however long the paths
    )


def _bench_league(
    seconds: Annotated[float, typer.Option(help="Simulated seconds per world, > 0.")] = 20.0,
    kick: Annotated[
        str | None,
        typer.Option(
            help="The T1's kick (motion name or file; default: its shipped kick_right, else it "
            "stands).",
            show_default=False,
        ),
    ] = None,
) -> None:
    """Speed of the league world in process, on a hosted server and of our MuJoCo world, the
    same work in one run (stand, kick, stand while the ball rolls), beside bare MuJoCo
    stepping of the league's T1 model."""
    from mimic import options
    from mimic.trials.world_speed import bench_worlds, format_world_speeds

    options.finite(seconds, "--seconds", above=0)
    rows = bench_worlds(seconds=seconds, kicks={"t1": kick} if kick else None)
    console.print(format_world_speeds(rows), highlight=False)
    console.print(
        "bare: mj_step of the league's T1 model alone (standing); bare-same: mj_step alone "
        "taking the league world's own physics steps of the kick; league: its simulation in this "
        "process; league-server: a hosted server. RTF: simulated s per wall s; +start: the "
        "same with opening and closing the world (the server's: hosting and joining it, once "
        "per trial episode); CPU/sim: CPU s per simulated s, the server's included; xbare: "
        "simulated s per CPU s as a ratio of bare stepping's.",
        style="dim",
        highlight=False,
    )


def register(app: typer.Typer) -> None:
    from mimic.tasks.registry import TASKS

    for task in TASKS.values():
        trial_app.command(task.name)(_trial_command(task))
    app.add_typer(trial_app, name="trial")
    from mimic.cli.train import bench_app

    bench_app.command("league")(reports_errors(_bench_league))
