"""`mimic improve`: targets and their files, the learned-model correction, the seeded and
resumable CMA-ES search, held-out validation, the command. Tiny episodes (3 s walks)."""

import dataclasses
import json
import subprocess

import numpy as np
import pytest
from typer.testing import CliRunner

from mimic.agents.other_team import WalkParams
from mimic.agents.params_file import load_params
from mimic.agents.registry import agent_spec
from mimic.cli.main import app
from mimic.errors import MimicError
from mimic.improve import improve
from mimic.improve.correction import corrected_model
from mimic.improve.objectives import OBJECTIVES
from mimic.improve.search import MAX_SEARCH_EPISODE, CheckpointError
from mimic.improve.targets import load_target
from mimic.improve.validation import held_out_episodes
from mimic.model.model_file import load_model, save_model
from mimic.model.motion_model import MotionModel
from mimic.model.network import Layout, init_params
from mimic.motion.files import load_motion, parse_motion
from mimic.robot.nao import nao
from mimic.tasks.kick import KickObjective, KickTrialConfig
from mimic.tasks.walk import WalkObjective, WalkTrialConfig
from mimic.trials.parallel import derive_seed

#: The NAO's joint count (the tiny model's outputs: these angles and the ended flag).
N = nao().num_joints

#: 3 s walks: a search of 8 evaluations plays in about a second in one process.
TINY_WALK = WalkObjective(episodes=1, trial_config=WalkTrialConfig(timeout_s=3.0))


def _tiny_model(kick: bool = True) -> MotionModel:
    layout = Layout(in_dim=1, out_dim=N + 1, hidden=(8,))
    rng = np.random.default_rng(0)
    meta = {"motion": "tiny", "ball_offset_m": [0.16, -0.07]} if kick else {"motion": "tiny"}
    return MotionModel(
        layout,
        init_params(layout, rng),
        input_offset_s=0.3,
        input_scale_per_s=2.0,
        duration_s=1.5,
        output_mean=rng.normal(0, 0.2, N + 1),
        output_std=rng.uniform(0.1, 0.3, N + 1),
        metadata=meta,
    )


def test_model_correction_is_exact_and_an_ordinary_model_file(tmp_path):
    model = _tiny_model()
    rng = np.random.default_rng(1)
    rate, offsets, gains = 1.25, rng.normal(0, 0.05, N), rng.uniform(0.8, 1.2, N)
    fixed = corrected_model(model, rate, offsets, gains)
    t = np.linspace(0.0, 1.2, 13)
    mean = model.output_mean[:N]
    want = mean + gains * (model.predict(rate * t)[:, :N] - mean) + offsets
    assert np.allclose(fixed.predict(t)[:, :N], want, atol=1e-12)
    assert np.allclose(fixed.predict(t)[:, N], model.predict(rate * t)[:, N])
    assert fixed.duration_s == pytest.approx(1.5 / rate)
    path = save_model(fixed, tmp_path / "fixed.mimic")
    assert np.allclose(load_model(path).predict(t), fixed.predict(t))
    assert load_model(path).metadata["correction"]["rate"] == rate
    assert agent_spec(str(path)).kind == "model"


def test_model_target_searches_a_time_warp_and_leg_offsets_and_gains(tmp_path):
    path = save_model(_tiny_model(), tmp_path / "kick.mimic")
    target = load_target(str(path))
    assert target.space.dim == 25 and target.space.names[0] == "time_rate"
    assert "offset.right_hip_roll" in target.space.names
    assert "gain.left_ankle_roll" in target.space.names
    zero = target.spec(np.zeros(25)).model
    assert np.array_equal(
        zero.predict(np.linspace(0, 1, 5)), target.model.predict(np.linspace(0, 1, 5))
    )
    assert target.spec(np.zeros(25)).ball_offset_m() == (0.16, -0.07)


