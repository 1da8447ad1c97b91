"""Learning get-ups black-box (issue 35): how a motion starts, compensation that sees the
whole body on the ground and the joint stops, one-shot models past their end, training on a
window of a recording with gaps, and the get-up trial."""

from __future__ import annotations

import math

import numpy as np
import pytest
from typer.testing import CliRunner

from mimic.agents.neural_player import NeuralPlayer
from mimic.cli.main import app
from mimic.learn.checks import input_warnings
from mimic.learn.pd_compensate import pd_references
from mimic.learn.train import TrainConfig, train_model, training_dataset
from mimic.recording import layout as L
from mimic.recording.writer import RecordingWriter
from mimic.robot.registry import get_robot
from mimic.world.base import Observation, posture_quat

T1 = get_robot("t1")


def _pitch_quat(pitch_rad: float) -> np.ndarray:
    return np.array([math.cos(pitch_rad / 2), 0.0, math.sin(pitch_rad / 2), 0.0])


def _black_box_getup(path, skip_s=(), dt=0.04, seconds=4.0):
    """A league-like recording of a 'get-up': the robot lies on its front 1 s, its torso
    turns upright over 2 s while the knees bend and stretch, then it stands 1 s. Joint states
    and the torso on /tf, no motion metadata but the robot (a monitor recording says the
    robot starts standing); the samples at ``skip_s`` are missing (skipped monitor frames)."""
    info = L.RecordingInfo(motion="others_3", agent="league player", robot="t1", world="league")
    t = np.arange(0.0, seconds, dt)
    t = t[~np.any([np.isclose(t, s) for s in skip_s], axis=0)] if skip_s else t
    up = np.clip((t - 1.0) / 2.0, 0.0, 1.0)
    q = np.tile(np.asarray(T1.stand_pose_rad), (len(t), 1))
    knee = [T1.joint_names.index(n) for n in ("Left_Knee_Pitch", "Right_Knee_Pitch")]
    q[:, knee] += (1.2 * np.sin(math.pi * up))[:, None]
    pitch = (1.0 - up) * math.pi / 2
    height = 0.15 + 0.5 * up
    with RecordingWriter(path, info) as w:
        for k, tk in enumerate(t):
            ns = int(round(tk * L.NS_PER_S))
            w.write_joints(ns, q[k])
            w.write_tf(
                ns,
                [L.WORLD_FRAME],
                [T1.root_link],
                np.array([[0.0, 0.0, height[k]]]),
                np.array([_pitch_quat(pitch[k])]),
            )
    return t, q


# --- 1. a model knows how its motion starts -------------------------------------------


def test_start_posture_is_read_from_the_torso():
    from mimic.learn.posture import start_posture

    assert start_posture([0, 0, 0.1], posture_quat(0.3, "lying_front"), T1) == "lying_front"
    assert start_posture([0, 0, 0.1], posture_quat(-2.0, "lying_back"), T1) == "lying_back"
    assert start_posture([0, 0, 0.65], posture_quat(1.0, "standing"), T1) == "standing"
    assert start_posture([0, 0, 0.35], _pitch_quat(0.2), T1) == "sitting"


def test_a_black_box_get_up_learns_that_it_starts_lying(tmp_path):
    path = tmp_path / "seen.mcap"
    _black_box_getup(path)
    # The recording says nothing (a monitor recording's metadata says standing); the torso
    # at the window's start does.
    lying = training_dataset(path, L.JOINT_STATES, "reached", start_s=0.4, end_s=3.2)
    assert lying.metadata["start_posture"] == "lying_front"
    standing = training_dataset(path, L.JOINT_STATES, "reached", start_s=3.2, end_s=3.9)
    assert standing.metadata["start_posture"] == "standing"
    model = train_model(lying, TrainConfig(epochs=50))
    assert NeuralPlayer(model).start_posture == "lying_front"


def test_play_says_what_happens_to_a_lying_agent_on_a_given_server(tmp_path):
    # Nothing listens on this loopback port: the note comes before the connection fails.
    res = CliRunner().invoke(
        app, ["play", "getup_front", "--server", "127.0.0.1:9", "--settle", "0.5"]
    )
    assert res.exit_code != 0
    assert "starts lying on its front" in res.output and "0.5 s (--settle)" in res.output


