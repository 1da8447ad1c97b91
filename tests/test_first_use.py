"""What a new user meets (#31, section 3; #30 item 4): no hangs without a display, results that
say when they are worse, trials that say what ran, one-line errors for every bad value, and
`mimic play` that records the torso and ball and says what happened."""

from __future__ import annotations

import json
import zipfile

import numpy as np
import pytest
from _cli_helpers import one_line_error
from _learn_helpers import joint_frame, smooth_motion
from typer.testing import CliRunner

from mimic.cli.main import app
from mimic.errors import ModelFileError
from mimic.learn.dataset import dataset_from_frame
from mimic.learn.presets import FAST
from mimic.learn.train import TrainConfig, train_model
from mimic.model.model_file import describe_model, load_model, save_model

runner = CliRunner()
_one_line_error = one_line_error


@pytest.fixture(scope="module")
def model_path(tmp_path_factory):
    t, q = smooth_motion(30)
    ds = dataset_from_frame(joint_frame(t, q), metadata={"motion": "wave", "team": "mimic"})
    path = tmp_path_factory.mktemp("model") / "wave.mimic"
    return save_model(train_model(ds, TrainConfig(FAST, seed=0, epochs=20)), path)


def _edited(model_path, tmp_path, field, value):
    """A copy of the model whose meta.json has ``field`` set to ``value`` (or removed)."""
    out = tmp_path / "edited.mimic"
    with zipfile.ZipFile(model_path) as src, zipfile.ZipFile(out, "w") as dst:
        for item in src.infolist():
            data = src.read(item)
            if item.filename == "meta.json":
                meta = json.loads(data)
                if value is _REMOVE:
                    meta.pop(field, None)
                else:
                    meta[field] = value
                data = json.dumps(meta).encode()
            dst.writestr(item, data)
    return out


_REMOVE = object()
_EDITS = [
    (field, value)
    for field in (
        "format_version",
        "robot",
        "joint_names",
        "input_kind",
        "input_offset_s",
        "input_scale_per_s",
        "period_s",
        "duration_s",
        "layout",
        "metrics",
        "source",
        "preset",
    )
    for value in (_REMOVE, "x", [1, 2], True)
] + [
    ("layout", {"in_dim": "1", "out_dim": 23, "hidden": [8]}),
    ("layout", {"in_dim": 1, "out_dim": 23, "hidden": "8"}),
    ("layout", {"in_dim": 1, "out_dim": 23}),
    ("metrics", {"mae_rad_per_joint": [1, 2]}),
    ("joint_names", [1] * 22),
]


@pytest.mark.parametrize("field, value", _EDITS)
def test_an_edited_meta_json_is_one_line_never_a_traceback(model_path, tmp_path, field, value):
    path = _edited(model_path, tmp_path, field, value)
    for read in (load_model, describe_model):
        try:
            read(path)
        except ModelFileError as err:
            assert "\n" not in str(err) and str(path) in str(err)
    for args in (["info", str(path)], ["info", str(path), "--json"]):
        result = runner.invoke(app, args)
        assert result.exception is None or isinstance(result.exception, SystemExit), (
            f"{result.exception!r}: {result.output}"
        )
        if result.exit_code:
            _one_line_error(result, 2, str(path))


# --- mimic view without a display ---------------------------------------------------------


@pytest.fixture(scope="module")
def stand_recording(tmp_path_factory):
    rec = tmp_path_factory.mktemp("rec") / "stand.mcap"
    result = runner.invoke(app, ["record", "stand", "-o", str(rec), "--duration", "0.5"])
    assert result.exit_code == 0, result.output
    return rec


def test_view_without_a_display_says_so_and_how_to_save(stand_recording, monkeypatch):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    monkeypatch.setattr("sys.platform", "linux")
    # No viewer is running either (one on this machine's port would be used instead).
    monkeypatch.setattr("mimic.viz.display._viewer_running", lambda *a, **k: False)
    result = runner.invoke(app, ["view", str(stand_recording)])
    _one_line_error(result, 2, "no display", "--save stand.rrd")


