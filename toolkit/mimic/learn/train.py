"""Training motion networks: one or many datasets, one preset, one seed, batched.

Every dataset gets the same initial weights for a given seed (drawn from
``np.random.default_rng(seed)``), so a model does not depend on which other motions it was
trained with; same seed and data -> identical weights. Models with the same input kind
(time or phase) and the same robot joints train together as one batch (``AdamTrainer`` with
K stacked networks); the network's N + 1 outputs come from the dataset's joints.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_limits

from mimic import __version__, options
from mimic.errors import DatasetError, MimicError
from mimic.geometry import in_robot_frame, one_hemisphere, yaw_from_quat
from mimic.learn.compensate import compensate_references
from mimic.learn.dataset import (
    Dataset,
    as_cyclic,
    average_jittery_joints,
    cut_dataset,
    dataset_from_file,
    detect_period_s,
    drop_non_repeating,
    symmetric_cycle,
)
from mimic.learn.foot_track import foot_track
from mimic.learn.pd_compensate import pd_references
from mimic.learn.posture import start_posture
from mimic.learn.presets import FAST, Preset
from mimic.learn.steps import find_steps
from mimic.learn.window import window
from mimic.model.keys import FOOT_TRACK_KEY
from mimic.model.motion_model import INPUT_PHASE, INPUT_TIME, MotionModel
from mimic.model.network import AdamTrainer, Layout, init_params
from mimic.recording import layout as L
from mimic.recording.layout import JOINT_STATES
from mimic.recording.reader import read_recording, read_tf
from mimic.robot.actuators import PDMotors, SpeedServos
from mimic.robot.registry import get_robot
from mimic.world.base import CYCLE_S
from mimic.world.kinematics import FootKinematics
from mimic.world.registry import get_world

__all__ = [
    "TrainConfig",
    "TrainProgress",
    "train_models",
    "train_model",
    "evaluate",
    "input_mapping",
    "training_dataset",
    "pd_compensated_targets",
    "recorded_torso",
    "TARGET_REACHED",
    "TARGET_COMPENSATED",
    "PERIOD_STEPS",
]


@dataclass(frozen=True)
class TrainConfig:
    """What to train with."""

    # Training preset (schedule, scaling, init).
    preset: Preset = FAST
    # Seed of the initial weights.
    seed: int = 0
    # Total epochs override (the preset's phases are stretched/shrunk), or None.
    epochs: int | None = None
    # Report progress (and loss curves) every this many epochs.
    log_every: int = 250

    def __post_init__(self) -> None:

        options.seed(self.seed)
        options.count(self.epochs, "--epochs")
        options.count(self.log_every, "log_every")

    def schedule(self) -> Preset:
        return self.preset if self.epochs is None else self.preset.with_epochs(self.epochs)


@dataclass(frozen=True)
class TrainProgress:
    """A progress report while training (one per ``log_every`` epochs and phase end)."""

    # Motion names of the batch being trained.
    names: tuple[str, ...]
    # Index of the learning-rate phase and its rate.
    phase: int
    lr: float
    # Epochs done in total (over all phases) and the total to do.
    epoch: int
    epochs_total: int
    # (K,) mean squared error of the (standardised) training loss, per model.
    loss: np.ndarray
    # (K,) mean absolute joint error [rad], per model.
    mae_rad: np.ndarray
    # Wall time since the start of this batch [s].
    wall_s: float


def input_mapping(dataset: Dataset, preset: Preset) -> dict:
    """Input kind and scaling of a dataset under a preset (``MotionModel`` fields)."""
    if dataset.period_s is not None:
        return dict(
            input_kind=INPUT_PHASE,
            period_s=float(dataset.period_s),
            input_offset_s=0.0,
            input_scale_per_s=1.0,
        )
    t0, t1 = float(dataset.time_s[0]), float(dataset.time_s[-1])
    if preset.scale_input:
        return dict(
            input_kind=INPUT_TIME,
            input_offset_s=0.5 * (t0 + t1),
            input_scale_per_s=2.0 * preset.input_half_range / max(t1 - t0, 1e-9),
        )
    return dict(input_kind=INPUT_TIME, input_offset_s=0.0, input_scale_per_s=1.0)


def _output_scaling(dataset: Dataset, preset: Preset) -> tuple[np.ndarray, np.ndarray]:
    if not preset.standardise_output:
        width = dataset.targets.shape[1]
        return np.zeros(width), np.ones(width)
    mean = dataset.targets.mean(axis=0)
    std = np.maximum(dataset.targets.std(axis=0), preset.min_output_std)
    return mean, std


def evaluate(model: MotionModel, dataset: Dataset) -> dict:
    """Fit metrics of ``model`` on ``dataset``: per-joint and mean absolute error [rad], largest
    single error [rad], ended-flag accuracy (flag > 0.5 vs target, share of samples).

    Raises:
        ValueError: the model and the dataset have different joints.
    """
    if model.joint_names != dataset.joint_names:
        raise ValueError(
            f"model of the {model.robot} ({model.num_joints} joints) evaluated on "
            f"a {dataset.robot} dataset ({dataset.num_joints} joints)"
        )
    n = model.num_joints
    y = model.predict(dataset.time_s)
    err = np.abs(y[:, :n] - dataset.angles_rad)
    flag_ok = (y[:, n] > 0.5) == (dataset.targets[:, n] > 0.5)
    return {
        "mae_rad_per_joint": {j: float(v) for j, v in zip(model.joint_names, err.mean(axis=0))},
        "mae_rad": float(err.mean()),
        "max_error_rad": float(err.max()),
        "ended_accuracy": float(flag_ok.mean()),
        "n_samples": int(dataset.n_samples),
    }


def train_models(
    datasets: Sequence[Dataset],
    config: TrainConfig = TrainConfig(),
    progress: Callable[[TrainProgress], None] | None = None,
) -> list[MotionModel]:
    """Train one model per dataset (batched by input kind and joints); returns them in input
    order."""
    models: list[MotionModel | None] = [None] * len(datasets)
    # Networks stack only with equal shapes: same input width and the same N + 1 outputs.
    groups: dict[tuple[int, tuple[str, ...]], list[int]] = {}
    for i, d in enumerate(datasets):
        groups.setdefault((1 if d.period_s is None else 2, d.joint_names), []).append(i)
    for (in_dim, _), idx in groups.items():
        for i, m in zip(idx, _train_batch([datasets[i] for i in idx], in_dim, config, progress)):
            models[i] = m
    return models  # type: ignore[return-value]


def train_model(
    dataset: Dataset,
    config: TrainConfig = TrainConfig(),
    progress: Callable[[TrainProgress], None] | None = None,
) -> MotionModel:
    """Train one model."""
    return train_models([dataset], config, progress)[0]


def _train_batch(
    datasets: list[Dataset], in_dim: int, config: TrainConfig, progress
) -> list[MotionModel]:
    preset = config.schedule()
    n_joints = datasets[0].num_joints
    layout = Layout.for_joints(n_joints, in_dim)
    k, n_max = len(datasets), max(d.n_samples for d in datasets)
    x = np.zeros((k, n_max, in_dim))
    y = np.zeros((k, n_max, layout.out_dim))
    shells, scales = [], []
    for i, d in enumerate(datasets):
        mapping = input_mapping(d, preset)
        mean, std = _output_scaling(d, preset)
        shell = MotionModel(
            layout,
            np.zeros(layout.n_params, np.float32),
            **mapping,
            duration_s=float(d.time_s[-1]),
            output_mean=mean,
            output_std=std,
            preset=preset.name,
            robot=d.robot,
            joint_names=d.joint_names,
            metadata=dict(d.metadata),
        )
        x[i, : d.n_samples] = shell.network_inputs(d.time_s)
        y[i, : d.n_samples] = (d.targets - mean) / std
        shells.append(shell)
        scales.append(std[:n_joints])
    params0 = init_params(
        layout, np.random.default_rng(config.seed), preset.init, knot_range=preset.input_half_range
    )
    trainer = AdamTrainer(
        layout,
        np.repeat(params0[None], k, axis=0),
        x,
        y,
        np.array([d.n_samples for d in datasets]),
        preset.betas,
        preset.eps,
    )
    std_j = np.stack(scales)[:, None, :]  # (K, 1, N)
    names = tuple(d.name for d in datasets)
    total, done, start = preset.epochs, 0, time.perf_counter()

    def report(phase: int, lr: float, epochs_done: int) -> None:
        pred = trainer.predict()
        err = np.abs(pred[..., :n_joints] - y[..., :n_joints]) * std_j * trainer.valid[..., None]
        mae = err.sum(axis=(1, 2)) / (trainer.n_samples * n_joints)
        progress(
            TrainProgress(
                names,
                phase,
                lr,
                epochs_done,
                total,
                trainer.mse(),
                mae,
                time.perf_counter() - start,
            )
        )

    # One BLAS thread: on these tiny matrices a second thread only adds synchronisation, and
    # on a busy machine its spin-waits make an epoch ~40x slower (measured: 63 s vs 1.5 s).
    with np.errstate(over="ignore", under="ignore"), threadpool_limits(limits=1, user_api="blas"):
        for p, ph in enumerate(preset.phases):
            trainer.reset_optimizer()  # the study resets Adam at every phase
            cb = (lambda e, p=p, lr=ph.lr, base=done: report(p, lr, base + e)) if progress else None
            trainer.run(ph.epochs, ph.lr, callback=cb, every=config.log_every if progress else 0)
            done += ph.epochs
    wall_s = time.perf_counter() - start
    out = []
    for i, (shell, d) in enumerate(zip(shells, datasets)):
        model = replace(shell, params=trainer.params[i].copy())
        model.metrics = {
            **evaluate(model, d),
            "epochs": total,
            "wall_s": wall_s,
            "batch_size": k,
            "seed": config.seed,
            "toolkit_version": __version__,
        }
        out.append(model)
    return out


#: Training target kinds: the recorded angles as they are, or compensated references.
TARGET_REACHED = "reached"
TARGET_COMPENSATED = "compensated"


def training_dataset(
    path,
    topic: str | None = None,
    target: str | None = None,
    *,
    start_s: float | None = None,
    end_s: float | None = None,
    period: float | str | None = None,
    symmetric: bool = False,
) -> Dataset:
    """Dataset from a recording or study table, with the training target chosen.

    ``start_s``/``end_s`` cut the recording [s from its first sample] after the targets are
    made (``cut_dataset``); ``period`` makes the cut one cyclic motion: a period [s], or
    ``"auto"`` to find it in the angles (``detect_period_s``; a black-box recording of a walk
    does not say its period), or ``"steps"`` (``PERIOD_STEPS``) to time each step on its own
    from where the feet touch down (``learn.steps``: a walk that never repeats a step exactly,
    learned as the cycle of its mean step pair). Where the recording shows the feet, a period
    that is not the cycle of two steps (a multiple of it, or one step) is refused, and the
    steps' statistics (``metadata["steps"]``) and the walking speed over them
    (``metadata["walk_speed_m_s"]``) are kept. ``symmetric`` joins every sample of a cyclic motion by its mirror
    image half a cycle later (``learn.dataset.symmetric_cycle``; a straight walk), and its foot
    track likewise.

    ``target``: ``reached`` (learn the recorded values), ``compensated`` (learn the references
    that reproduce the recorded angles through the robot's motors: its speed servos, see
    ``mimic.learn.compensate``, or its PD motors, see ``mimic.learn.pd_compensate``, which
    needs the torso pose on ``/tf``) or None: compensated when the data are observed angles
    (``/joint_states``) that can be compensated, else reached.

    Raises:
        DatasetError, RecordingError: unreadable input; unknown target kind.
        MimicError: ``compensated`` asked for a PD-motor robot's recording without a torso
            pose.
    """

    if target not in (None, TARGET_REACHED, TARGET_COMPENSATED):
        raise DatasetError(
            f"unknown target {target!r}; use {TARGET_REACHED} or {TARGET_COMPENSATED}"
        )
    ds = observed_ds = dataset_from_file(path, topic)
    robot = get_robot(ds.robot)
    observed = ds.metadata.get("topic") == JOINT_STATES
    tf = _RecordedTf.read(path, ds)  # the recording's /tf, read once (None: there is none)
    torso = None
    if isinstance(robot.actuator, PDMotors) and target != TARGET_REACHED and observed:
        torso = None if tf is None else tf.torso_at_samples(robot, ds.time_s)
    if target is None:
        servos = isinstance(robot.actuator, SpeedServos)
        target = (
            TARGET_COMPENSATED if observed and (servos or torso is not None) else TARGET_REACHED
        )
    if target == TARGET_COMPENSATED:
        # Compensate the window being learned (and a margin), gaps inside it closed: what
        # lies outside (a skipped monitor frame, the robot moved by the referee) does not
        # matter (``learn.window``).
        # (The observed angles too: the steps and the period are read from the same samples.)
        ds = observed_ds = window(ds, start_s, end_s)
        if torso is not None:
            torso = tf.torso_at_samples(robot, ds.time_s)
    if target == TARGET_COMPENSATED and isinstance(robot.actuator, PDMotors):
        if torso is None:
            raise MimicError(
                f"the {robot.name} has PD motors: compensated targets need its observed angles "
                f"(/joint_states) and its torso pose on /tf, which {path} lacks; learn its "
                "reached angles (--target reached)"
            )
        ds = ds.with_angles(
            pd_compensated_targets(ds.time_s, ds.angles_rad, *torso, robot, tf.world),
            target=target,
        )
    elif target == TARGET_COMPENSATED:
        ds = ds.with_angles(
            compensate_references(ds.time_s, ds.angles_rad, ds.robot), target=target
        )
    else:
        ds = replace(ds, metadata={**ds.metadata, "target": target})
    ds = cut_dataset(ds, start_s, end_s)
    posture = None if tf is None else tf.start_posture(robot, ds.metadata.get("cut_s"))
    if posture is not None:
        ds = replace(ds, metadata={**ds.metadata, "start_posture": posture})
    if "ball_offset_m" not in ds.metadata and ds.period_s is None and period is None:
        offset = None if tf is None else tf.ball_offset_m(robot, ds.metadata.get("cut_s"))
        if offset is not None:
            ds = replace(ds, metadata={**ds.metadata, "ball_offset_m": offset})
    if period is None:
        return symmetric_cycle(ds) if symmetric else ds
    seen = cut_dataset(observed_ds, start_s, end_s)
    first_s = (seen.metadata.get("cut_s") or [0.0])[0]
    torso_quat = None
    if tf is not None and observed:
        torso = tf.torso_at_samples(robot, seen.time_s + first_s)
        torso_quat = None if torso is None else torso[1]
    steps = None
    if torso_quat is not None and robot.foot_links:
        steps = _steps(seen, torso_quat, robot, required=period == PERIOD_STEPS)
    elif period == PERIOD_STEPS:
        raise DatasetError(
            f"{ds.metadata.get('source', 'recording')}: --period steps finds the steps where "
            "the feet touch down, from the observed angles (/joint_states) and the torso pose "
            "on /tf, which this recording lacks; give a period in seconds or 'auto'"
        )
    phase_time_s = seen.time_s  # what the cycle's phase is read from, per sample
    if period == PERIOD_STEPS:
        period_s = steps.period_s
        phase_time_s = steps.warped_s[steps.keep]
        seen = replace(seen, time_s=phase_time_s, targets=seen.targets[steps.keep])
        ds = replace(ds, time_s=phase_time_s, targets=ds.targets[steps.keep])
        ds = replace(ds, metadata={**ds.metadata, "step_phase": True})
    elif period == "auto":
        # The period of what the robot did (its recorded values), not of the targets.
        period_s = detect_period_s(seen.time_s, seen.angles_rad)
        ds = replace(ds, metadata={**ds.metadata, "period_detected": True})
    else:
        try:
            period_s = float(period)
        except ValueError:
            raise DatasetError(
                f"--period must be a number of seconds, 'auto' or '{PERIOD_STEPS}', got {period!r}"
            ) from None
        t = np.asarray(ds.time_s, float)
        # The time the samples cover: first to last, and the last sample's own step.
        span_s = float(t[-1] - t[0] + np.median(np.diff(t))) if len(t) > 1 else 0.0
        if period_s > span_s * (1 + 1e-6):  # not one whole cycle in it: nothing to repeat
            raise DatasetError(
                f"--period {period_s:g} s is longer than the motion learned ({span_s:.2f} s of "
                f"{path}); give the period of one cycle, or --period auto"
            )
    if steps is not None:
        _check_period(period_s, steps, period)
        ds = replace(ds, metadata={**ds.metadata, "steps": steps.summary()})
        span = first_s + steps.touchdown_s[[0, -1]]
        speed = tf.walk_speed_m_s(robot, float(span[0]), float(span[1]))
        if speed is not None:
            ds = replace(ds, metadata={**ds.metadata, "walk_speed_m_s": speed})
    ds = average_jittery_joints(drop_non_repeating(as_cyclic(ds, period_s)))
    if symmetric:
        ds = symmetric_cycle(ds)
    track = None
    if torso_quat is not None:
        quat = torso_quat if period != PERIOD_STEPS else torso_quat[steps.keep]
        track = _foot_track(phase_time_s, seen.angles_rad, quat, robot, period_s)
    if track is None:
        return ds
    if symmetric:
        track = track.symmetric()
    return replace(ds, metadata={**ds.metadata, FOOT_TRACK_KEY: track.to_metadata()})


#: ``--period steps``: each step timed on its own, from the feet's touchdowns (``learn.steps``).
PERIOD_STEPS = "steps"
#: A period whose ratio to two mean steps lies outside this range is not the walk's cycle.
_CYCLE_RATIO = (0.8, 1.25)


def _steps(seen: Dataset, torso_quat: np.ndarray, robot, required: bool):
    """The walk's steps (``learn.steps.find_steps``) over the cut ``seen``; None if there are
    none and they were not ``required``."""

    kin = FootKinematics(robot)
    feet_z = np.stack([kin.feet_height_m(q, quat) for q, quat in zip(seen.angles_rad, torso_quat)])
    try:
        return find_steps(seen.time_s, feet_z, str(seen.metadata.get("source", "recording")))
    except MimicError:
        if required:
            raise
        return None


def _check_period(period_s: float, steps, period) -> None:
    """Refuse a cyclic motion's period that is not the cycle of two steps its feet show."""

    ratio = period_s / steps.period_s
    if _CYCLE_RATIO[0] <= ratio <= _CYCLE_RATIO[1]:
        return
    how = "found in the angles" if period == "auto" else "given"
    what = (
        f"{ratio:.1f} cycles of its steps"
        if ratio > 1
        else f"{ratio * 2:.1f} of its steps, not a cycle of two"
    )
    raise DatasetError(
        f"the period {period_s:.3f} s {how} is {what} (the feet show {steps.describe()}: a "
        f"cycle of two is {steps.period_s:.3f} s); give --period {steps.period_s:.3f}, or "
        f"--period {PERIOD_STEPS} to time each step on its own"
    )