# --- 2. compensation sees the whole body on the ground and the joint stops -------------


def _lying_still(seconds=0.6, dt=0.04):
    """The T1 laid on its back in our world and settled, seen still for ``seconds``."""
    from mimic.episode import Scene
    from mimic.world.mujoco_world import MujocoWorld

    world = MujocoWorld("t1")
    Scene(posture="lying_back", settle_s=1.0).setup(world, np.random.default_rng(0))
    t = np.arange(0.0, seconds, dt)
    q = np.tile(world.joint_angles_rad(), (len(t), 1))
    pos = np.tile(world.torso_pos_m(), (len(t), 1))
    quat = np.tile(world.torso_quat_wxyz(), (len(t), 1))
    return t, q, pos, quat


def test_a_robot_lying_still_is_held_by_the_ground_not_by_its_motors():
    t, q, pos, quat = _lying_still()
    comp = pd_references(t, q, pos, quat, "t1")
    # The ground carries the 31.6 kg robot (feet alone: the whole weight unexplained).
    assert comp.base_residual.max() < 5.0
    assert comp.body_contacts[:, comp.contact_bodies.index("torso")].all()
    # Lying still needs little torque: no reference far from the pose.
    assert np.abs(comp.references_rad - q).max() < 0.5


def test_a_joint_at_its_stop_gets_only_the_torque_the_stop_cannot_give():
    t, q, pos, quat = _lying_still()
    comp = pd_references(t, q, pos, quat, "t1")
    upper = np.array([j.upper_rad for j in T1.joints])
    lower = np.array([j.lower_rad for j in T1.joints])
    at_upper = q > upper - 0.03
    at_lower = q < lower + 0.03
    assert (comp.at_stop == (at_upper | at_lower)).all()
    assert (comp.torques_nm[at_upper] >= 0).all() and (comp.torques_nm[at_lower] <= 0).all()
    # A knee pressed into its upper stop by the body: a reference beyond the stop.
    knee = T1.joint_names.index("Left_Knee_Pitch")
    q2 = q.copy()
    q2[:, knee] = upper[knee]
    comp2 = pd_references(t, q2, pos, quat, "t1")
    assert (comp2.references_rad[:, knee] >= upper[knee] - 1e-6).all()


# --- 3. one-shot models hold their last pose past their end ----------------------------


def test_a_one_shot_model_played_past_its_end_holds_its_last_pose(tmp_path):
    path = tmp_path / "seen.mcap"
    _black_box_getup(path)
    ds = training_dataset(path, L.JOINT_STATES, "reached", start_s=0.4, end_s=3.2)
    model = train_model(ds, TrainConfig(epochs=200))
    player = NeuralPlayer(model)
    n = T1.num_joints
    obs = Observation(
        time_s=0.0,
        joint_angles_rad=np.asarray(T1.stand_pose_rad),
        joint_speeds_rad_s=np.zeros(n),
        gyro_rad_s=np.zeros(3),
        accelerometer_m_s2=np.zeros(3),
        torso_quat_wxyz=np.array([1.0, 0, 0, 0]),
        foot_forces_n=np.zeros(2),
        torso_pos_m=np.zeros(3),
        ball_pos_m=np.zeros(3),
    )
    player.reset(obs)
    last = model.predict(model.duration_s)[:n]
    for t_s in (model.duration_s + 0.5, 2 * model.duration_s, 10.0):
        obs.time_s = t_s
        command = player.act(obs)
        assert np.allclose(command.reference_rad, last), t_s
    assert player.done


# --- 4. training on a window ------------------------------------------------------------


def test_gaps_outside_the_window_do_not_matter_and_inside_are_resampled(tmp_path):
    path = tmp_path / "seen.mcap"
    _black_box_getup(path, skip_s=(0.2, 2.0))
    # The gap at 0.2 s lies outside the window: compensated as if it were not there.
    ds = training_dataset(path, L.JOINT_STATES, "compensated", start_s=1.2, end_s=1.5)
    assert "resampled_gaps" not in ds.metadata and ds.metadata["start_posture"] == "lying_front"
    # The gap at 1.96-2.04 s lies inside: resampled on the 0.04 s step, and named.
    ds = training_dataset(path, L.JOINT_STATES, "compensated", start_s=1.2, end_s=3.0)
    assert np.allclose(np.diff(ds.time_s), 0.04)
    assert ds.metadata["resampled_gaps"] == [[1.96, 0.08]]
    (line,) = input_warnings(ds)
    assert "1.96 s (0.08 s)" in line and "\n" not in line


