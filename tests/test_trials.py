"""The kick and walk trials: real episodes in the simulator, small budgets."""

import json
import subprocess

import numpy as np
import polars as pl
import pyarrow.parquet as pq
import pytest
from _learn_helpers import joint_frame
from typer.testing import CliRunner

from mimic.agents.registry import AgentSpec
from mimic.agents.registry import agent_spec as parse_agent_spec
from mimic.cli.main import app
from mimic.errors import MimicError
from mimic.learn.dataset import dataset_from_frame
from mimic.learn.presets import FAST
from mimic.learn.train import TrainConfig, train_model
from mimic.model.model_file import save_model
from mimic.robot.nao import nao
from mimic.trials.api import kick_trial, walk_trial
from mimic.trials.parallel import derive_seed
from mimic.viz.trials import save_trial_dashboard

KICK_COLUMNS = {
    "variant",
    "attempts",
    "successful",
    "accuracy_pct",
    "mean_distance_m",
    "std_distance_m",
    "goals",
    "falls",
    "getups",
    "stuck",
}
WALK_COLUMNS = {
    "variant",
    "runs",
    "mean_speed_m_s",
    "std_speed_m_s",
    "mean_y_error_m",
    "std_y_error_m",
    "runs_fell",
    "falls",
}


@pytest.fixture(scope="module")
def kick_result(tmp_path_factory):
    out = tmp_path_factory.mktemp("trial") / "kick.parquet"
    return kick_trial(
        [AgentSpec("motion", "kick_right")], minutes=2.0, seed=7, workers=2, out=out, trace=True
    )


def test_two_minute_kick_trial_counts_kicks_and_distances(kick_result):
    summary = kick_result.summary.row(0, named=True)
    assert KICK_COLUMNS <= set(kick_result.summary.columns)
    assert summary["attempts"] >= 2
    # Whole episodes that end within the budget count, never more (the first always counts).
    assert summary["episodes"] == 1 or summary["simulated_min"] <= 2.0
    kicks = kick_result.rows
    assert (kicks["distance_m"] > 0.0).all()
    assert (kicks["distance_m"] < 30.0).all()
    # The kicks go toward the opponent goal, not anywhere.
    assert kicks["direction_error_deg"].median() < 30.0
    assert summary["successful"] == int((kicks["distance_m"] > 2.0).sum())


def test_kick_trial_files_carry_configuration(kick_result):
    parquet = kick_result.files[0]
    meta = json.loads(pq.read_schema(parquet).metadata[b"mimic"])
    assert meta["kind"] == "kick" and meta["seed"] == 7 and "toolkit_version" in meta
    assert pl.read_parquet(parquet).height == kick_result.rows.height
    assert any(f.suffix == ".md" for f in kick_result.files)


def test_same_seed_same_table_whatever_the_workers(kick_result, tmp_path):
    out = tmp_path / "again.parquet"
    again = kick_trial([AgentSpec("motion", "kick_right")], minutes=2.0, seed=7, workers=1, out=out)
    assert again.rows.drop("variant").equals(kick_result.rows.drop("variant"))
    # Byte for byte: the rows file of a 2-worker run and of a 1-worker run.
    assert out.read_bytes() == kick_result.files[0].read_bytes()


def test_printed_table_keeps_every_number_whole_in_80_columns(kick_result):
    from mimic.cli import trial as cli_trial

    console = cli_trial.console
    width = console.width
    console.width = 80
    try:
        with console.capture() as captured:
            cli_trial._print(kick_result, "kick trial")
    finally:
        console.width = width
    text = captured.get()
    row = kick_result.summary.row(0, named=True)
    assert "…" not in text
    for column in ("attempts", "accuracy_pct", "mean_distance_m", "std_distance_m", "falls"):
        value = row[column]
        assert (f"{value:.3g}" if isinstance(value, float) else str(value)) in text
    assert max(len(line) for line in text.splitlines()) <= 80


