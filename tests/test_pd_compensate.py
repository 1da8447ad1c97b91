"""PD compensation: references rebuilt from an observed T1 walk reproduce it through the motors.

The T1 other team's walk is recorded in our world (observed angles and the torso pose only);
from one recorded mid-walk instant the robot is set to the recorded state and continues open
loop, once with the reached angles as references (the study's replay) and once with the
compensated references. The physical outcome decides: how long the robot stays up and how
close its joints stay to the recording.
"""

from __future__ import annotations

import numpy as np
import pytest

from mimic.errors import MimicError
from mimic.learn.pd_compensate import body_rates_rad_s, local_polynomial, pd_references
from mimic.learn.train import training_dataset
from mimic.recording import layout as L
from mimic.recording.reader import read_joint_table, read_recording, read_tf
from mimic.recording.recorder import record
from mimic.robot.actuators import JointCommand
from mimic.robot.registry import get_robot
from mimic.world.base import CYCLE_S
from mimic.world.mujoco_world import MujocoWorld

T1 = get_robot("t1")


@pytest.fixture(scope="module")
def walk(tmp_path_factory):
    """(times, angles, torso positions, torso orientations) of a recorded T1 walk, 50 Hz."""
    from mimic.agents.registry import make_agent

    path = tmp_path_factory.mktemp("pd") / "t1_walk.mcap"
    record(make_agent("other-team-walk", robot="t1"), path, duration_s=6.0)
    rec = read_recording(path)
    table = read_joint_table(rec, L.JOINT_STATES)
    torso = read_tf(rec)[T1.root_link]
    assert len(torso.times_ns) == table.height  # one pose per joint sample
    t = table[L.TIME_COLUMN].to_numpy()
    return path, t, table.select(T1.joint_names).to_numpy(), torso.pos_m, torso.quat_wxyz


def _continue(walk, references: np.ndarray, start: int) -> tuple[int, float]:
    """Set the robot to the recorded state at sample ``start`` and play ``references`` open
    loop: (cycles until it fell or the recording ended, mean joint error over 0.5 s [rad])."""
    _, t, q, pos, quat = walk
    dt = float(np.median(np.diff(t)))
    q_s, dq, _ = local_polynomial(q, dt, 3, 3)
    p_s, dp, _ = local_polynomial(pos, dt, 3, 3)
    quat_s, dquat, _ = local_polynomial(quat, dt, 3, 3)
    quat_s /= np.linalg.norm(quat_s, axis=1, keepdims=True)
    omega = body_rates_rad_s(quat_s[start : start + 1], dquat[start : start + 1])[0]
    world = MujocoWorld("t1")
    world.set_robot_state(p_s[start], quat_s[start], q_s[start], dp[start], omega, dq[start])
    errors = []
    for k in range(start, len(t) - 1):
        world.step(JointCommand.references(references[k]))
        errors.append(np.abs(world.joint_angles_rad() - q_s[k + 1]).mean())
        if world.fallen():
            break
    return len(errors), float(np.mean(errors[: round(0.5 / CYCLE_S)]))


def test_compensated_references_keep_a_recorded_walk_going(walk):
    _, t, q, pos, quat = walk
    assert np.median(np.diff(t)) == pytest.approx(CYCLE_S, abs=1e-6)
    comp = pd_references(t, q, pos, quat, "t1")
    assert comp.references_rad.shape == q.shape
    # A walk: each foot carries the robot a good part of the time, one foot at a time often.
    assert 0.3 < comp.contacts.mean(axis=0).min() and (comp.contacts.sum(axis=1) == 1).any()
    assert np.all(np.abs(comp.torques_nm) <= T1.actuator.max_torque_nm + 1e-9)
    # Three mid-walk instants (walks are chaotic: one start alone proves little).
    outcomes = []
    for start in (60, 100, 140):
        remaining = len(t) - 1 - start
        reached_cycles, reached_err = _continue(walk, q, start)
        comp_cycles, comp_err = _continue(walk, comp.references_rad, start)
        outcomes.append((reached_cycles, comp_cycles, remaining, reached_err, comp_err))
        # Reached angles as references sag and lag again: the robot falls within a second
        # (measured: 30-46 cycles from six instants), far off the recorded joint paths.
        assert reached_cycles < 60 and reached_err > 0.04, outcomes
        # The compensated ones track the recording closely (measured: 0.009 rad) ...
        assert comp_err < 0.02, outcomes
    # ... and walk on open loop, most of the time to the recording's end (measured: from 6
    # instants, 3 to the end, the others 221, 215 and 205 cycles of 253, 233 and 213).
    assert sum(c >= min(150, r) for _, c, r, _, _ in outcomes) >= 2, outcomes


def test_training_compensates_a_pd_robot_with_a_torso_pose(walk):
    path = walk[0]
    ds = training_dataset(path, L.JOINT_STATES)  # default: compensated, the torso is there
    assert ds.metadata["target"] == "compensated" and ds.robot == "t1"
    reached = training_dataset(path, L.JOINT_STATES, "reached")
    assert reached.metadata["target"] == "reached"
    shift = np.abs(ds.angles_rad - reached.angles_rad).max(axis=0)
    # The support legs' references lead their sagging angles; the head barely moves.
    knee = T1.joint_names.index("Left_Knee_Pitch")
    assert shift[knee] > 0.02 and shift[T1.joint_names.index("AAHead_yaw")] < 0.01


