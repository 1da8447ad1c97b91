"""What a first-time user hit (issue 16), case by case, through the real CLI.

1. lost files; 2. a hang; 3. tracebacks; 4. checks before work; 5. silent bad results;
(6. the quick start: ``test_quickstart.py``); 7. tables and progress; 8. interop.
Trials never run an episode here: ``run_episodes`` is replaced by a function that fails the
test, so every check below must come before the work.
"""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import time
import zipfile
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from _learn_helpers import smooth_motion
from typer.testing import CliRunner

from mimic.cli.main import app
from mimic.recording import layout as L
from mimic.recording.reader import read_joint_table, read_recording
from mimic.recording.recorder import record
from mimic.recording.writer import RecordingWriter
from mimic.robot.nao import nao

REPO = Path(__file__).resolve().parents[1]
SHIPPED_KICK = REPO / "recordings" / "kick_right.mcap"
runner = CliRunner()


def cli(*args) -> SimpleNamespace:
    result = runner.invoke(app, [str(a) for a in args])
    out = result.output
    return SimpleNamespace(
        code=result.exit_code, out=out, lines=[ln for ln in out.splitlines() if ln.strip()]
    )


def one_error_line(res, *words) -> None:
    assert res.code != 0, res.out
    assert "Traceback" not in res.out and not isinstance(res.code, BaseException), res.out
    errors = [ln for ln in res.lines if ln.startswith("error:")]
    assert len(errors) == 1, res.out
    for w in words:
        assert w in errors[0], res.out


@pytest.fixture()
def no_episodes(monkeypatch):
    """Any trial that gets as far as running an episode fails the test."""

    def forbidden(*args, **kwargs):
        raise AssertionError("an episode ran before the checks")

    monkeypatch.setattr("mimic.trials.api.run_episodes", forbidden)


@pytest.fixture(scope="module")
def files(tmp_path_factory) -> SimpleNamespace:
    """A short recording, a small kick model, the same model with bytes flipped mid-file, a
    study-format table."""
    root = tmp_path_factory.mktemp("new_user")
    stand = root / "stand.mcap"
    record("stand", stand, duration_s=0.4)
    model = root / "kick.mimic"
    res = cli("train", SHIPPED_KICK, "-o", model, "--epochs", "200")
    assert res.code == 0, res.out
    data = bytearray(model.read_bytes())
    mid = len(data) // 2
    data[mid : mid + 40] = bytes(b ^ 0xFF for b in data[mid : mid + 40])
    broken = root / "broken.mimic"
    broken.write_bytes(bytes(data))
    table = root / "wave.txt"
    t, q = smooth_motion(20)
    names = (
        "neckYaw neckPitch leftShoulderPitch leftShoulderYaw leftArmRoll leftArmYaw "
        "rightShoulderPitch rightShoulderYaw rightArmRoll rightArmYaw leftHipYawPitch "
        "leftHipRoll leftHipPitch leftKneePitch leftFootPitch leftFootRoll "
        "rightHipYawPitch rightHipRoll rightHipPitch rightKneePitch rightFootPitch "
        "rightFootRoll"
    ).split()
    rows = ["::".join(f"{v:.6f}" for v in [t[k], *q[k], float(k == 19)]) for k in range(20)]
    table.write_text("\n".join(["::".join(["timestep", *names, "hasEnded"]), *rows]) + "\n")
    return SimpleNamespace(root=root, stand=stand, model=model, broken=broken, table=table)


def partials(folder: Path) -> list[Path]:
    return list(folder.rglob("*.partial-*"))


# --- 1. A file is lost ---------------------------------------------------------------------


def test_failed_view_keeps_the_good_rrd_and_leaves_no_stub(files, tmp_path):
    good = tmp_path / "good.rrd"
    good.write_bytes(b"a good dashboard" * 1000)
    res = cli("view", tmp_path / "missing.mcap", "--save", good, "--force")
    one_error_line(res, "missing.mcap", "no such file")
    assert good.read_bytes() == b"a good dashboard" * 1000
    res = cli("view", tmp_path / "missing.mcap", "--save", tmp_path / "new" / "new.rrd")
    one_error_line(res)
    assert list(tmp_path.iterdir()) == [good], "no stub, no folder"