def _foot_track(phase_time_s, angles_rad, torso_quat, robot, period_s):
    """The recorded cycle's foot track (``model.foot_track``: where the feet were under
    the torso by phase, for the balance layer's foot placement), from the observed angles and
    the torso's orientation over the cut, each sample at its phase ``phase_time_s /
    period_s``; None without two legs."""

    try:
        return foot_track(phase_time_s, angles_rad, torso_quat, robot, period_s)
    except MimicError:
        return None


def _interp_columns(t_new: np.ndarray, t: np.ndarray, values: np.ndarray) -> np.ndarray:
    """(len(t_new), K) linear interpolation of each column of (T, K) ``values`` sampled at
    ``t``, held at the ends."""
    return np.stack([np.interp(t_new, t, values[:, i]) for i in range(values.shape[1])], axis=1)


#: Farthest a ball may lie from the torso at a motion's start to count as the ball the motion
#: kicks [m] (a kick's ball lies 0.2-0.4 m ahead; our recorder puts an unused ball 3 m aside).
_KICK_REACH_M = 1.0


@dataclass(frozen=True)
class _RecordedTf:
    """A recording's ``/tf`` tracks in the world frame, timed [s] like its joint samples
    (from the joint topic's first message, as ``read_joint_table``), and its world."""

    world: str
    tracks: dict
    first_ns: int

    @classmethod
    def read(cls, path, ds: Dataset) -> _RecordedTf | None:

        if Path(path).suffix.lower() != ".mcap":
            return None
        rec = read_recording(path)
        topic = ds.metadata.get("topic")
        if L.TF not in rec.topics or topic not in rec.topics:
            return None
        world = rec.info.world if rec.info is not None else "nao"
        return cls(world, read_tf(rec), rec.topics[topic].first_ns)

    def _times_s(self, track) -> np.ndarray:
        return (track.times_ns - self.first_ns) / 1e9

    def torso_at_samples(self, robot, time_s: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
        """(positions, orientations) of the robot's root link at ``time_s``, or None."""
        track = self.tracks.get(robot.root_link)
        if track is None or len(track.times_ns) < 2:
            return None
        t = self._times_s(track)
        quat = _interp_columns(time_s, t, one_hemisphere(track.quat_wxyz))
        quat /= np.linalg.norm(quat, axis=1, keepdims=True)
        return _interp_columns(time_s, t, track.pos_m), quat

    def walk_speed_m_s(self, robot, start_s: float, end_s: float) -> float | None:
        """The torso's mean speed over the ground from ``start_s`` to ``end_s`` [m/s]: the
        straight distance between its places then, over the time; None without a torso."""
        track = self.tracks.get(robot.root_link)
        if track is None or len(track.times_ns) < 2 or not end_s > start_s:
            return None
        t = self._times_s(track)
        at = _interp_columns(np.array([start_s, end_s]), t, track.pos_m)
        return round(float(np.hypot(*(at[1, :2] - at[0, :2])) / (end_s - start_s)), 4)

    def start_posture(self, robot, cut_s: list[float] | None) -> str | None:
        """How the robot lay or stood at the motion's first sample (``learn.posture``), from
        its torso pose; None without a torso."""

        torso = self.torso_at_samples(robot, np.array([(cut_s or [0.0])[0]]))
        return None if torso is None else start_posture(torso[0][0], torso[1][0], robot)

    def ball_offset_m(self, robot, cut_s: list[float] | None) -> list[float] | None:
        """Where the ball lay in the robot frame (x forward, y left of the torso [m]) at the
        motion's first sample (a black-box kick wants the ball there), or None."""

        ball, torso = self.tracks.get(L.BALL_FRAME), self.tracks.get(robot.root_link)
        if ball is None or torso is None:
            return None
        t0 = (cut_s or [0.0])[0]
        b = ball.pos_m[int(np.argmin(np.abs(self._times_s(ball) - t0)))]
        k = int(np.argmin(np.abs(self._times_s(torso) - t0)))
        offset = in_robot_frame(b, torso.pos_m[k], yaw_from_quat(torso.quat_wxyz[k]))
        if np.hypot(*offset) > _KICK_REACH_M:
            return None  # a ball lying aside (a get-up, a wave) is not where a kick wanted it
        return [round(float(v), 4) for v in offset]


def recorded_torso(path, ds: Dataset) -> tuple[np.ndarray, np.ndarray] | None:
    """The torso (root link) pose a recording's ``/tf`` gives at ``ds``'s sample times:
    positions (T, 3) [m] and orientations (T, 4) (w, x, y, z), or None without one."""
    tf = _RecordedTf.read(path, ds)
    return None if tf is None else tf.torso_at_samples(get_robot(ds.robot), ds.time_s)


def pd_compensated_targets(
    time_s: np.ndarray,
    angles_rad: np.ndarray,
    torso_pos_m: np.ndarray,
    torso_quat_wxyz: np.ndarray,
    robot,
    world: str,
) -> np.ndarray:
    """(T, N) PD references for observed samples (``learn.pd_compensate.pd_references``), sent
    early by the command delay of ``world`` (``league`` or ours), as ``mimic train`` learns
    them."""

    refs = pd_references(time_s, angles_rad, torso_pos_m, torso_quat_wxyz, robot).references_rad
    # A reference acts from the cycle after it is sent (the league server: one cycle later
    # still): learn the one that acts mid-cycle, (delay + 0.5) cycles on.
    delay = get_world(world).command_delay_cycles
    return _interp_columns(time_s + (delay + 0.5) * CYCLE_S, time_s, refs)
