"""`mimic improve` (CMA-ES on a motion, a learned model or the other team's walk parameters)
and `mimic bench scaling` (episodes per second: process pool against Ray)."""

from __future__ import annotations

from dataclasses import fields
from enum import Enum
from pathlib import Path
from typing import Annotated

import typer
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

from mimic.cli.common import FORCE, ROBOT, SUCCESS_M, WORLD, console, reports_errors
from mimic.cli.executor_options import RAY, RAY_ADDRESS, WORKERS, check_workers
from mimic.errors import MimicError
from mimic.tasks.registry import TASKS, get_task

__all__ = ["register"]


#: The objectives: every trial task's (``tasks.registry``).
ObjectiveName = Enum("ObjectiveName", {name: name for name in TASKS}, type=str)


class Pick(str, Enum):
    best = "best"
    mean = "mean"


def _search_bar(budget: int):
    progress = Progress(
        TextColumn("[bold]{task.description}"),
        BarColumn(),
        TextColumn("{task.fields[status]}"),
        TimeElapsedColumn(),
        console=console,
        disable=not console.is_terminal,  # no bar, and no blank line, in a pipe
    )
    task = progress.add_task("search", total=budget, status="")

    def update(result) -> None:
        progress.start()  # on the first generation: bad input fails before any bar shows
        g = result.generations[-1]
        _, best, _ = result.best
        progress.update(
            task,
            completed=min(result.evaluations, budget),
            status=f"{result.evaluations}/{budget} evaluations, generation "
            f"{g.index}: best {g.scores.max():.3f}, overall {best:.3f}",
        )

    return progress, update


def _stop(shown: Progress) -> None:
    """Stop a progress display (the search's, once the validation starts)."""
    if shown.live.is_started:
        shown.stop()