def _outputs_cases(files, tmp_path):
    out = tmp_path / "existing"
    return {
        "record": ["record", "stand", "-o", out.with_suffix(".mcap"), "--duration", "0.1"],
        "import": ["import", files.table, "-o", out.with_suffix(".mcap")],
        "view": ["view", files.stand, "--save", out.with_suffix(".rrd")],
        "train": ["train", files.table, "-o", out.with_suffix(".mimic"), "--epochs", "10"],
        "train --save": [
            "train",
            files.table,
            "-o",
            tmp_path / "new.mimic",
            "--epochs",
            "10",
            "--save",
            out.with_suffix(".rrd"),
        ],
        "export": ["export", files.model, "--onnx", out.with_suffix(".onnx")],
        "trial -o": [
            "trial",
            "kick",
            "kick_right",
            "--minutes",
            "1",
            "-o",
            out.with_suffix(".parquet"),
        ],
        "trial --save": ["trial", "walk", "walk", "--runs", "1", "--save", out.with_suffix(".rrd")],
        "demo": ["demo", "-o", tmp_path],
    }


@pytest.mark.parametrize(
    "command",
    [
        "record",
        "import",
        "view",
        "train",
        "train --save",
        "export",
        "trial -o",
        "trial --save",
        "demo",
    ],
)
def test_no_command_replaces_an_existing_output_without_force(
    files, tmp_path, no_episodes, command
):
    args = _outputs_cases(files, tmp_path)[command]
    target = (
        Path(next(a for a in args if "existing" in str(a)))
        if command != "demo"
        else tmp_path / "kick_right.mcap"
    )
    target.write_bytes(b"precious")
    res = cli(*args)
    one_error_line(res, str(target), "exists", "--force")
    assert target.read_bytes() == b"precious" and not partials(tmp_path)


@pytest.mark.parametrize("command", ["record", "import", "view", "train", "export"])
def test_force_replaces_an_existing_output(files, tmp_path, command):
    args = _outputs_cases(files, tmp_path)[command]
    target = Path(next(a for a in args if "existing" in str(a)))
    target.write_bytes(b"old")
    res = cli(*args, "--force")
    assert res.code == 0, res.out
    assert target.read_bytes() != b"old" and not partials(tmp_path)


@pytest.mark.parametrize(
    "args",
    [
        ["train", "{broken}", "-o", "{out}.mimic"],
        ["export", "{broken}", "--onnx", "{out}.onnx"],
        ["import", "{model}", "-o", "{out}.mcap"],
        ["view", "{model}", "--save", "{out}.rrd"],
    ],
)
def test_failed_commands_leave_no_file(files, tmp_path, args):
    fill = {"broken": files.broken, "model": files.model, "out": tmp_path / "out"}
    res = cli(*[a.format(**fill) for a in args])
    one_error_line(res)
    assert list(tmp_path.iterdir()) == []


