"""An improve run in Rerun: the fitness curve per generation, every candidate's score, and the
validation (the trial dashboard, with the improved candidate's first held-out episode in 3D)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import rerun as rr
import rerun.blueprint as rrb

from mimic.viz.paths import WORLD
from mimic.viz.save import save_rrd
from mimic.viz.trials import log_trial

__all__ = ["log_improve", "improve_blueprint", "save_improve"]

_GENERATION = "generation"
_EVALUATION = "evaluation"
_SCORE = "improve/score"
# Where ``viz.trials`` replays a variant's traced episode.
_REPLAY = f"{WORLD}/replay"


def _slug(label: str) -> str:
    return "".join(c if c.isalnum() else "_" for c in label).strip("_")


def log_improve(rec: rr.RecordingStream, run) -> None:
    """Everything of an ``improve.ImproveRun`` onto ``rec``."""
    generations = run.search.generations
    index = [rr.TimeColumn(_GENERATION, sequence=[g.index for g in generations])]
    best = np.array([g.scores.max() for g in generations])
    curves = {
        "best": best,
        "mean": np.array([g.scores.mean() for g in generations]),
        "best_so_far": np.maximum.accumulate(best),
    }
    for name, values in curves.items():
        rec.send_columns(
            f"{_SCORE}/{name}", indexes=index, columns=rr.Scalars.columns(scalars=values)
        )
    scores = np.concatenate([g.scores for g in generations])
    rec.send_columns(
        "improve/candidates",
        indexes=[rr.TimeColumn(_EVALUATION, sequence=np.arange(len(scores)))],
        columns=rr.Scalars.columns(scalars=scores),
    )
    z, score, generation = run.search.best
    text = (
        f"# {run.target.label}: {run.objective.name} objective\n\n"
        f"{run.search.evaluations} evaluations, best score {score:.4g} "
        f"(generation {generation})\n\n```json\n"
        f"{json.dumps(run.target.space.describe(z), indent=1)}\n```\n"
    )
    rec.log("improve/best", rr.TextDocument(text, media_type="text/markdown"), static=True)
    if run.validation is not None:
        log_trial(rec, run.validation)


def improve_blueprint(run) -> rrb.Blueprint:
    """Fitness curves and candidates on the left; the improved episode in 3D and the
    validation table on the right."""
    left = [
        rrb.TimeSeriesView(origin=_SCORE, name="score per generation"),
        rrb.TimeSeriesView(origin="improve/candidates", name="every candidate"),
        rrb.TextDocumentView(origin="improve/best", name="best candidate"),
    ]
    right = []
    if run.validation is not None:
        right += [
            rrb.Spatial3DView(
                origin=WORLD,
                name=f"held-out episode: {label}",
                contents=[f"{WORLD}/field/**", f"{_REPLAY}/{_slug(label)}/**"],
            )
            for label in run.validation.traces
        ]
        right.append(rrb.TextDocumentView(origin="summary", name="validation"))
    return rrb.Blueprint(
        rrb.Horizontal(rrb.Vertical(*left), *([rrb.Vertical(*right)] if right else []))
    )


def save_improve(run, path: Path) -> None:
    """Write the run to an .rrd file with its blueprint (moved into place when complete)."""

    rec = rr.RecordingStream("mimic_improve")
    save_rrd(rec, path, lambda: log_improve(rec, run), blueprint=improve_blueprint(run))