def test_train_on_a_window_of_a_recording_with_a_gap_far_away(tmp_path):
    path = tmp_path / "seen.mcap"
    _black_box_getup(path, skip_s=(0.2,))
    out = tmp_path / "m.mimic"
    res = CliRunner().invoke(
        app,
        ["train", str(path), "--start", "1.2", "--end", "3.6", "--epochs", "100", "-o", str(out)],
    )
    assert res.exit_code == 0, res.output
    assert "evenly spaced" not in res.output


def test_compensation_names_the_gap_it_cannot_use():
    t, q, pos, quat = _lying_still(seconds=1.0)
    keep = ~np.isclose(t, 0.48)
    with pytest.raises(Exception, match=r"0\.080 s between 0\.44 s and 0\.52 s"):
        pd_references(t[keep], q[keep], pos[keep], quat[keep], "t1")


# --- 5. the get-up trial ----------------------------------------------------------------


def test_getup_trial_compares_get_ups_by_success_and_time(tmp_path):
    from mimic.agents.registry import agent_spec
    from mimic.trials.api import getup_trial
    from mimic.trials.executors import make_executor

    specs = [agent_spec("getup_front"), agent_spec("getup_back")]
    with make_executor(1) as executor:
        result = getup_trial(specs, runs=3, seed=5, executor=executor, out=tmp_path / "g.parquet")
    rows = result.summary.to_dicts()
    assert [r["side"] for r in rows] == ["front", "back"]
    # Our NAO's get-ups stand up (97/100 and 90/100 in benchmarks/motion_rates.py).
    assert sum(r["stood"] for r in rows) >= 5
    assert all(
        r["mean_time_to_stand_s"] is None or 1.0 < r["mean_time_to_stand_s"] < 8.0 for r in rows
    )
    assert "mean_time_to_stand_s_ratio" in result.summary.columns
    assert result.rows.height == 6 and (tmp_path / "g.parquet").exists()


def test_getup_trial_cli_refuses_an_agent_that_does_not_lie(tmp_path):
    res = CliRunner().invoke(app, ["trial", "getup", "walk", "--runs", "1", "--workers", "1"])
    assert res.exit_code == 2 and "--side front or --side back" in res.output


def test_the_league_like_world_applies_each_command_a_cycle_late():
    from mimic.robot.actuators import JointCommand
    from mimic.world.registry import default_robot, open_world

    assert default_robot("league-like") == "t1"
    with open_world("league-like", "t1") as world:
        world.reset()
        world.place_robot(0.0, 0.0, 0.0, np.asarray(T1.stand_pose_rad))
        knee = T1.joint_names.index("Left_Knee_Pitch")
        bent = np.asarray(T1.stand_pose_rad).copy()
        bent[knee] += 0.5
        before = world.joint_angles_rad()[knee]
        world.step(JointCommand.references(bent))
        assert abs(world.joint_angles_rad()[knee] - before) < 0.02  # the cycle before's
        world.step(JointCommand.references(bent))
        assert world.joint_angles_rad()[knee] - before > 0.05


def test_the_getup_objective_scores_standing_first_then_speed():
    from mimic.improve.objectives import make_objective
    from mimic.tasks.base import EpisodeBatch

    objective = make_objective("getup", episodes=2)
    fast, slow, down = (
        dict(stood=True, time_to_stand_s=5.0),
        dict(stood=True, time_to_stand_s=9.0),
        dict(stood=False, time_to_stand_s=None),
    )

    def score(*rows):
        return objective.score(EpisodeBatch(list(rows), []))

    assert score(fast, fast) > score(slow, slow) > score(fast, down) > score(down, down)