def test_a_display_or_a_running_viewer_counts():
    from mimic.viz.display import has_display

    assert not has_display({}, "linux")
    assert has_display({"DISPLAY": ":0"}, "linux")
    assert has_display({"WAYLAND_DISPLAY": "wayland-0"}, "linux")
    assert has_display({}, "darwin") and has_display({}, "win32")


# --- mimic improve: a result worse than the start is not kept --------------------------------


@pytest.mark.parametrize("keep_worse", [False, True])
def test_improve_keeps_the_start_when_its_result_validates_worse(tmp_path, monkeypatch, keep_worse):
    import dataclasses

    import polars as pl

    from mimic.improve import run as improve_run
    from mimic.improve.objectives import OBJECTIVES
    from mimic.improve.targets import load_target
    from mimic.tasks.walk import WalkObjective, WalkTrialConfig

    tiny = WalkObjective(episodes=1, trial_config=WalkTrialConfig(timeout_s=3.0))
    monkeypatch.setitem(OBJECTIVES, "walk", lambda **kw: dataclasses.replace(tiny, **kw))
    real = improve_run.validate

    def validated_worse(specs, objective, **kw):  # the held-out episodes went badly
        result = real(specs, objective, **kw)
        labels = result.summary["variant"].to_list()
        scores = [0.2 if label.endswith("(improved)") else 1.0 for label in labels]
        result.summary = result.summary.with_columns(pl.Series("score", scores))
        return result

    monkeypatch.setattr(improve_run, "validate", validated_worse)
    monkeypatch.chdir(tmp_path)
    args = ["improve", "other-team-walk", "--objective", "walk", "--budget", "4"]
    args += ["--episodes", "1", "--validate", "1", "--workers", "1", "-o", "walk.json"]
    result = runner.invoke(app, args + (["--keep-worse"] if keep_worse else []))
    assert result.exit_code == 0, result.output
    last = result.output.strip().splitlines()[-1]
    assert "validated WORSE" in last and "0.2" in last and "1" in last, last
    target = load_target("other-team-walk")
    start = json.loads(
        target.write(np.zeros(target.space.dim), tmp_path / "s.json", {}).read_text()
    )
    written = json.loads((tmp_path / "walk.json").read_text())
    if keep_worse:
        assert "wrote it anyway" in last and written["params"] != start["params"]
    else:
        assert "kept the starting point" in last and written["params"] == start["params"]
        assert written["provenance"]["kept_start"] is True


# --- trials: what ran, and one robot ----------------------------------------------------------


def _batch(*durations_s):
    from mimic.tasks.base import EpisodeBatch

    batch = EpisodeBatch([], [], task="kick")
    for i, d in enumerate(durations_s):
        batch.add([{"distance_m": 1.0}], {"episode": i, "duration_s": d, "falls": 0, "kicks": 1})
    return batch


def test_progress_never_shows_more_than_the_budget():
    from mimic.tasks.kick import KickTask
    from mimic.trials.report import progress_status

    line = progress_status(KickTask, _batch(138.0), 2.0, None)  # one 2.3 min episode of 2 min
    assert "2.3/2" not in line and "one episode" in line, line
    assert progress_status(KickTask, _batch(30.0, 30.0), 2.0, None).startswith("1.0/2 min")


def test_each_variants_clock_stops_when_it_ends_and_starts_when_it_starts():
    from mimic.cli.trial import TrialProgress

    progress = TrialProgress(2.0, None)
    progress.live = True  # as on a terminal
    with progress:
        progress("a", _batch())
        progress("a", _batch(30.0, 30.0))  # 1 of 2 min: the budget ends short of the bar
        progress("b", _batch())
        tasks = {t.description: t for t in progress._bar.tasks}
        assert tasks["a"].finished and not tasks["b"].finished


def test_a_trial_announces_each_variant_before_its_first_episode():
    from mimic.agents.registry import agent_spec
    from mimic.tasks.walk import WalkTrialConfig
    from mimic.trials.api import walk_trial

    calls = []
    walk_trial(
        [agent_spec("walk"), agent_spec("other-team-walk")],
        runs=1,
        workers=1,
        config=WalkTrialConfig(timeout_s=1.0),
        progress=lambda label, batch: calls.append((label, len(batch.episodes))),
    )
    assert calls == [("walk", 0), ("walk", 1), ("other-team-walk", 0), ("other-team-walk", 1)]