def test_kick_rows_flags_are_booleans_and_the_table_has_intervals(kick_result):
    from mimic.stats import mean_interval, wilson_interval

    rows = kick_result.rows
    for flag in ("goal", "ball_out", "success", "fell"):
        assert rows[flag].dtype == pl.Boolean, flag
    assert pl.read_parquet(kick_result.files[0])["goal"].dtype == pl.Boolean
    row = kick_result.summary.row(0, named=True)
    low, high = wilson_interval(row["successful"], row["attempts"])
    assert (row["accuracy_pct_ci_low"], row["accuracy_pct_ci_high"]) == (100 * low, 100 * high)
    assert row["accuracy_pct_ci_low"] <= row["accuracy_pct"] <= row["accuracy_pct_ci_high"]
    interval = mean_interval(rows["distance_m"].to_numpy())
    assert (row["mean_distance_m_ci_low"], row["mean_distance_m_ci_high"]) == interval
    meta = json.loads(pq.read_schema(kick_result.files[0]).metadata[b"mimic"])
    (saved,) = meta["summary"]
    assert saved["accuracy_pct_ci_high"] == row["accuracy_pct_ci_high"]
    assert "Wilson" in meta["confidence"]


def test_printed_table_shows_intervals_and_explains_stuck(kick_result):
    from mimic.cli import trial as cli_trial

    with cli_trial.console.capture() as captured:
        cli_trial._print(kick_result, "kick trial")
    text = captured.get()
    row = kick_result.summary.row(0, named=True)
    assert f"{row['accuracy_pct_ci_low']:.0f}-{row['accuracy_pct_ci_high']:.0f}" in text
    assert "95% CI" in text and "Wilson" in text
    assert "stuck: episodes that ended because the robot could not reach the ball" in " ".join(
        text.split()
    )


def test_dashboard_replays_the_first_episode_in_3d(kick_result, tmp_path, rerun_cli):
    trace = kick_result.traces["kick_right"]
    # The trace is the episode as it happened: time runs forward, the ball left the centre spot.
    assert (np.diff(trace.times_s) > 0).all()
    assert np.linalg.norm(trace.ball_pos_m[-1, :2] - trace.ball_pos_m[0, :2]) > 2.0
    torso = trace.poses()["torso"][0]
    assert torso[0, 2] > 0.3, "the episode starts with the robot standing"
    rrd = tmp_path / "kick.rrd"
    save_trial_dashboard(kick_result, rrd)
    text = subprocess.run(
        [rerun_cli, "rrd", "print", str(rrd)],
        check=True,
        capture_output=True,
        text=True,
        timeout=120,
    ).stdout
    assert "/world/replay/kick_right/robot/torso - data columns: [Transform3D" in text
    assert "/world/replay/kick_right/ball - data columns: [Transform3D" in text
    assert "/world/replay/kick_right/robot/left_foot/shape" in text
    assert "/histogram/kick_right" in text and "/trial/running_accuracy_pct/kick_right" in text
    assert "/episodes/kick_right" in text


def test_episode_seeds_differ_and_are_stable():
    seeds = [derive_seed(3, i) for i in range(5)]
    assert len(set(seeds)) == 5 and seeds == [derive_seed(3, i) for i in range(5)]


def test_three_run_walk_trial_measures_speed_and_drift():
    result = walk_trial([AgentSpec("behaviour", "walk")], runs=3, seed=1, workers=2)
    assert WALK_COLUMNS <= set(result.summary.columns)
    runs = result.rows
    assert runs.height == 3
    assert (runs["distance_m"] > 0.0).all(), "the robot walked forward"
    assert (runs["speed_m_s"] < 1.5).all() and (runs["y_error_m"] < 5).all()
    assert set(runs["end"]) <= {"finished", "fell", "timeout", "agent stopped"}
    # A run that ended in a fall counts that fall; the summary adds every run's falls.
    assert (runs.filter(pl.col("fell"))["falls"] >= 1).all()
    assert result.summary["falls"][0] == runs["falls"].sum()
    assert result.summary["runs_fell"][0] == runs["fell"].sum()
    row = result.summary.row(0, named=True)
    assert row["mean_speed_m_s_ci_low"] <= row["mean_speed_m_s"] <= row["mean_speed_m_s_ci_high"]
    assert (
        0.0 <= row["fall_rate_pct_ci_low"] <= row["fall_rate_pct"] <= row["fall_rate_pct_ci_high"]
    )


def test_unknown_variant_is_one_clear_line():
    result = CliRunner().invoke(app, ["trial", "kick", "--motion", "kik_right", "--minutes", "1"])
    assert result.exit_code == 2
    assert "unknown agent 'kik_right'" in result.output
    with pytest.raises(MimicError, match="not found"):
        parse_agent_spec("missing.mimic")