def _improve(
    target: Annotated[
        str,
        typer.Argument(
            help="What to improve: a keyframe motion (name or "
            ".txt), a learned model (.mimic, +balance), "
            "other-team-walk or a .json parameter file.",
            show_default=False,
        ),
    ],
    objective: Annotated[
        ObjectiveName,
        typer.Option(
            help="kick: distance x accuracy, falls "
            "penalised; walk: speed over 15 m, falls "
            "and drift penalised.",
            show_default=False,
        ),
    ],
    budget: Annotated[
        int,
        typer.Option(help="Candidate evaluations in all (whole generations).", show_default=False),
    ],
    out: Annotated[
        Path,
        typer.Option(
            "--out",
            "-o",
            help="The improved motion (.txt), model (.mimic) or parameter file (.json).",
            show_default=False,
        ),
    ],
    seed: Annotated[int, typer.Option(help="Seeds the search and its episodes.")] = 0,
    episodes: Annotated[
        int | None, typer.Option(help="Trial episodes per evaluation (default: kick 2, walk 4).")
    ] = None,
    validate: Annotated[
        int | None,
        typer.Option(
            help="Held-out validation episodes, never "
            "played in the search (default: kick 12, "
            "walk 40; 0: none)."
        ),
    ] = None,
    compare: Annotated[
        list[str] | None,
        typer.Option(
            help="Reference variants at the head of the validation table, e.g. kick_right."
        ),
    ] = None,
    joints: Annotated[
        str,
        typer.Option(
            help="Joints a motion or model may change: legs, all, or names separated by commas."
        ),
    ] = "legs",
    window: Annotated[
        str | None,
        typer.Option(
            metavar="START,END",
            help="A learned one-shot model: its offsets and gains act only from START to END "
            "(seconds of the motion), and its time warp from START on, e.g. where the copy fails "
            "(the model file keeps the network as learned and the correction, exact). auto "
            "(--objective getup): the stand window, from just before the copy is first upright "
            "(or highest) in its own runs to its end.",
        ),
    ] = None,
    follow: Annotated[
        Path | None,
        typer.Option(
            metavar="REC.mcap",
            help="--objective getup, a learned copy of REC: fit its references in the trial's "
            "simulation until it follows REC (iterative learning control, from just after it "
            "first lies face down to its end, at REC's own speed; fitted on the joints alone "
            "and with REC's torso pitch on the hips, then, if the copy does not rise, both "
            "again with a 1 s front that each run mends for itself; the fit that follows "
            "further kept); "
            "--budget: rounds per fit, --episodes: runs per round (default 3). No search, no "
            "validation.",
        ),
    ] = None,
    pick: Annotated[
        Pick,
        typer.Option(
            help="Write the best candidate scored, or the "
            "optimiser's final mean (steadier under noisy "
            "scores)."
        ),
    ] = "best",
    fall_penalty: Annotated[
        float | None,
        typer.Option(
            help="Score lost per fall: kick, metres per fall per kick (default 2); walk, m/s "
            "per share of runs that fell (default 1)."
        ),
    ] = None,
    sigma: Annotated[float, typer.Option(help="Initial CMA-ES step, in parameter scales.")] = 1.0,
    population: Annotated[
        int | None, typer.Option(help="Candidates per generation (default: 4 + 3 ln d).")
    ] = None,
    checkpoint: Annotated[
        Path | None,
        typer.Option(help="Checkpoint to resume from and write (default: OUT.ckpt.json)."),
    ] = None,
    save: Annotated[
        Path | None,
        typer.Option(
            help="Save a Rerun .rrd: fitness curve, every "
            "candidate, the improved candidate's held-out "
            "episode in 3D."
        ),
    ] = None,
    workers: Annotated[int | None, WORKERS] = None,
    ray: Annotated[bool, RAY] = False,
    ray_address: Annotated[str | None, RAY_ADDRESS] = None,
    world: Annotated[str, WORLD] = "mujoco",
    robot: Annotated[str | None, ROBOT] = None,
    success_m: Annotated[float | None, SUCCESS_M] = None,
    force: Annotated[bool, FORCE] = False,
    keep_worse: Annotated[
        bool,
        typer.Option(
            "--keep-worse",
            help="Write the improved candidate even when it validates worse than the "
            "starting point (default: write the starting point then).",
        ),
    ] = False,
) -> None:
    """Improve a motion with CMA-ES, scored by trial episodes; validate on held-out episodes;
    a result that validates worse than the starting point is not kept (--keep-worse)."""
    from mimic import options
    from mimic.cli.trial import TrialProgress, _print, _world_text
    from mimic.files import check_outputs, spec_files
    from mimic.improve import improve
    from mimic.improve.objectives import make_objective
    from mimic.trials.executors import RAY_LOCAL

    if budget <= 0:
        raise MimicError(f"--budget must be > 0 evaluations, got {budget}")
    options.seed(seed)
    check_outputs([out, save], force=force, inputs=[*spec_files(target), checkpoint, follow])
    options.finite(sigma, "--sigma", above=0)
    task = get_task(objective.value)
    settings = {}
    if fall_penalty is not None:
        options.finite(fall_penalty, "--fall-penalty", at_least=0)
        if task.Objective.fall_penalty_setting is None:
            raise MimicError(
                f"--fall-penalty is a rule of objectives that count falls; {task.name} does not"
            )
        settings[task.Objective.fall_penalty_setting] = fall_penalty
    if success_m is not None:
        if "success_distance_m" not in {f.name for f in fields(task.Config)}:
            raise MimicError(f"--success-m is the kick objective's rule; drop it for {task.name}")
        options.finite(success_m, "--success-m", at_least=0)
        settings["trial_config"] = task.Config(success_distance_m=success_m)
    n_validate = task.validation_episodes if validate is None else validate
    bar, on_generation = _search_bar(budget)
    checks = TrialProgress(None, n_validate)  # the held-out episodes, as a trial shows them

    def before_search(tgt, obj, pop) -> None:
        console.print(
            f"{tgt.label}: {tgt.space.dim} parameters, {pop} candidates per "
            f"generation, {obj.episodes} {obj.name} episodes per evaluation",
            highlight=False,
        )
        if getattr(tgt, "window_s", None) is not None:
            lo, hi = tgt.window_s
            console.print(f"correction window: {lo:.2f}-{hi:.2f} s of the motion", highlight=False)

    if follow is not None:
        search_only = {
            "--validate": validate is not None,
            "--compare": bool(compare),
            "--pick": Pick(pick) != Pick.best,
            "--fall-penalty": fall_penalty is not None,
            "--sigma": sigma != 1.0,
            "--population": population is not None,
            "--checkpoint": checkpoint is not None,
            "--save": save is not None,
            "--ray": ray or ray_address is not None,
            "--success-m": success_m is not None,
            "--keep-worse": keep_worse,
        }
        given = [name for name, set_ in search_only.items() if set_]
        if given:
            raise MimicError(
                f"--follow fits in rounds, without a search or validation: drop {', '.join(given)}"
            )
        _follow(target, follow, task, budget, episodes, seed, joints, window, world, robot, out)
        return
    workers = check_workers(workers, ray or bool(ray_address))
    try:  # improve() checks every input before it starts workers
        run = improve(
            target,
            objective=make_objective(objective.value, episodes, **settings),
            budget=budget,
            out=out,
            seed=seed,
            episodes=episodes,
            sigma=sigma,
            population=population,
            joints=joints,
            window_s=_window(window),
            pick=Pick(pick).value,
            validation_episodes=n_validate,
            references=tuple(compare or ()),
            checkpoint=checkpoint,
            workers=workers,
            ray=(ray_address or RAY_LOCAL) if ray or ray_address else None,
            on_generation=on_generation,
            before_search=before_search,
            on_validation=lambda label, b: (_stop(bar), checks(label, b)),
            world=world,
            robot=robot,
            keep_worse=keep_worse,
        )
    finally:
        _stop(bar)
        checks.__exit__(None, None, None)
    z, score, generation = run.search.best
    resumed = (
        f", {run.search.resumed} generations from the checkpoint" if run.search.resumed else ""
    )
    console.print(
        f"search: {run.search.evaluations} evaluations in {run.search_wall_s:.1f} s"
        f"{resumed}; best score {score:.4g} (generation {generation})",
        highlight=False,
    )
    if run.stand_window is not None:
        console.print(run.stand_window.describe(), highlight=False)
    console.print(f"wrote {run.out}")
    if run.validation is not None:
        _print(
            run.validation,
            f"validation: {n_validate} held-out episodes per variant, "
            f"seed {seed} ({run.validation_wall_s:.1f} s); {_world_text(run.validation)}",
            run.objective.trial_config,
        )
        for f in run.files:
            console.print(f"wrote {f}")
    if save:
        from mimic.viz.improve import save_improve

        save_improve(run, save)
        console.print(f"wrote {save}")
    verdict = _verdict(run)
    if verdict:
        console.print(verdict, highlight=False, soft_wrap=True)