def test_a_trial_title_says_the_minutes_that_ran(monkeypatch, tmp_path):
    monkeypatch.chdir(tmp_path)
    result = runner.invoke(app, ["trial", "walk", "--minutes", "0.05", "--workers", "1"])
    assert result.exit_code == 0, result.output
    text = " ".join(result.output.split())
    assert "simulated min per variant (0.05 asked)" in text, text
    assert "0.05 simulated min per variant," not in text


@pytest.fixture(scope="module")
def t1_model(tmp_path_factory):
    t, q = smooth_motion(30, robot="t1")
    ds = dataset_from_frame(
        joint_frame(t, q, robot="t1"), robot="t1", period_s=0.6, metadata={"motion": "t1wave"}
    )
    path = tmp_path_factory.mktemp("t1") / "t1wave.mimic"
    return save_model(train_model(ds, TrainConfig(FAST, seed=0, epochs=20)), path)


def test_a_variant_made_for_another_robot_is_refused(t1_model):
    args = ["trial", "walk", "--compare", "walk", str(t1_model), "--robot", "nao", "--runs", "1"]
    _one_line_error(runner.invoke(app, args), 2, "made for the T1", "--robot nao")
    result = runner.invoke(
        app, ["trial", "walk", "--compare", "walk", str(t1_model), "--runs", "1"]
    )
    _one_line_error(result, 2, "cannot drive the T1")  # the model says T1: the NAO walk is not


# --- smaller: one line for every bad value ------------------------------------------------------


@pytest.mark.parametrize(
    "args, fragment",
    [
        (["trial", "kick", "--workers", "abc"], "'--workers'"),
        (["trial", "walk", "--runs", "abc"], "'--runs'"),
        (["record", "stand", "-o", "x.mcap", "--seed", "abc"], "'--seed'"),
        (["train", "x.mcap", "-o", "x.mimic", "--epochs", "1.5"], "'--epochs'"),
        (["play", "stand", "--player", "abc"], "'--player'"),
        (["improve", "kick_right", "--objective", "jump", "--budget", "4", "-o", "x.txt"], "jump"),
        (["bench", "train", "--batch", "x"], "'--batch'"),
        (["no-such-command"], "no-such-command"),
        (["record", "--no-such-option"], "--no-such-option"),
        (["train"], "missing argument"),
    ],
)
def test_bad_option_values_are_one_error_line(args, fragment, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    line = _one_line_error(runner.invoke(app, args), 2, fragment)
    assert "--help" in line and "╭" not in line


def test_train_refuses_a_period_longer_than_the_recording(stand_recording, tmp_path):
    result = runner.invoke(
        app, ["train", str(stand_recording), "--period", "100", "-o", str(tmp_path / "m.mimic")]
    )
    _one_line_error(result, 2, "--period 100 s is longer than the motion learned")
    assert not list(tmp_path.iterdir())


def test_import_of_a_folder_says_it_is_a_folder(tmp_path):
    folder = tmp_path / "game_logs"
    folder.mkdir()
    for extra in ([], ["--team", "a", "--player", "1"], ["--all"]):
        result = runner.invoke(app, ["import", str(folder), "-o", str(tmp_path / "x"), *extra])
        _one_line_error(result, 2, "is a directory")


def test_duration_is_one_option_with_seconds_as_its_other_name(tmp_path):
    for flag in ("--duration", "--seconds"):
        out = tmp_path / f"stand{flag}.mcap"
        result = runner.invoke(app, ["record", "stand", "-o", str(out), flag, "0.5"])
        assert result.exit_code == 0, result.output
        summary = json.loads(runner.invoke(app, ["info", str(out), "--json"]).output)
        assert summary["duration_s"] == pytest.approx(0.5)


def test_info_json_gives_booleans_and_numbers_typed(stand_recording):
    summary = json.loads(runner.invoke(app, ["info", str(stand_recording), "--json"]).output)
    end = summary["end"]
    assert end["interrupted"] is False
    assert isinstance(end["last_time_ns"], int) and end["last_time_ns"] == 500_000_000
    assert isinstance(end["samples"], int)