def test_the_getup_objective_climbs_from_sitting_up_to_rolling_over_to_staying_up():
    """Runs that stay down are ranked by how far they got (the T1's back get-up: a copy that
    sits up and falls back, one that rolls onto its front, one that stands and topples);
    any run that stands scores above them all."""
    from mimic.improve.objectives import make_objective
    from mimic.tasks.base import EpisodeBatch

    objective = make_objective("getup", episodes=1)

    def score(**row):
        base = dict(stood=False, time_to_stand_s=None, upright_s=0.0)
        return objective.score(EpisodeBatch([{**base, **row}], []))

    lies = score(max_torso_height_m=0.15, min_torso_forward_z=0.95)
    sits = score(max_torso_height_m=0.18, min_torso_forward_z=0.5)
    rolls = score(max_torso_height_m=0.39, min_torso_forward_z=-1.0)
    topples = score(max_torso_height_m=0.66, min_torso_forward_z=-1.0, upright_s=1.5)
    best_down = score(max_torso_height_m=0.75, min_torso_forward_z=-1.0, upright_s=20.0)
    slowest_up = score(stood=True, time_to_stand_s=objective.trial_config.timeout_s)
    assert lies < sits < rolls < topples < best_down < slowest_up
    # Rolling over is worth more than sitting up higher without it.
    assert score(max_torso_height_m=0.3, min_torso_forward_z=0.5) < rolls


def test_the_getup_trial_says_how_far_the_torso_turned_and_how_long_it_stood():
    from mimic.agents.registry import agent_spec
    from mimic.tasks.getup import GetupTrialConfig, run_getup_episode

    config = GetupTrialConfig()
    (row,), _ = run_getup_episode(agent_spec("getup_back"), 1, config)
    # Our NAO's back get-up rolls onto its front on the way up, then stands to the end.
    assert row["side"] == "back" and row["min_torso_forward_z"] < -0.7
    assert row["stood"]
    stood_for_s = row["duration_s"] - config.settle_s - row["time_to_stand_s"]
    assert row["upright_s"] == pytest.approx(stood_for_s, abs=0.05)


def test_the_stand_window_starts_just_before_the_copy_is_first_upright():
    """``mimic improve --window auto``: played in the trial, our NAO's back get-up lies, rolls
    and is first upright a while before it has stood for good; the window starts the fade-in's
    length before the first upright cycle and runs to the motion's end."""
    from mimic.agents.registry import agent_spec
    from mimic.improve.stand_window import STAND_LEAD_S, stand_window
    from mimic.tasks.getup import GetupTrialConfig, run_getup_episode
    from mimic.trials.parallel import derive_seed

    spec, config = agent_spec("getup_back"), GetupTrialConfig()
    duration_s = spec.build().movement.duration_s
    placed = stand_window(spec, duration_s, config, seed=7, runs=1)
    (row,), _ = run_getup_episode(spec, derive_seed(7, 0), config)
    assert row["stood"] and placed.upright_runs == placed.runs == 1
    assert placed.stand_s == row["first_upright_s"]
    # Upright only once the torso has risen from the ground, at the latest when it stays up.
    assert 1.0 < placed.stand_s <= row["time_to_stand_s"]
    assert placed.start_s == pytest.approx(placed.stand_s - STAND_LEAD_S, abs=0.006)
    assert placed.end_s == duration_s
    assert "--window auto: " in placed.describe()


def test_improve_places_the_window_of_a_copy_that_never_stands_before_its_highest(tmp_path):
    """``improve(..., window_s="auto")`` on a learned get-up that lies and stirs but never
    gets up (the fake recording's copy, played in the league-like world): the window starts
    the fade-in's length before the torso was highest, runs to the end, and the model written
    is corrected in that window."""
    from mimic.improve import improve
    from mimic.improve.objectives import make_objective
    from mimic.improve.stand_window import STAND_LEAD_S
    from mimic.model.model_file import load_model, save_model

    rec, path = tmp_path / "seen.mcap", tmp_path / "copy.mimic"
    _black_box_getup(rec)
    ds = training_dataset(rec, L.JOINT_STATES, "reached", start_s=0.4, end_s=3.2)
    save_model(train_model(ds, TrainConfig(epochs=50)), path)
    run = improve(
        str(path),
        objective=make_objective("getup", 1),
        budget=4,
        population=4,
        out=tmp_path / "stand.mimic",
        window_s="auto",
        world="league-like",
        workers=1,
    )
    placed = run.stand_window
    assert placed.runs == 1 and placed.upright_runs == 0
    assert 0.0 < placed.stand_s and placed.start_s == pytest.approx(
        max(0.0, placed.stand_s - STAND_LEAD_S), abs=0.006
    )
    written = load_model(run.out)
    assert written.metadata["correction"]["window_s"][0] == placed.start_s
    assert "never upright" in placed.describe()