def test_a_windowed_correction_acts_in_its_window_and_its_file_keeps_it_exact(tmp_path):
    """``--window A,B``: offsets and gains only from A to B (faded in over 0.2 s), the time
    warp from A on, the motion before A as learned; the file keeps the network and the
    correction, and loads back to the same references (ONNX export refuses it)."""
    from mimic.learn.export import model_to_onnx
    from mimic.model.windowed import WindowedModel

    path = save_model(_tiny_model(), tmp_path / "kick.mimic")
    target = load_target(str(path), window_s=(0.6, 1.0))
    z = np.zeros(target.space.dim)
    z[target.space.names.index("offset.right_knee_pitch")] = 3.0  # 0.09 rad
    played = target.spec(z).model
    knee = target.model.joint_names.index("right_knee_pitch")
    t = np.array([0.2, 0.59, 0.7, 0.8, 0.9, 1.2])
    shift = played.predict(t)[:, knee] - target.model.predict(t)[:, knee]
    assert np.allclose(shift, [0.0, 0.0, 0.045, 0.09, 0.045, 0.0], atol=1e-9)
    z[0] = 5.0  # time_rate 1.25: from 0.6 s on
    warped = target.spec(z).model
    assert warped.duration_s == pytest.approx(0.6 + 0.9 / 1.25)
    early = np.array([0.1, 0.3, 0.55])
    assert np.allclose(warped.predict(early), target.model.predict(early), atol=1e-12)
    out = tmp_path / "fixed.mimic"
    target.write(z, out, {"objective": "test"})
    written = load_model(out)
    assert isinstance(written, WindowedModel)
    grid = np.linspace(0.0, warped.duration_s, 31)
    assert np.allclose(written.predict(grid), warped.predict(grid), atol=1e-9)
    assert written.metadata["correction"]["window_s"] == [0.6, 1.0]
    with pytest.raises(MimicError, match="window"):
        model_to_onnx(written)
    with pytest.raises(MimicError, match="--window"):
        load_target("kick_right", window_s=(0.6, 1.0))


def test_motion_target_round_trips_through_a_motion_file(tmp_path):
    target = load_target("kick_right", joints="right_hip_pitch,right_knee_pitch")
    steps = len(load_motion("kick_right").steps)
    assert target.space.dim == 2 * steps + steps + 1
    assert target.movement_at(np.zeros(target.space.dim)).steps == load_motion("kick_right").steps
    z = np.random.default_rng(2).normal(size=target.space.dim)
    path = target.write(z, tmp_path / "better.txt", {"evaluations": 8, "best_score": 1.5})
    text = path.read_text()
    assert text.startswith("# improved by mimic improve")
    back = parse_motion(text, str(path))
    assert back.steps == target.movement_at(z).steps
    assert back.speed_rate == pytest.approx(target.movement_at(z).speed_rate)
    assert agent_spec(str(path)).kind == "motion"


def test_walk_parameters_go_to_a_parameter_file_every_command_accepts(tmp_path):
    target = load_target("other-team-walk")
    assert target.kind == "params" and "servo.gain" in target.space.names
    z = np.zeros(target.space.dim)
    z[target.space.names.index("speed_m_s")] = 2.0
    z[target.space.names.index("servo.gain")] = -1.0
    path = target.write(z, tmp_path / "walk.json", {"evaluations": 4})
    agent, params = load_params(path)
    assert agent == "other-team-walk"
    assert params.speed_m_s == pytest.approx(WalkParams().speed_m_s + 0.06)
    assert params.servo.gain == pytest.approx(WalkParams().servo.gain - 0.03)
    assert params.step_cycles == WalkParams().step_cycles
    spec = agent_spec(str(path))
    assert spec.kind == "params" and spec.label == "walk (params)"
    assert spec.build().params == params
    assert load_target(str(path)).params == params  # a parameter file improves further