def test_a_short_strike_at_the_monitor_rate_keeps_its_peak(walk):
    """The league's 25 Hz: the fits reach 0.06 s each side (2 samples; 3 at our 50 Hz), and
    the reference builds on the observed angle, so a kick's brief peak is not flattened."""
    from mimic.learn.pd_compensate import PdCompensationConfig

    config = PdCompensationConfig()
    assert (config.half_window(0.02), config.half_window(0.04)) == (3, 2)
    _, t, q, pos, quat = walk
    t25, q25, pos25, quat25 = t[::2], q[::2].copy(), pos[::2], quat[::2]
    knee = T1.joint_names.index("Right_Knee_Pitch")
    k = len(t25) // 2
    q25[k, knee] += 0.3  # one sample: a snap of the shank, as a kick's strike is seen
    comp = pd_references(t25, q25, pos25, quat25, "t1")
    # The references peak where the angle did (measured: 0.14 rad above the sample before,
    # 0.48 above the one after). Built on the smoothed angle the peak was gone: a 5-sample
    # cubic puts its top a sample early and 0.15 rad lower.
    ref = comp.references_rad[:, knee]
    assert ref[k] > ref[k - 1] + 0.1 and ref[k] > ref[k + 1] + 0.1
    smoothed, _, _ = local_polynomial(q25[:, knee], 0.04, 2, 3)
    assert q25[k, knee] - smoothed[k] > 0.1 and smoothed[k - 1] > smoothed[k]


def test_bad_input_is_one_line():
    t = np.arange(20) * CYCLE_S
    q = np.tile(T1.stand_pose_rad, (20, 1))
    with pytest.raises(MimicError, match="needs PD motors; the nao") as err:
        pd_references(t, np.zeros((20, 22)), np.zeros((20, 3)), np.ones((20, 4)), "nao")
    assert "\n" not in str(err.value)
    with pytest.raises(MimicError, match="evenly spaced"):
        pd_references(t**1.5, q, np.zeros((20, 3)), np.tile([1.0, 0, 0, 0], (20, 1)), "t1")
    with pytest.raises(MimicError, match="at least 7 samples"):
        pd_references(t[:5], q[:5], np.zeros((5, 3)), np.tile([1.0, 0, 0, 0], (5, 1)), "t1")


def test_the_view_shows_the_compensated_references_of_a_t1(walk, tmp_path):
    from mimic.learn.presets import FAST
    from mimic.learn.train import TrainConfig, train_model
    from mimic.model.model_file import save_model
    from mimic.viz.recording import view_recording

    path = walk[0]
    ds = training_dataset(path, L.JOINT_STATES)
    model = tmp_path / "walk.mimic"
    save_model(train_model(ds, TrainConfig(FAST, epochs=300)), model)
    logged = view_recording(path, model=model, save=tmp_path / "view.rrd")
    assert logged["series"] == ["reached", "learned", "compensated", "replayed"]


def test_a_twist_against_the_ground_gets_the_friction_the_ground_gave():
    """Lying on its back the T1 twists its waist 1.2 rad in 0.3 s and raises a leg: the
    ground's friction holds the torso while the pelvis and legs drag. The friction-cone split
    (an option) finds more of the waist's torque than the least-squares one (measured:
    0.060 against 0.085 rad rms from the references sent)."""
    from mimic.episode import Scene
    from mimic.learn.pd_compensate import PdCompensationConfig

    world = MujocoWorld("t1")
    Scene(posture="lying_back", settle_s=0.3).setup(world, np.random.default_rng(0))
    waist, hip = T1.joint_names.index("Waist"), T1.joint_names.index("Left_Hip_Pitch")
    sent, q, pos, quat = [], [], [], []
    for k in range(60):
        ref = np.array(T1.stand_pose_rad)
        ref[waist] = min(1.2, 1.2 * k * CYCLE_S / 0.3) if k > 5 else 0.0
        ref[hip] = -min(1.0, k * CYCLE_S / 0.3)
        q.append(world.joint_angles_rad().copy())
        pos.append(world.torso_pos_m().copy())
        quat.append(world.torso_quat_wxyz().copy())
        sent.append(ref)
        world.step(JointCommand.references(ref))
    sent, q, pos, quat = map(np.array, (sent, q, pos, quat))
    t = np.arange(len(q)) * CYCLE_S
    cone = PdCompensationConfig(friction=1.0, saturation_share=0.9)
    errors = {}
    for name, config in (("cone", cone), ("least squares", PdCompensationConfig())):
        refs = pd_references(t, q, pos, quat, "t1", config).references_rad
        errors[name] = float(np.sqrt(np.mean((refs[5:50, waist] - sent[5:50, waist]) ** 2)))
    assert errors["cone"] < 0.075 < errors["least squares"], errors


def test_a_saturated_push_is_referenced_where_it_ends():
    """Step 8: over a push whose needed torque reaches the motor's limit, the reference is
    the farthest the push reaches from there on (its bound rises as the joint catches up)."""
    from mimic.learn.pd_compensate import _saturation_envelope

    refs = np.array([[0.0], [0.2], [0.5], [0.9], [1.0], [0.8], [0.3]])
    torques = np.array([[5.0], [29.0], [30.0], [30.0], [28.0], [-5.0], [-29.0]])
    saturated = np.abs(torques) >= 27.0
    out = _saturation_envelope(refs, torques, saturated)
    assert out[:, 0].tolist() == [0.0, 1.0, 1.0, 1.0, 1.0, 0.8, 0.3]