def _follow(target, recording, task, rounds, runs, seed, joints, window, world, robot, out):
    """``--follow REC``: the copy's references fitted until it follows its recording."""
    from mimic.agents.registry import agent_spec
    from mimic.files import input_file
    from mimic.improve.follow import FollowConfig, follow_recording
    from mimic.improve.targets import resolve_joints
    from mimic.model.model_file import load_model, save_model
    from mimic.world.registry import check_world, default_robot

    if task.name != "getup":
        raise MimicError(
            f"--follow fits a get-up copy; it needs --objective getup, not {task.name}"
        )
    if window is not None:
        raise MimicError("--follow places its own window; drop --window")
    input_file(recording, "recording", "give the .mcap the copy was learned from")
    spec = agent_spec(target, robot=robot or default_robot(world))
    if spec.kind != "model" or spec.balance:
        raise MimicError(f"--follow fits a learned model (.mimic), not {target!r}")
    model = load_model(spec.ref)
    check_world(world, model.robot)
    config = FollowConfig(rounds=rounds, runs=3 if runs is None else runs, seed=seed)

    def show(r) -> None:
        followed = " ".join(f"{v:.2f}" for v in r.followed_s)
        console.print(
            f"round {len(shown) + 1}: followed to {followed} s, torso highest "
            f"{max(r.highest_m):.2f} m, error {r.error_rad:.3f} rad"
            + (" (torso term)" if r.torso_gain else "")
            + ("" if r.kept else " (undone)"),
            highlight=False,
        )
        shown.append(r)

    shown: list = []
    result = follow_recording(
        model,
        recording,
        resolve_joints(model.robot, joints),
        task.Config(world=world),
        config,
        on_round=show,
    )
    save_model(result.model, out)
    console.print(result.describe(), highlight=False)
    console.print(f"wrote {out}")


def _verdict(run) -> str:
    """The last line: whether the improved candidate held up on held-out episodes."""
    if run.start_score is None or run.improved_score is None:
        return ""
    scores = f"score {run.improved_score:.4g} against the starting point's {run.start_score:.4g}"
    if not run.validated_worse:
        return f"the improved candidate validated better: {scores} on held-out episodes"
    if run.kept_start:
        return (
            f"the improved candidate validated WORSE ({scores}); kept the starting point: "
            f"{run.out} holds it (--keep-worse writes the candidate instead)"
        )
    return (
        f"the improved candidate validated WORSE ({scores}); wrote it anyway (--keep-worse) "
        f"to {run.out}"
    )


def _bench_scaling(
    episodes: Annotated[int, typer.Option(help="Timed episodes per measurement.")] = 8,
    ray: Annotated[
        bool | None,
        typer.Option(
            "--ray/--no-ray",
            help="Measure Ray too (needs the ray extra; default: when it is installed).",
            show_default=False,
        ),
    ] = None,
) -> None:
    """Episodes per second for 1 and 2 local workers, process pool against Ray."""
    import importlib.util

    from mimic.trials.scaling import bench_scaling, format_scaling

    if episodes < 1:
        raise MimicError(f"--episodes must be >= 1, got {episodes}")
    if ray is None:
        ray = importlib.util.find_spec("ray") is not None
        if not ray:
            console.print(
                'Ray is not installed: the process pool only (pip install -e ".[ray]" for Ray)',
                highlight=False,
                markup=False,
            )
    console.print(format_scaling(bench_scaling(episodes=episodes, ray=ray)), highlight=False)


def register(app: typer.Typer) -> None:
    app.command("improve")(reports_errors(_improve))
    from mimic.cli.train import bench_app

    bench_app.command("scaling")(reports_errors(_bench_scaling))


def _window(text: str | None) -> tuple[float, float] | str | None:
    """``--window START,END`` as two times [s], or ``auto``; one line for anything else."""
    if text is None or text == "auto":
        return text
    try:
        lo, hi = (float(v) for v in text.split(","))
    except ValueError:
        raise MimicError(
            f"--window takes START,END in seconds (e.g. 4.3,10.3) or auto; got {text!r}"
        ) from None
    return lo, hi