@pytest.fixture(scope="module")
def nao_front_copies(tmp_path_factory):
    """Two NAO copies of ``getup_front`` seen through ``/joint_states``: the whole motion
    (stands up in most runs) and its first second only (it never stands)."""
    folder = tmp_path_factory.mktemp("copies")
    rec = folder / "front.mcap"
    runner = CliRunner()
    res = runner.invoke(app, ["record", "getup_front", "--observe-only", "-o", str(rec)])
    assert res.exit_code == 0, res.output
    copies = {}
    for name, window in (("whole", []), ("first_second", ["--end", "1.0"])):
        copies[name] = folder / f"{name}.mimic"
        args = ["train", str(rec), "--topic", "/joint_states", "--target", "reached"]
        res = runner.invoke(app, [*args, *window, "-o", str(copies[name])])
        assert res.exit_code == 0, res.output
    return copies


def test_keep_best_copies_the_model_that_stood_up_more(tmp_path, nao_front_copies):
    whole, part = nao_front_copies["whole"], nao_front_copies["first_second"]
    best = tmp_path / "best.mimic"
    trial = ["trial", "getup", "--compare", "getup_front", str(part), str(whole)]
    trial += ["--runs", "3", "--seed", "7", "--workers", "1", "--keep-best", str(best)]
    res = CliRunner().invoke(app, trial)
    assert res.exit_code == 0, res.output
    assert best.read_bytes() == whole.read_bytes()
    (kept,) = [line for line in res.output.splitlines() if line.startswith("kept")]
    assert kept.startswith(f"kept {whole} as {best}: the best of 2 learned models")
    # The kept file is the user's: a second trial does not replace it without --force...
    best.write_bytes(part.read_bytes())
    res = CliRunner().invoke(app, trial)
    assert res.exit_code != 0 and "pass --force" in res.output
    assert best.read_bytes() == part.read_bytes()
    # ...and with it, replaces it only once the trial is done.
    res = CliRunner().invoke(app, [*trial, "--force"])
    assert res.exit_code == 0 and best.read_bytes() == whole.read_bytes()


def test_keep_best_is_checked_before_the_first_run(tmp_path, nao_front_copies):
    whole = str(nao_front_copies["whole"])
    trial = ["trial", "getup", "--runs", "1", "--workers", "1", "--keep-best"]
    for args, says in (
        ([str(tmp_path / "best.txt"), whole], "a model file's name ends in .mimic"),
        ([str(tmp_path / "best.mimic"), "getup_front", "getup_back"], "give at least one .mimic"),
        ([whole, "--compare", "getup_front", whole], "is also an input"),
    ):
        res = CliRunner().invoke(app, [*trial, *args])
        assert res.exit_code != 0 and says in " ".join(res.output.split()), res.output
        assert "Traceback" not in res.output and "runs" not in res.output
    assert not any(tmp_path.iterdir())
    # Only a trial that ranks its variants offers it.
    res = CliRunner().invoke(app, ["trial", "kick", "--keep-best", "k.mimic"])
    assert res.exit_code == 2 and "no such option: --keep-best" in res.output


def test_keep_best_prefers_more_stood_then_faster_then_the_first_given(tmp_path):
    import polars as pl

    from mimic.agents.registry import AgentSpec
    from mimic.trials.api import TrialResult, keep_best

    specs = [AgentSpec("motion", "getup_front")]
    for name in ("a", "b", "c", "d"):
        (tmp_path / f"{name}.mimic").write_bytes(name.encode())
        specs.append(AgentSpec("model", str(tmp_path / f"{name}.mimic")))
    summary = pl.DataFrame(
        {
            "variant": ["getup_front", "a", "b", "c", "d"],
            "runs": [10] * 5,
            "stood": [10, 9, 9, 9, 0],
            "success_pct": [100.0, 90.0, 90.0, 90.0, 0.0],
            "mean_time_to_stand_s": [5.0, 6.0, 5.5, 5.5, None],
        }
    )
    result = TrialResult("getup", pl.DataFrame(), summary)
    best, row = keep_best(result, specs, tmp_path / "best.mimic")
    assert best == specs[2] and row["variant"] == "b"
    assert (tmp_path / "best.mimic").read_bytes() == b"b"