def test_a_killed_recording_keeps_what_it_wrote(tmp_path):
    out = tmp_path / "long.mcap"
    mimic = Path(sys.executable).with_name("mimic")
    cmd = [str(mimic)] if mimic.exists() else [sys.executable, "-m", "mimic.cli.main"]
    proc = subprocess.Popen(
        cmd + ["record", "stand", "-o", str(out), "--duration", "600"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    deadline = time.monotonic() + 60
    while (
        time.monotonic() < deadline and sum(p.stat().st_size for p in partials(tmp_path)) < 20_000
    ):
        time.sleep(0.1)
    proc.send_signal(signal.SIGKILL)
    proc.wait(timeout=60)
    assert not out.exists(), "a killed recording is not passed off as complete"
    (partial,) = partials(tmp_path)
    rec = read_recording(partial)
    assert not rec.recovery.complete and len(read_joint_table(rec)) > 20


# --- 2. A hang -----------------------------------------------------------------------------


@pytest.mark.parametrize(
    "args, flag",
    [
        (
            ["trial", "kick", "--compare", "kick_right", "kick_left", "--minutes", "nan"],
            "--minutes",
        ),
        (
            ["trial", "kick", "--compare", "kick_right", "kick_left", "--minutes", "inf"],
            "--minutes",
        ),
        (["trial", "kick", "--minutes", "0"], "--minutes"),
        (["trial", "kick", "--success-m", "nan"], "--success-m"),
        (["trial", "walk", "--minutes", "-inf"], "--minutes"),
        (["trial", "walk", "--minutes", "nan"], "--minutes"),
        (["trial", "walk", "--speed-rate", "nan"], "--speed-rate"),
        (["trial", "walk", "--speed-rate", "inf"], "--speed-rate"),
        (["record", "stand", "-o", "{tmp}/x.mcap", "--duration", "nan"], "--duration"),
        (["record", "stand", "-o", "{tmp}/x.mcap", "--duration", "inf"], "--duration"),
        (["record", "walk", "-o", "{tmp}/x.mcap", "--warmup", "inf"], "--warmup"),
        (["import", "{tmp}/t.txt", "-o", "{tmp}/x.mcap", "--distance", "nan"], "--distance"),
        (["demo", "-o", "{tmp}/d", "--minutes", "nan"], "--minutes"),
        (["paper", "-o", "{tmp}/p", "--minutes", "inf"], "--minutes"),
    ],
)
def test_every_float_option_must_be_finite_and_in_range(
    tmp_path, no_episodes, monkeypatch, args, flag
):
    def forbidden(*a, **k):
        raise AssertionError("recorded before checking the options")

    monkeypatch.setattr("mimic.pipeline.record", forbidden)
    res = cli(*[a.format(tmp=tmp_path) for a in args])
    one_error_line(res, flag, "finite")
    assert list(tmp_path.iterdir()) == []


# --- 3. Tracebacks instead of one line -----------------------------------------------------


@pytest.mark.parametrize(
    "args",
    [
        ["info", "{broken}"],
        ["export", "{broken}", "--onnx", "{tmp}/x.onnx"],
        ["trial", "kick", "--compare", "kick_right", "{broken}", "--minutes", "1"],
        ["trial", "walk", "--compare", "walk", "{broken}", "--runs", "1"],
        ["record", "--model", "{broken}", "-o", "{tmp}/x.mcap"],
    ],
)
def test_a_model_file_with_flipped_bytes_is_one_line(files, tmp_path, no_episodes, args):
    res = cli(*[a.format(broken=files.broken, tmp=tmp_path) for a in args])
    one_error_line(res, "broken.mimic", "broken model file", "CRC")


@pytest.mark.parametrize(
    "args",
    [
        ["trial", "kick", "--seed", "-5"],
        ["trial", "walk", "--seed", "-5"],
        ["train", "{table}", "-o", "{tmp}/x.mimic", "--seed", "-5"],
        ["record", "stand", "-o", "{tmp}/x.mcap", "--seed", "-5"],
        ["demo", "-o", "{tmp}/d", "--seed", "-5"],
        ["trial", "kick", "--seed", str(2**32)],
    ],
)
def test_a_negative_seed_is_one_line(files, tmp_path, no_episodes, args):
    res = cli(*[a.format(table=files.table, tmp=tmp_path) for a in args])
    one_error_line(res, "--seed", "0 to 4294967295")
    assert list(tmp_path.iterdir()) == []


def test_view_save_into_a_new_folder_works_and_an_impossible_one_is_one_line(files, tmp_path):
    res = cli("view", files.stand, "--save", tmp_path / "no" / "dir" / "x.rrd")
    assert res.code == 0, res.out
    assert (tmp_path / "no" / "dir" / "x.rrd").stat().st_size > 1000
    blocker = tmp_path / "file"
    blocker.write_text("a file, not a folder")
    res = cli("view", files.stand, "--save", blocker / "x.rrd")
    one_error_line(res, "cannot create the folder")


@pytest.mark.parametrize("kind", ["kick", "walk"])
def test_trial_save_to_an_impossible_place_fails_before_the_trial(tmp_path, no_episodes, kind):
    blocker = tmp_path / "file"
    blocker.write_text("a file, not a folder")
    for flag in ("--save", "--save-rrd"):
        res = cli("trial", kind, "--minutes", "1", flag, blocker / "x.rrd")
        one_error_line(res, "cannot create the folder")


# --- 4. Checks before work -----------------------------------------------------------------


def test_trial_checks_every_variant_before_the_first(files, tmp_path, no_episodes):
    res = cli(
        "trial", "kick", "--compare", "kick_right", files.model, files.broken, "--minutes", "1"
    )
    one_error_line(res, "broken.mimic")
    other = tmp_path / "other_robot.mimic"
    with zipfile.ZipFile(files.model) as src, zipfile.ZipFile(other, "w") as dst:
        for item in src.namelist():
            data = src.read(item)
            if item == "meta.json":
                meta = json.loads(data)
                meta["joint_names"] = meta["joint_names"][:20]
                data = json.dumps(meta).encode()
            dst.writestr(item, data)
    res = cli("trial", "walk", "--compare", "walk", other, "--runs", "1")
    one_error_line(res, "other_robot.mimic", "different joint layout")


@pytest.mark.parametrize("damage", ["flipped", "cut"])
def test_info_on_a_broken_model_says_broken_model_file(files, tmp_path, damage):
    path = files.broken
    if damage == "cut":
        path = tmp_path / "cut.mimic"
        path.write_bytes(files.model.read_bytes()[:3000])
    res = cli("info", path)
    one_error_line(res, "broken model file")
    assert "MCAP" not in res.out


def test_compare_with_an_unknown_variant_names_it(no_episodes):
    res = cli("trial", "kick", "--compare", "nope")
    one_error_line(res, "'nope'", "unknown")
    assert "at least two" not in res.out
    res = cli("trial", "kick", "--compare", "kick_right")
    one_error_line(res, "at least two variants")


@pytest.mark.parametrize(
    "args",
    [
        ["info", "{dir}"],
        ["train", "{dir}", "-o", "{tmp}/x.mimic"],
        ["export", "{dir}", "--onnx", "{tmp}/x.onnx"],
        ["view", "{dir}"],
        ["import", "{dir}", "-o", "{tmp}/x.mcap"],
        ["record", "--model", "{dir}", "-o", "{tmp}/x.mcap"],
    ],
)
def test_a_directory_given_as_input_is_named_as_a_directory(tmp_path, args):
    folder = (
        tmp_path / "folder.mimic"
        if "--model" in args or "export" in args
        else tmp_path / "folder.mcap"
    )
    folder.mkdir()
    res = cli(*[a.format(dir=folder, tmp=tmp_path) for a in args])
    one_error_line(res, "is a directory")
    assert "no such file" not in res.out


@pytest.mark.parametrize(
    "args, flag",
    [
        (["trial", "kick", "--workers", "0"], "--workers"),
        (["trial", "kick", "--workers", "-3"], "--workers"),
        (["trial", "walk", "--workers", "0"], "--workers"),
        (["trial", "walk", "--runs", "0"], "--runs"),
        (["trial", "walk", "--speed-rate", "0"], "--speed-rate"),
        (["trial", "walk", "--speed-rate", "-1"], "--speed-rate"),
        (["record", "walk", "-o", "{tmp}/x.mcap", "--warmup", "-3"], "--warmup"),
        (["record", "stand", "-o", "{tmp}/x.mcap", "--duration", "0"], "--duration"),
        (["train", "{table}", "-o", "{tmp}/x.mimic", "--epochs", "0"], "--epochs"),
        (["demo", "-o", "{tmp}/d", "--workers", "0"], "--workers"),
        (["bench", "train", "--batch", "0"], "--batch"),
    ],
)
def test_counts_and_rates_out_of_range_are_one_line(files, tmp_path, no_episodes, args, flag):
    res = cli(*[a.format(tmp=tmp_path, table=files.table) for a in args])
    one_error_line(res, flag)
    assert list(tmp_path.iterdir()) == []


# --- 5. Silent bad results -----------------------------------------------------------------


def _cut_recording(tmp_path) -> Path:
    data = SHIPPED_KICK.read_bytes()
    cut = tmp_path / "cut_kick.mcap"
    cut.write_bytes(data[: len(data) // 8])
    return cut


def test_train_on_a_truncated_recording_warns_and_strict_refuses(tmp_path):
    cut = _cut_recording(tmp_path)
    res = cli("train", cut, "-o", tmp_path / "m.mimic", "--epochs", "50")
    assert res.code == 0, res.out
    warning = next(ln for ln in res.lines if ln.startswith("warning:") and "cut_kick" in ln)
    assert "truncated" in warning and "recovered" in warning
    assert "may be incomplete" in warning and "kick_right, which lasts 3.31 s" in warning
    res = cli("train", cut, "-o", tmp_path / "strict.mimic", "--strict")
    one_error_line(res, "may be incomplete", "--strict")
    assert not (tmp_path / "strict.mimic").exists()


def test_train_on_an_interrupted_recording_warns(tmp_path):
    path = tmp_path / "interrupted.mcap"
    with RecordingWriter(path, L.RecordingInfo(motion="kick_right", agent="test")) as w:
        for k in range(12):
            w.write_joints(k * 20_000_000, np.full(nao().num_joints, 0.01 * k))
            w.write_ended(k * 20_000_000, False)
        w.finish(interrupted=True)
    res = cli("train", path, "-o", tmp_path / "m.mimic", "--epochs", "50")
    assert res.code == 0, res.out
    assert any("interrupted" in ln and "0.22 s" in ln for ln in res.lines), res.out
    one_error_line(cli("train", path, "-o", tmp_path / "s.mimic", "--strict"), "interrupted")


def test_train_warns_about_a_poor_fit_and_says_what_to_do(tmp_path):
    res = cli("train", SHIPPED_KICK, "-o", tmp_path / "m.mimic", "--epochs", "5")
    assert res.code == 0, res.out
    warning = next(ln for ln in res.lines if "poor fit" in ln)
    assert "mean absolute error" in warning and "--epochs" in warning


def test_poor_fit_of_many_cycles_suggests_learning_one():
    from mimic.learn.checks import fit_warnings
    from mimic.learn.dataset import Dataset
    from mimic.robot.registry import get_robot

    t = np.arange(0, 97, 0.02)
    nao = get_robot("nao")
    walk = Dataset(
        t,
        np.zeros((len(t), nao.num_joints + 1)),
        nao.name,
        nao.joint_names,
        0.28,
        {"motion": "walk"},
    )
    model = SimpleNamespace(name="walk", metrics={"mae_rad": 0.166})
    (warning,) = fit_warnings(model, walk)
    assert "0.166 rad" in warning and "one steady cycle" in warning
    assert fit_warnings(SimpleNamespace(name="walk", metrics={"mae_rad": 0.01}), walk) == []


def test_info_on_an_mcap_without_joint_states_says_so(tmp_path):
    from mcap.writer import Writer

    path = tmp_path / "foreign.mcap"
    with open(path, "wb") as f:
        w = Writer(f)
        w.start()
        schema = w.register_schema("std_msgs/msg/String", "ros2msg", b"string data\n")
        channel = w.register_channel("/chatter", "cdr", schema)
        for k in range(5):
            w.add_message(channel, log_time=k, publish_time=k, data=b"\0\1\0\0\1\0\0\0\0")
        w.finish()
    res = cli("info", path)
    assert res.code == 0, res.out
    assert "mimic None" not in res.out and "0.0 Hz" not in res.out
    assert any(ln.startswith("warning:") and "no /joint_states" in ln for ln in res.lines)
    assert any("not written by mimic" in ln for ln in res.lines)


# --- 7. Tables and progress ----------------------------------------------------------------


def _paper_tables():
    import polars as pl

    from mimic.pipeline import network_summary
    from mimic.trials.report import STUDY_KICK, STUDY_WALK

    metrics = {
        "kick_right": {"mae_rad": 0.0043, "max_error_rad": 0.05, "epochs": 25000},
        "kick_right from /joint_states": {
            "mae_rad": 0.0061,
            "max_error_rad": 0.07,
            "epochs": 25000,
        },
        "other_team_walk": {"mae_rad": 0.0102, "max_error_rad": 0.22, "epochs": 25000},
    }
    kick = pl.concat(
        [
            STUDY_KICK,
            pl.DataFrame(
                {
                    "variant": [
                        "kick_right",
                        "kick_right (learned)",
                        "kick_right_observed (learned) + balance",
                    ],
                    "attempts": [68, 59, 60],
                    "successful": [60, 51, 52],
                    "accuracy_pct": [88.235, 86.44, 86.67],
                    "mean_distance_m": [3.371, 3.39, 3.95],
                    "std_distance_m": [1.29, 1.23, 1.75],
                    "goals": [14, 10, 14],
                    "falls": [2, 2, 2],
                }
            ),
        ],
        how="vertical_relaxed",
    )
    walk = pl.concat(
        [
            STUDY_WALK,
            pl.DataFrame(
                {
                    "variant": [
                        "other-team-walk",
                        "other_team_walk (learned)",
                        "other_team_walk (learned) + balance",
                    ],
                    "runs": [54, 21, 48],
                    "mean_speed_m_s": [0.439, 0.234, 0.39],
                    "std_speed_m_s": [0.02, 0.058, 0.021],
                    "mean_y_error_m": [0.27, 0.25, 0.3],
                    "std_y_error_m": [0.18, 0.31, 0.19],
                    "falls": [2, 21, 1],
                }
            ),
        ],
        how="vertical_relaxed",
    )
    return network_summary(metrics), kick, walk


def test_paper_tables_fit_80_columns_with_every_name_and_number_whole():
    from mimic.cli import pipeline as cli_pipeline

    network, kick, walk = _paper_tables()
    console = cli_pipeline.console
    width, console.width = console.width, 80
    try:
        with console.capture() as captured:
            cli_pipeline._table(network, "Table 1")
            cli_pipeline._table(kick, "Table 2")
            cli_pipeline._table(walk, "Table 3")
    finally:
        console.width = width
    text = captured.get()
    assert "…" not in text and max(len(ln) for ln in text.splitlines()) <= 80
    tokens = set(text.split())
    for frame in (network, kick, walk):
        for name in frame[frame.columns[0]]:
            assert set(name.split()) <= tokens, name  # every word of every name, whole
    for header in ("m/s", "acc", "%", "err", "params", "MAE"):
        assert header in tokens, header
    walk_text = text.split("Table 3")[1]
    assert {"falls", "runs"} <= set(walk_text.split())
    learned = next(ln for ln in walk_text.splitlines() if "(learned)" in ln and "study" not in ln)
    assert learned.split()[-1] == "21" and "21" in learned.split()[2:4]  # fell in 21 of 21


def test_walk_progress_counts_runs_not_kicks():
    from mimic.tasks.base import EpisodeBatch
    from mimic.tasks.kick import KickTask
    from mimic.tasks.walk import WalkTask
    from mimic.trials.report import progress_status

    walk = EpisodeBatch(
        [{"speed_m_s": 0.4}] * 4, [{"duration_s": 30.0, "falls": f} for f in (0, 1, 0, 0)]
    )
    line = progress_status(WalkTask, walk, 30.0, None)
    assert "kicks" not in line and "goals" not in line
    assert "4 runs" in line and "1 fall" in line and "2.0/30 min" in line
    kick = EpisodeBatch([{}] * 7, [{"duration_s": 60.0, "kicks": 7, "goals": 1, "falls": 2}])
    assert progress_status(KickTask, kick, 30.0, None) == "1.0/30 min 7 kicks 1 goals 2 falls"


def test_progress_lines_fit_80_columns():
    from rich.console import Console

    from mimic.cli import trial as cli_trial
    from mimic.tasks.base import EpisodeBatch

    batch = EpisodeBatch(
        [{}] * 140, [{"duration_s": 1798.0, "kicks": 140, "goals": 30, "falls": 12}], task="kick"
    )
    progress = cli_trial.TrialProgress(30.0, None)
    progress.live = True  # as on a terminal, without starting the live display
    progress._bar.start = lambda: None
    progress("kick_right_observed (learned) + balance", batch)
    screen = Console(width=80, color_system=None, force_terminal=True)
    with screen.capture() as captured:
        screen.print(progress._bar.make_tasks_table(progress._bar.tasks))
    text = captured.get()
    assert "…" not in text and max(len(ln) for ln in text.splitlines()) <= 80
    assert "30.0/30 min 140 kicks 30 goals 12 falls" in text


def test_progress_without_a_terminal_prints_lines(monkeypatch):
    from mimic.cli import trial as cli_trial
    from mimic.tasks.base import EpisodeBatch

    monkeypatch.setattr(cli_trial, "PLAIN_PROGRESS_EVERY_S", 0.0)
    assert not cli_trial.console.is_terminal or pytest.skip("stdout is a terminal")
    with cli_trial.console.capture() as captured:
        with cli_trial.TrialProgress(None, 3) as progress:
            for k in range(1, 4):
                runs = [{"duration_s": 20.0, "falls": 0}] * k
                progress("walk", EpisodeBatch([{}] * k, runs, task="walk"))
    assert [ln for ln in captured.get().splitlines()] == [
        "walk: 1/3 runs 0 falls",
        "walk: 2/3 runs 0 falls",
        "walk: 3/3 runs 0 falls",
    ]


def test_wilson_and_t_intervals():
    from mimic.stats import mean_interval, t_quantile_95, wilson_interval

    low, high = wilson_interval(60, 68)  # the README's 88.2 % of our kick
    assert (round(low, 4), round(high, 4)) == (0.7847, 0.9392)
    assert wilson_interval(0, 21)[0] == 0.0 and wilson_interval(21, 21)[1] == 1.0
    assert round(wilson_interval(21, 21)[0], 4) == 0.8454
    assert t_quantile_95(1) == 12.706 and t_quantile_95(30) == 2.042
    assert abs(t_quantile_95(40) - 2.0211) < 2e-4 and abs(t_quantile_95(120) - 1.9799) < 2e-4
    low, high = mean_interval([1.0, 2.0, 3.0, 4.0])
    assert (round(low, 3), round(high, 3)) == (0.446, 4.554)
    assert np.isnan(mean_interval([1.0])).all() and np.isnan(wilson_interval(0, 0)).all()


# --- 8. Interop ----------------------------------------------------------------------------


def test_recordings_carry_data_crcs_and_wall_clock_log_times(tmp_path):
    from mcap.records import Chunk, DataEnd, Message, Metadata
    from mcap.stream_reader import StreamReader

    before_ns = time.time_ns()
    path = tmp_path / "stand.mcap"
    record("stand", path, duration_s=0.3)
    with open(path, "rb") as f:
        records = list(StreamReader(f, validate_crcs=True, emit_chunks=True).records)
    (end,) = [r for r in records if isinstance(r, DataEnd)]
    assert end.data_section_crc != 0
    assert all(c.uncompressed_crc != 0 for c in records if isinstance(c, Chunk))
    meta = next(r for r in records if isinstance(r, Metadata) and r.name == "mimic").metadata
    start_ns = int(meta["start_wall_time_ns"])
    assert before_ns <= start_ns <= time.time_ns()
    with open(path, "rb") as f:
        times = [r.log_time for r in StreamReader(f).records if isinstance(r, Message)]
    assert min(times) >= start_ns  # not 1970
    table = read_joint_table(path)
    assert table["time_s"][0] == 0.0 and abs(table["time_s"][-1] - 0.3) < 1e-9
    rec = read_recording(path)
    assert rec.time_origin_ns == start_ns and abs(rec.recovery.last_time_s - 0.3) < 1e-9
    assert abs(rec.duration_s - 0.3) < 1e-9 and abs(rec.rate_hz - 50.0) < 1e-6
    _, msg = next(iter(rec.decoded(L.JOINT_STATES)))
    assert msg.header.stamp.sec * 10**9 + msg.header.stamp.nanosec == start_ns


@pytest.mark.parametrize("name", ["stand", "kick_right", "getup_front"])
def test_shipped_recordings_with_log_times_from_zero_still_read(name):
    rec = read_recording(REPO / "recordings" / f"{name}.mcap")
    assert rec.time_origin_ns == 0 and rec.recovery.complete
    table = read_joint_table(rec)
    assert table["time_s"][0] == 0.0
    assert abs(rec.recovery.last_time_s - table["time_s"][-1]) < 1e-9


def test_view_shows_the_ended_flag(files, tmp_path, rerun_cli):
    rrd = tmp_path / "view.rrd"
    assert cli("view", files.stand, "--save", rrd).code == 0
    text = subprocess.run(
        [rerun_cli, "rrd", "print", str(rrd)],
        check=True,
        capture_output=True,
        text=True,
        timeout=120,
        env={"RERUN_ANALYTICS": "off", "PATH": "/usr/bin:/bin"},
    ).stdout
    assert "/motion/ended" in text


def test_onnx_inputs_and_outputs_have_doc_strings(files, tmp_path):
    import onnx

    out = tmp_path / "kick.onnx"
    assert cli("export", files.model, "-o", out).code == 0
    graph = onnx.load(str(out)).graph
    assert "seconds from the motion start" in graph.input[0].doc_string
    doc = graph.output[0].doc_string
    assert "head_yaw" in doc and "[rad]" in doc and "ended" in doc


def test_one_name_for_the_save_option():
    for command in (["view"], ["train"], ["trial", "kick"], ["trial", "walk"]):
        res = runner.invoke(app, [*command, "--help"], env={"COLUMNS": "200"})
        assert "--save " in res.output and "--save-rrd" not in res.output, command
        assert "--force" in res.output, command


def _every_command(command, context, path=()):
    yield path, command
    if hasattr(command, "list_commands"):
        for name in command.list_commands(context):
            yield from _every_command(command.get_command(context, name), context, (*path, name))


def test_help_texts_keep_their_units_in_brackets():
    # Typer renders help as Rich markup: an unescaped "[s]" is a tag and vanishes ("Learn
    # from this time on ."). Every bracket a help text shows must come through as written.
    import typer
    from rich.text import Text

    root = typer.main.get_command(app)
    context = type(root).context_class(root)
    seen = 0
    for path, command in _every_command(root, context):
        for param in command.params:
            text = getattr(param, "help", None) or ""
            if "[" in text:
                seen += 1
                assert Text.from_markup(text).plain == text.replace("\\[", "["), (path, param.name)
    assert seen >= 4  # units in brackets: --start, --end, --period, --distance
    res = runner.invoke(app, ["train", "--help"], env={"COLUMNS": "200"})
    assert "[s from the recording's first sample]" in res.output


def test_command_lists_wrap_each_summary_as_one_sentence():
    # A group's list shows each command's first help paragraph; the docstrings' own line
    # breaks used to cut it mid-sentence ("... our MuJoCo world, the" / "same work ...").
    for group in ([], ["trial"], ["bench"]):
        res = runner.invoke(app, [*group, "--help"], env={"COLUMNS": "80"})
        assert res.exit_code == 0, group
        rows = [line.strip("│ ").rstrip() for line in res.output.splitlines() if "│" in line]
        # A summary's line is never cut short while its next line goes on with the sentence.
        for line, after in zip(rows, rows[1:]):
            if after.startswith(" ") and after.strip() and after.strip()[0].islower():
                assert len(line) > 60, (group, line, after)
    res = runner.invoke(app, ["bench", "--help"], env={"COLUMNS": "80"})
    assert "MuJoCo world, the same work" in " ".join(res.output.split())