def test_balance_suffix_wraps_one_model_in_the_balance_layer(tmp_path):
    refs = np.tile(nao().stand_pose(), (10, 1))
    ds = dataset_from_frame(joint_frame(np.arange(10) * 0.02, refs), metadata={"motion": "kick"})
    model = save_model(
        train_model(ds, TrainConfig(FAST, seed=0, epochs=20)), tmp_path / "kick.mimic"
    )
    wrapped, plain = parse_agent_spec(f"{model}+balance"), parse_agent_spec(str(model))
    assert (wrapped.kind, wrapped.ref, wrapped.balance) == ("model", str(model), True)
    assert not plain.balance and wrapped.label == "kick (learned) + balance"
    with pytest.raises(MimicError, match="wraps learned motions only"):
        parse_agent_spec("kick_right+balance")


def test_a_kick_episode_stops_at_its_live_cap_as_at_its_limit():
    """A kick episode reads its live cap (``tasks.budget``) at each decision: cut by a cap
    of 6 s it plays exactly as with a 6 s limit, to 6 s."""
    from mimic.tasks.budget import episode_cap
    from mimic.tasks.kick import KickTrialConfig, run_kick_episode

    kick = AgentSpec("motion", "kick_right")
    with episode_cap(lambda played_s: 6.0):
        capped = run_kick_episode(kick, 5, KickTrialConfig())
    limited = run_kick_episode(kick, 5, KickTrialConfig(episode_limit_s=6.0))
    assert capped == limited
    assert capped[1]["duration_s"] == pytest.approx(6.0)


def test_a_kick_trial_counts_its_budget_to_its_end():
    """The episode the budget ends in counts to the budget's end: its kicks that ended by
    then (the first kicks of the same episode played on its own), its falls and pushes by
    then; and the trial is the same on two workers, where that episode starts before the one
    before it ends and plays under a live cap."""
    from mimic.tasks.kick import KickTrialConfig, run_kick_episode
    from mimic.trials.executors import InlineExecutor, PoolExecutor
    from mimic.trials.parallel import run_episodes

    kick, budget_s = AgentSpec("motion", "kick_right"), 260.0

    def trial(executor):
        return run_episodes(
            run_kick_episode, kick, KickTrialConfig(), budget_s=budget_s, seed=2, executor=executor
        )

    one = trial(InlineExecutor())
    *whole, cut = one.episodes
    assert [e["end"] for e in whole] == ["goal", "goal"] and cut["end"] == "budget"
    left_s = budget_s - sum(e["duration_s"] for e in whole)
    assert cut["duration_s"] == pytest.approx(left_s)
    assert one.simulated_s == pytest.approx(budget_s)
    alone_rows, alone = run_kick_episode(kick, derive_seed(2, cut["episode"]), KickTrialConfig())
    assert alone["duration_s"] > left_s  # on its own it plays past what the budget left
    counted = [r for r in one.rows if r["episode"] == cut["episode"]]
    assert 0 < cut["kicks"] == len(counted) < len(alone_rows)
    assert [{k: v for k, v in r.items() if k != "episode"} for r in counted] == alone_rows[
        : len(counted)
    ]
    # Each kick's end: the first checkpoint that has it. The next had not ended by the budget's.
    kick_ends_s = [
        next(t for t, r, _ in alone["checkpoints"] if len(r) > k) for k in range(len(alone_rows))
    ]
    assert kick_ends_s[len(counted) - 1] <= left_s < kick_ends_s[len(counted)]
    # Its summary is the episode's own as of its last checkpoint before the budget's end.
    *_, (_, _, then) = [c for c in alone["checkpoints"] if c[0] <= left_s]
    same = {k: v for k, v in cut.items() if k not in ("duration_s", "episode")}
    assert same == {k: v for k, v in then.items() if k != "duration_s"}
    with PoolExecutor(2) as pool:
        two = trial(pool)
    assert two.rows == one.rows and two.episodes == one.episodes


def test_a_spread_within_rounding_prints_as_zero():
    """Runs that all stood up at the same cycle: their times' spread is rounding (1.9e-15 s),
    which the table shows as 0, not in scientific notation wider than its column."""
    from mimic.cli.trial import _ci_text, _number

    assert _number("std_time_s", 1.87e-15) == "0" and _number("mean_time_s", 9.32) == "9.32"
    row = {"t_ci_low": 9.32 - 1.8e-15, "t_ci_high": 9.32 + 1.8e-15}
    assert _ci_text(row, "t", "half") == "±0"
    assert _ci_text({"t_ci_low": 9.0, "t_ci_high": 9.5}, "t", "half") == "±0.25"
