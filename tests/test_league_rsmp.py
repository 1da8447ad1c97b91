"""Scene-graph frames and decoding, on frames written here from the T1's own MuJoCo model.

The frames follow the server's layout (a body: its transform, a shape, its child bodies;
local transforms, column-major, 4 decimals; diff frames bare except for moved nodes), so the
decoder is checked against known joint angles, including a shoulder pitch beyond -pi.
"""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from mimic.league.decode import PlayerDecoder
from mimic.league.rsmp import SceneState, is_rsmp
from mimic.robot.mjcf_reader import load_model
from mimic.robot.registry import get_robot

T1 = get_robot("t1")


def _slt(rot: np.ndarray, pos: np.ndarray) -> str:
    m = np.eye(4)
    m[:3, :3], m[:3, 3] = rot, pos
    return "(SLT " + " ".join(f"{v:.4f}" for v in m.T.ravel()) + ")"


def _robot_nodes(m, d, b: int, full: bool, moved: set[int]) -> str:
    p = m.body_parentid[b]
    rp, rc = d.xmat[p].reshape(3, 3), d.xmat[b].reshape(3, 3)
    rot, pos = rp.T @ rc, rp.T @ (d.xpos[b] - d.xpos[p])
    trf = f"(nd TRF{_slt(rot, pos)}" if (full or b in moved) else "(nd"
    shape = "(nd SMN (setVisible 1)(load models/T1/part.STL)(sMat gray))" if full else "(nd)"
    kids = "".join(
        _robot_nodes(m, d, c, full, moved)
        for c in range(m.nbody)
        if m.body_parentid[c] == b and c != b
    )
    return f"{trf}{shape}{kids})"


def _frame(
    m,
    d,
    time_s: float,
    full: bool,
    moved: set[int] = frozenset(),
    ball=(1.0, 2.0, 0.11),
    team="mimic",
    unum=7,
) -> bytes:
    eye = np.eye(3)
    root = m.body(T1.root_link).id
    robot = _robot_nodes(m, d, root, full, moved)
    agent = f"(nd DSC(agent {team} {unum}){robot})" if full else f"(nd{robot})"
    ball_node = (
        (f"(nd DSC(ball)(nd TRF{_slt(eye, np.array(ball))}(nd SMN (load StdUnitSphere))))")
        if full
        else "(nd(nd(nd)))"
    )
    world = f"(nd TRF{_slt(eye, np.zeros(3))}" if full else "(nd"
    graph = f"{world}{ball_node}{agent})"
    return (
        f"((RSMP 1 0)((gt 1 0){time_s:.2f})((sg 1 0){'full' if full else 'diff'}{graph})"
        f"((gs 1 0)(time 0.0)(play_mode 0)(team_left {team})))"
    ).encode()


@pytest.fixture(scope="module")
def model():
    return load_model(T1.mjcf_path)


def _pose(model, angles, torso=(0.5, -1.0, 0.6)):
    d = mujoco.MjData(model)
    root_q = model.jnt_qposadr[model.body_jntadr[model.body(T1.root_link).id]]
    d.qpos[root_q : root_q + 3] = torso
    d.qpos[root_q + 3 : root_q + 7] = [np.cos(0.2), 0.0, 0.0, np.sin(0.2)]
    for name, q in zip(T1.joint_names, angles):
        d.qpos[model.jnt_qposadr[model.joint(name).id]] = q
    mujoco.mj_kinematics(model, d)
    return d


def test_full_frame_decodes_to_the_joint_angles(model):
    rng = np.random.default_rng(1)
    angles = rng.uniform(T1.lower_limits_rad, T1.upper_limits_rad)
    angles[T1.joint_index("Left_Shoulder_Pitch")] = -3.25  # beyond -pi: no wrap to +3.03
    d = _pose(model, angles)
    state = SceneState()
    assert state.apply(_frame(model, d, 3.4, full=True))
    assert [(p.team, p.player, p.model) for p in state.players] == [("mimic", 7, "T1")]
    np.testing.assert_allclose(state.ball_pos_m(), [1.0, 2.0, 0.11])
    sample = PlayerDecoder(T1).sample(state, "mimic", 7)
    assert sample.time_s == pytest.approx(3.4 - 0.005)  # poses are one physics step old
    assert np.abs(sample.joint_angles_rad - angles).max() < 1e-3  # 4 decimals
    np.testing.assert_allclose(sample.torso_pos_m, [0.5, -1.0, 0.6], atol=1e-4)
    assert abs(abs(np.dot(sample.torso_quat_wxyz, [np.cos(0.2), 0, 0, np.sin(0.2)])) - 1) < 1e-6
    assert PlayerDecoder(T1).sample(state, "mimic", 8) is None


def test_diff_frames_update_what_moved_only(model):
    zero = np.zeros(T1.num_joints)
    state = SceneState()
    state.apply(_frame(model, _pose(model, zero), 1.0, full=True))
    knee = T1.joint_index("Right_Knee_Pitch")
    bent = zero.copy()
    bent[knee] = 1.0
    shank = model.body(T1.joints[knee].child_link).id
    assert state.apply(_frame(model, _pose(model, bent), 1.04, full=False, moved={shank}))
    sample = PlayerDecoder(T1).sample(state, "mimic", 7)
    assert sample.joint_angles_rad[knee] == pytest.approx(1.0, abs=1e-3)
    assert np.abs(np.delete(sample.joint_angles_rad, knee)).max() < 1e-3
    assert state.time_s == 1.04 and state.frames == 2


def test_a_diff_that_does_not_fit_waits_for_the_next_full_frame(model):
    state = SceneState()
    assert not state.apply(_frame(model, _pose(model, np.zeros(23)), 1.0, full=False))
    assert state.skipped == 1 and not state.valid  # no full frame yet
    state.apply(_frame(model, _pose(model, np.zeros(23)), 1.04, full=True))
    assert not state.apply(b"((RSMP 1 0)((gt 1 0)1.08)((sg 1 0)diff(nd(nd))))")
    assert not state.valid and state.players == ()
    assert not state.apply(b"((RSMP 1 0)((gt 1 0)1.1")  # cut off
    assert state.apply(_frame(model, _pose(model, np.zeros(23)), 1.12, full=True))


def test_a_teleport_frame_is_refused_not_misread(model):
    """After a placement the server shows the root at its new place, the rest not yet."""
    state = SceneState()
    frame = _frame(model, _pose(model, np.zeros(23)), 1.0, full=True).decode()
    # Move the first child body (head) away from where the description says it hangs.
    start = frame.index("(nd TRF", frame.index("DSC(agent"))
    head = frame.index("(nd TRF", frame.index("(nd SMN", start))
    slt_end = frame.index(")", head)
    numbers = frame[head + len("(nd TRF(SLT ") : slt_end].split()
    numbers[12] = "0.3000"
    frame = frame[:head] + "(nd TRF(SLT " + " ".join(numbers) + frame[slt_end:]
    state.apply(frame.encode())
    assert state.valid and PlayerDecoder(T1).sample(state, "mimic", 7) is None


def test_rsmp_is_recognised_by_its_first_bytes():
    assert is_rsmp(b"((RSMP 1 0)((gt 1 0)0.00)")
    assert is_rsmp(b"\n  ((RSMP 1 0)")
    assert not is_rsmp(b"kick::left_hip_pitch 0.1")
