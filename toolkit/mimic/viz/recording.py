"""The richer view of a recording: robot, ball and field in 3D; joint curves grouped (head,
arms, legs) with references and reached angles overlaid; the motion-ended flag (``/ended``);
footsteps and centre-of-mass path for walks; a learned model's output overlaid when given.
Everything follows the recording's robot (``Recording.robot``): its joints, its link shapes,
its masses and feet."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import polars as pl
import rerun as rr
import rerun.blueprint as rrb

from mimic.agents.neural_player import NeuralPlayer
from mimic.errors import MimicError
from mimic.learn.compensate import compensate_references
from mimic.learn.train import TARGET_COMPENSATED, training_dataset
from mimic.model.model_file import load_model
from mimic.recording.layout import (
    BALL_FRAME,
    ENDED,
    ENDED_COLUMN,
    JOINT_REFERENCES,
    JOINT_STATES,
    TIME_COLUMN,
)
from mimic.recording.reader import Recording, read_joint_table, read_recording, read_tf
from mimic.recording.recorder import RecordConfig, record
from mimic.robot.actuators import SpeedServos
from mimic.robot.model import RobotDescription
from mimic.viz.curves import curves_blueprint, joint_columns, log_joint_table
from mimic.viz.gait import centre_of_mass_path, footsteps
from mimic.viz.paths import WORLD, time_column
from mimic.viz.save import save_rrd
from mimic.viz.scene import log_ball_poses, log_body_poses, log_field, log_robot_geometry

__all__ = ["log_recording", "recording_blueprint", "view_recording", "ENDED_PATH"]

#: Entity of the motion-ended flag (0/1 over simulated time).
ENDED_PATH = "motion/ended"


def log_recording(rec: rr.RecordingStream, path: str | Path | Recording, *, model=None) -> dict:
    """Log a recording (and optionally a model learned from it) onto ``rec``.

    With a model, three more series sit beside the recorded ones: ``learned`` (the network's
    output on the recording's times), ``compensated`` (the references computed from the
    observed angles, what a compensated model learns) and ``replayed`` (the angles reached when
    the network is played in the simulator, as ``mimic record --model`` would). Compensation
    is defined for speed servos, and for PD motors when the recording has the torso pose on
    ``/tf`` (``mimic.learn.pd_compensate``); other recordings get no ``compensated`` series.

    ``path``: a recording file or a ``Recording`` already read; ``model``: a model file or a
    loaded ``MotionModel``. Returns a short description of what was logged (robot, series
    names, counts).

    Raises:
        MimicError: the model was learned on another robot than the recording's.
    """
    recording = path if isinstance(path, Recording) else read_recording(path)
    robot = recording.robot
    logged = {"robot": robot.name, "series": []}
    table = None
    if JOINT_STATES in recording.topics:
        table = read_joint_table(recording, JOINT_STATES)
        log_joint_table(rec, table, "reached", robot)
        logged["series"].append("reached")
    if JOINT_REFERENCES in recording.topics:
        table = read_joint_table(recording, JOINT_REFERENCES)
        log_joint_table(rec, table, "reference", robot)
        logged["series"].append("reference")
    if table is not None and ENDED in recording.topics:
        rec.log(ENDED_PATH, rr.SeriesLines(colors=[(200, 40, 40)], names=["ended"]), static=True)
        rec.send_columns(
            ENDED_PATH,
            indexes=[time_column(table["time_s"].to_numpy())],
            columns=rr.Scalars.columns(scalars=table[ENDED_COLUMN].to_numpy()),
        )
        logged["ended"] = True
    if model is not None:
        loaded = load_model(model) if isinstance(model, (str, Path)) else model
        if loaded.robot != robot.name:
            raise MimicError(
                f"{model}: a model of the {loaded.robot}; the recording is of the {robot.name}"
            )
        observed = read_joint_table(recording, recording.joint_topic())
        times = observed[TIME_COLUMN].to_numpy()
        names = loaded.joint_names
        log_joint_table(rec, _joint_frame(times, loaded.predict(times), names), "learned", robot)
        logged["series"].append("learned")
        if isinstance(robot.actuator, SpeedServos):
            angles = observed.select(joint_columns(observed)).to_numpy()
            log_joint_table(
                rec,
                _joint_frame(times, compensate_references(times, angles, robot), names),
                "compensated",
                robot,
            )
            logged["series"].append("compensated")
        elif JOINT_STATES in recording.topics and recording.path is not None:
            # PD motors: compensated from the torso pose too, when the recording has it.

            try:
                ds = training_dataset(recording.path, JOINT_STATES, TARGET_COMPENSATED)
            except MimicError:
                ds = None
            if ds is not None:
                frame = _joint_frame(ds.time_s, ds.angles_rad, names)
                log_joint_table(rec, frame, "compensated", robot)
                logged["series"].append("compensated")
        log_joint_table(rec, _replayed_table(loaded, recording), "replayed", robot)
        logged["series"].append("replayed")
    tracks = read_tf(recording, in_world=True)
    if tracks:
        log_field(rec)
        log_robot_geometry(rec, robot)
        first = next(iter(tracks.values())).times_ns[0]
        for name, track in tracks.items():
            times = (track.times_ns - first) * 1e-9
            if name == BALL_FRAME:
                log_ball_poses(rec, times, track.pos_m)
            else:
                log_body_poses(rec, times, {name: (track.pos_m, track.quat_wxyz)})
        logged["frames"] = len(tracks)
        if recording.info is not None and recording.info.cyclic:
            _log_gait(rec, tracks, first, robot)
            logged["gait"] = True
    return logged


def _log_gait(
    rec: rr.RecordingStream, tracks: dict, first_ns: int, robot: RobotDescription
) -> None:
    torso = tracks.get(robot.root_link)
    if torso is None:
        return
    com = centre_of_mass_path(tracks, robot)
    ground = np.c_[com[:, :2], np.zeros(len(com))]
    rec.log(f"{WORLD}/com_path", rr.LineStrips3D([ground], colors=(240, 60, 60)), static=True)
    rec.send_columns(
        f"{WORLD}/com",
        indexes=[time_column((torso.times_ns - first_ns) * 1e-9)],
        columns=rr.Points3D.columns(positions=ground).partition([1] * len(ground)),
    )
    for side, foot_link, colour in (
        ("left", robot.foot_links[0], (60, 120, 240)),
        ("right", robot.foot_links[1], (240, 180, 40)),
    ):
        foot = tracks.get(foot_link)
        if foot is not None:
            steps = footsteps(foot)
            rec.log(
                f"{WORLD}/footsteps/{side}",
                rr.Boxes3D(
                    centers=steps + [0.025, 0, 0.002],
                    half_sizes=[[0.08, 0.04, 0.002]] * len(steps),
                    colors=colour,
                ),
                static=True,
            )


def _joint_frame(times_s: np.ndarray, angles_rad: np.ndarray, names) -> pl.DataFrame:
    """A joint table (time_s + the N joints ``names``) from (T,) times and (T, >= N) angles
    [rad] (a network's extra ended column is left out)."""
    return pl.DataFrame(
        {TIME_COLUMN: times_s, **{n: angles_rad[:, i] for i, n in enumerate(names)}}
    )


def _replayed_table(model, recording) -> pl.DataFrame:
    """Reached angles of the network played in a fresh simulation for the recording's length
    (through the recorder, so the robot starts and the ball lies as ``mimic record`` has them)."""
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "replay.mcap"
        player = NeuralPlayer(model)
        duration = None if player.period_s is None else recording.duration_s
        # Only the joint curves are shown: /tf once is enough.
        record(player, out, duration_s=duration, config=RecordConfig(tf_every=1000))
        return read_joint_table(out, JOINT_STATES)


def recording_blueprint() -> rrb.Blueprint:
    """3D scene on the left, one curve plot per joint group on the right."""
    curves = curves_blueprint()
    return rrb.Blueprint(
        rrb.Horizontal(
            rrb.Spatial3DView(origin=WORLD, name="robot"),
            rrb.Vertical(
                *curves,
                rrb.TimeSeriesView(origin=ENDED_PATH, name="ended (/ended)"),
                row_shares=[3] * len(curves) + [1],
            ),
            column_shares=[2, 3],
        )
    )


def view_recording(
    path: str | Path,
    *,
    model: str | Path | None = None,
    save: str | Path | None = None,
    spawn: bool = True,
    overwrite: bool = True,
) -> dict:
    """Open the view in the Rerun viewer, or save it as an .rrd file.

    The recording and the model are read before anything is written; the .rrd file is written
    under a temporary name and moved into place when complete (``mimic.files``), so a failure
    leaves no file and an existing ``save`` untouched. ``overwrite`` False refuses to replace
    an existing ``save``.
    """

    recording = read_recording(path)
    loaded = load_model(model) if model is not None else None
    rec = rr.RecordingStream("mimic", recording_id=str(path))
    if save is None:
        if spawn:
            rec.spawn(default_blueprint=recording_blueprint())
        logged = log_recording(rec, recording, model=loaded)
        rec.flush()
        return logged
    return save_rrd(
        rec,
        save,
        lambda: log_recording(rec, recording, model=loaded),
        blueprint=recording_blueprint(),
        overwrite=overwrite,
    )