def test_bad_parameter_files_are_one_clear_line(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text(
        json.dumps(
            {
                "format": "mimic-agent-params",
                "agent": "other-team-walk",
                "params": {"speed_m_s": 0.5, "warp": 1},
            }
        )
    )
    with pytest.raises(MimicError, match="no field 'warp'"):
        agent_spec(str(bad))
    bad.write_text("{")
    with pytest.raises(MimicError, match="not a parameter file"):
        agent_spec(str(bad))
    with pytest.raises(MimicError, match="not found"):
        agent_spec(str(tmp_path / "missing.json"))


def test_search_is_seeded_and_resumes_from_its_checkpoint(tmp_path):
    kw = dict(objective=TINY_WALK, population=4, workers=1)
    straight = improve("other-team-walk", budget=8, out=tmp_path / "a.json", **kw)
    assert straight.search.evaluations == 8 and len(straight.search.generations) == 2
    improve("other-team-walk", budget=4, out=tmp_path / "b.json", **kw)
    resumed = improve("other-team-walk", budget=8, out=tmp_path / "b.json", **kw)
    assert resumed.search.resumed == 1
    for g, h in zip(straight.search.generations, resumed.search.generations):
        assert np.array_equal(g.z, h.z) and np.array_equal(g.scores, h.scores)
    assert json.loads((tmp_path / "a.json").read_text()) == json.loads(
        (tmp_path / "b.json").read_text()
    )
    # Episodes of generation g are g * E .. g * E + E - 1, shared by its candidates.
    assert [g.first_episode for g in straight.search.generations] == [0, 1]
    # A checkpoint of another search, or a damaged one, stops the run with one line.
    with pytest.raises(CheckpointError, match="another search"):
        improve("other-team-walk", budget=8, out=tmp_path / "b.json", seed=1, **kw)
    (tmp_path / "b.json.ckpt.json").write_text('{"format": "mimic-improve-checkpoint"')
    with pytest.raises(CheckpointError, match="damaged"):
        improve("other-team-walk", budget=8, out=tmp_path / "b.json", **kw)


def test_validation_plays_seeds_the_search_never_played(tmp_path):
    run = improve(
        "other-team-walk",
        objective=TINY_WALK,
        budget=4,
        population=4,
        workers=1,
        out=tmp_path / "w.json",
        validation_episodes=3,
        pick="mean",
    )
    # The optimiser's final mean was written and validated, not the best candidate scored.
    assert np.array_equal(run.z, run.search.mean_z)
    assert not np.array_equal(run.z, run.search.best[0])
    assert json.loads((tmp_path / "w.json").read_text())["provenance"]["pick"] == "mean"
    summary = run.validation.summary
    assert summary["variant"].to_list() == ["other-team-walk", "other-team-walk (improved)"]
    assert summary["runs"].to_list() == [3, 3]
    search_seeds = {derive_seed(0, i) for i in run.search.search_episodes(1)}
    assert not search_seeds & set(run.validation.rows["seed"].to_list())
    assert held_out_episodes(0, 3, [0, 1]).start == MAX_SEARCH_EPISODE
    # The improved variant's first held-out episode is kept for the 3D replay.
    assert list(run.validation.traces) == ["other-team-walk (improved)"]
    assert [f.suffix for f in run.files] == [".csv", ".md"]


def test_kick_objective_scores_distance_times_success_minus_falls():
    from mimic.tasks.base import EpisodeBatch

    batch = EpisodeBatch([dict(distance_m=4.0), dict(distance_m=1.0)], [dict(falls=1)])
    assert KickObjective(fall_penalty_m=2.0).score(batch) == pytest.approx(2.0 - 1.0)
    assert KickObjective().search_config.episode_limit_s == 60.0
    assert (
        KickObjective(trial_config=KickTrialConfig(walk_timeout_s=5.0)).search_config.walk_timeout_s
        == 5.0
    )
    # A short kick's own rule: 0.5 m counts the 1 m kick; 0 scores plain distance.
    short = KickObjective(fall_penalty_m=2.0, trial_config=KickTrialConfig(success_distance_m=0.5))
    assert short.score(batch) == pytest.approx((4.0 + 1.0) / 2 - 1.0)
    assert short.describe()["success_distance_m"] == 0.5


def test_a_model_inside_the_balance_layer_searches_its_gains_and_its_file_keeps_them(tmp_path):
    from mimic.agents.balance import BalancedAgent, default_gains, with_balance_gains
    from mimic.agents.neural_player import NeuralPlayer

    path = save_model(_tiny_model(), tmp_path / "kick.mimic")
    target = load_target(str(path) + "+balance")
    gains = [n for n in target.space.names if n.startswith("balance.")]
    assert gains == [
        "balance.pitch",
        "balance.roll",
        "balance.pitch_rate_s",
        "balance.roll_rate_s",
        "balance.limit_rad",
    ]
    assert target.space.dim == 25 + 5
    # The search starts from the gains the layer uses around the model as it is (a kick:
    # its robot's one-shot gains).
    start = default_gains("nao", one_shot=True)
    assert target.space.describe(np.zeros(30))["balance.roll"] == start.roll
    z = np.zeros(30)
    z[target.space.names.index("balance.roll")] = 4.0  # one search unit is 0.25
    written = target.write(z, tmp_path / "better.mimic", {"evaluations": 8})
    # The file carries its gains: the layer around it (the way every command builds
    # M.mimic+balance) uses them, the rest of its gains stay its robot's.
    layer = agent_spec(str(written) + "+balance").build()
    assert isinstance(layer, BalancedAgent)
    assert layer.gains.roll == pytest.approx(start.roll + 1.0)
    assert layer.gains.support_delay_cycles == start.support_delay_cycles
    # Without the layer the target searches the correction only.
    assert load_target(str(path)).space.dim == 25
    # A model file with a gain the layer lacks is one line.
    bad = dataclasses.replace(_tiny_model(), metadata={"motion": "x", "balance_gains": {"yaw": 1}})
    with pytest.raises(MimicError, match="unknown balance gain yaw"):
        BalancedAgent(NeuralPlayer(bad))
    with pytest.raises(MimicError, match="unknown balance gain yaw"):
        with_balance_gains(_tiny_model(), {"roll": 2.0, "yaw": 1})
    given = with_balance_gains(_tiny_model(), {"roll": 2.0, "limit_rad": 0.4})
    assert BalancedAgent(NeuralPlayer(given)).gains == dataclasses.replace(
        start, roll=2.0, limit_rad=0.4
    )
    # Gains the search does not touch stay as the model had them.
    shared = with_balance_gains(_tiny_model(), {"hip_share": 0.5})
    path = save_model(shared, tmp_path / "shared.mimic")
    kept = load_target(str(path) + "+balance").write(z, tmp_path / "kept.mimic", {})
    assert agent_spec(str(kept) + "+balance").build().gains.hip_share == 0.5


@pytest.mark.parametrize(
    "args, message",
    [
        (["walk", "--objective", "walk", "--budget", "4", "-o", "x.json"], "cannot improve 'walk'"),
        (["kick_right", "--objective", "kick", "--budget", "0", "-o", "x.txt"], "--budget must be"),
        (["kick_right", "--objective", "kick", "--budget", "4", "-o", "x.json"], "as a .txt file"),
        (
            ["kick_right", "--objective", "kick", "--budget", "4", "-o", "x.txt", "--sigma", "nan"],
            "--sigma must be",
        ),
        (
            ["kick_right", "--objective", "kick", "--budget", "2", "-o", "x.txt"],
            "less than one generation",
        ),
        (
            [
                "kick_right",
                "--objective",
                "kick",
                "--budget",
                "4",
                "-o",
                "x.txt",
                "--ray-address",
                "127.0.0.1:1",
            ],
            "cannot reach a Ray cluster",
        ),
        (
            [
                "kick_right",
                "--objective",
                "kick",
                "--budget",
                "4",
                "-o",
                "x.txt",
                "--joints",
                "tail",
            ],
            "no joint 'tail'",
        ),
        (["other-team-walk", "--objective", "kick", "--budget", "4", "-o", "x.json"], "not a kick"),
        (
            ["kick_right", "--objective", "kick", "--budget", "4", "-o", "x.txt"]
            + ["--fall-penalty", "-1"],
            "--fall-penalty must be a finite number >= 0",
        ),
        (
            ["other-team-walk", "--objective", "walk", "--budget", "4", "-o", "x.json"]
            + ["--world", "league"],
            "engine parameters are searched for the NAO only",
        ),
        (
            ["kick_right", "--objective", "kick", "--budget", "4", "-o", "x.txt"]
            + ["--world", "league", "--robot", "nao"],
            "the league world plays league robots (t1, k1), not the nao",
        ),
        (
            ["kick_right", "--objective", "kick", "--budget", "4", "-o", "x.txt"]
            + ["--world", "moon"],
            "unknown world 'moon'",
        ),
        (
            ["other-team-walk", "--objective", "walk", "--budget", "4", "-o", "x.json"]
            + ["--success-m", "0.5"],
            "--success-m is the kick objective's rule",
        ),
        (
            ["kick_right", "--objective", "kick", "--budget", "4", "-o", "x.txt"]
            + ["--success-m", "-1"],
            "--success-m must be a finite number >= 0",
        ),
        (
            ["kick_right", "--objective", "kick", "--budget", "4", "-o", "x.txt"]
            + ["--window", "soon"],
            "--window takes START,END in seconds (e.g. 4.3,10.3) or auto",
        ),
        (
            ["kick_right", "--objective", "kick", "--budget", "4", "-o", "x.txt"]
            + ["--window", "auto"],
            "--window auto places a get-up's stand window; it needs --objective getup",
        ),
        (
            ["getup_back", "--objective", "getup", "--budget", "4", "-o", "x.txt"]
            + ["--window", "auto"],
            "--window corrects a learned model (.mimic), not 'getup_back'",
        ),
    ],
)
def test_bad_input_is_one_clear_line(args, message, tmp_path, monkeypatch):
    if "--ray-address" in args:  # without the ray extra the line says how to install it
        pytest.importorskip("ray")
    monkeypatch.chdir(tmp_path)
    result = CliRunner().invoke(app, ["improve", *args])
    assert result.exit_code == 2, result.output
    assert message in result.output
    assert "Traceback" not in result.output


def test_ray_without_the_extra_says_how_to_install_it(tmp_path, monkeypatch):
    import importlib.util

    if importlib.util.find_spec("ray") is not None:
        pytest.skip("ray is installed here")
    monkeypatch.chdir(tmp_path)
    args = ["kick_right", "--objective", "kick", "--budget", "4", "-o", "x.txt", "--ray"]
    result = CliRunner().invoke(app, ["improve", *args])
    assert result.exit_code == 2 and "Traceback" not in result.output
    assert ".[ray]" in result.output


def test_corrupt_checkpoint_is_one_clear_line(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "x.txt.ckpt.json").write_text("not json")
    result = CliRunner().invoke(
        app,
        [
            "improve",
            "kick_right",
            "--objective",
            "kick",
            "--budget",
            "4",
            "-o",
            "x.txt",
            "--workers",
            "1",
        ],
    )
    assert result.exit_code == 2 and "damaged or not a checkpoint" in result.output


def test_command_writes_the_file_the_trial_accepts_and_a_rerun_run(
    tmp_path, rerun_cli, monkeypatch
):
    # 3 s walks instead of the trial's 15 m for the search and validation.
    monkeypatch.setitem(OBJECTIVES, "walk", lambda **kw: dataclasses.replace(TINY_WALK, **kw))
    monkeypatch.chdir(tmp_path)
    runner = CliRunner()
    result = runner.invoke(
        app,
        [
            "improve",
            "other-team-walk",
            "--objective",
            "walk",
            "--budget",
            "4",
            "--episodes",
            "1",
            "--validate",
            "1",
            "--workers",
            "1",
            "-o",
            "walk.json",
            "--save",
            "run.rrd",
            "--fall-penalty",
            "3",
        ],
    )
    assert result.exit_code == 0, result.output
    assert "search: 4 evaluations" in result.output and "validation" in result.output
    assert (tmp_path / "walk.json.ckpt.json").is_file()
    provenance = json.loads((tmp_path / "walk.json").read_text())["provenance"]
    assert provenance["evaluations"] == 4 and provenance["objective"] == "walk"
    assert provenance["objective_settings"]["fall_penalty_m_s"] == 3.0
    text = subprocess.run(
        [rerun_cli, "rrd", "print", "run.rrd"],
        check=True,
        capture_output=True,
        text=True,
        timeout=120,
    ).stdout
    for entity in (
        "/improve/score/best ",
        "/improve/score/best_so_far",
        "/improve/candidates",
        "/world/replay/other_team_walk__improved/robot/torso",
    ):
        assert entity in text
    trial = runner.invoke(app, ["trial", "walk", "walk.json", "--runs", "1", "--workers", "1"])
    assert trial.exit_code == 0, trial.output
    assert "walk (params)" in trial.output


def test_walk_params_dataclass_is_frozen_so_candidates_never_share_state():
    assert dataclasses.is_dataclass(WalkParams) and WalkParams.__dataclass_params__.frozen


def test_improve_plays_in_the_league_world(tmp_path):
    # Every episode, search and validation, in a league simulation of its own: the T1's own
    # kick (a name the NAO does not have), cut to 6 s episodes; one joint searched.
    tiny_league_kick = KickObjective(
        episodes=1, search_limit_s=6.0, trial_config=KickTrialConfig(episode_limit_s=6.0)
    )
    run = improve(
        "kick_right_copyable",
        objective=tiny_league_kick,
        world="league",
        budget=4,
        population=4,
        joints="Right_Knee_Pitch",
        workers=1,
        out=tmp_path / "k.txt",
        validation_episodes=1,
        sigma=0.1,
    )
    assert run.objective.trial_config.world == "league"
    summary = run.validation.summary
    assert summary["world"].to_list() == ["league", "league"]
    assert summary["reach"].to_list() == ["place", "place"]
    assert summary["attempts"].min() >= 1  # both kicked, in the league's simulation
    improved = load_motion(str(tmp_path / "k.txt"), "t1")
    assert improved.robot == "t1"
    assert "robot t1" in (tmp_path / "k.txt").read_text()
    # A model says its own robot; a --robot that contradicts it is one line.
    save_model(_tiny_model(), tmp_path / "nao.mimic")
    with pytest.raises(MimicError, match="drives the nao, not the t1; pass --robot nao"):
        improve(
            str(tmp_path / "nao.mimic"),
            objective="kick",
            budget=4,
            robot="t1",
            out=tmp_path / "x.mimic",
        )


def test_a_second_window_corrects_the_first_windowed_model_and_its_file_keeps_both(tmp_path):
    """A model corrected in one window (the T1 back get-up's rise) takes a second on top (its
    stand), in the first's played time; the file loads back to the same references; a
    whole-motion correction of it is refused in one line."""
    from mimic.model.windowed import WindowedModel

    path = save_model(_tiny_model(), tmp_path / "kick.mimic")
    first = load_target(str(path), window_s=(0.2, 0.8))
    knee = first.model.joint_names.index("right_knee_pitch")
    z = np.zeros(first.space.dim)
    z[0] = 5.0  # time_rate 1.25 from 0.2 s on
    z[first.space.names.index("offset.right_knee_pitch")] = 3.0  # 0.09 rad
    once = tmp_path / "once.mimic"
    first.write(z, once, {"objective": "test"})
    inner = load_model(once)
    second = load_target(str(once), window_s=(0.9, 1.1))
    z2 = np.zeros(second.space.dim)
    z2[second.space.names.index("offset.right_knee_pitch")] = -2.0  # -0.06 rad
    twice = tmp_path / "twice.mimic"
    second.write(z2, twice, {"objective": "test"})
    both = load_model(twice)
    assert isinstance(both, WindowedModel) and isinstance(both.inner, WindowedModel)
    assert both.duration_s == pytest.approx(inner.duration_s)  # no warp in the second
    t = np.array([0.1, 0.5, 0.85, 1.0, 1.3])
    shift = both.predict(t)[:, knee] - inner.predict(t)[:, knee]
    assert np.allclose(shift, [0.0, 0.0, 0.0, -0.06, 0.0], atol=1e-9)
    grid = np.linspace(0.0, both.duration_s, 41)
    assert np.allclose(both.predict(grid), second.spec(z2).model.predict(grid), atol=1e-9)
    assert both.metadata["correction"]["previous"]["window_s"] == [0.2, 0.8]
    with pytest.raises(MimicError, match="corrected in a window"):
        load_target(str(twice))
