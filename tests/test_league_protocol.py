"""The league's wire format without a server: framing, s-expressions, names, messages."""

from __future__ import annotations

import math
import socket

import numpy as np
import pytest

from mimic.errors import MimicError
from mimic.league.client import format_command, parse_perception
from mimic.league.errors import LeagueConnectionError, LeagueError
from mimic.league.names import wire_names
from mimic.league.protocol import Connection, parse_address, parse_sexp
from mimic.robot.actuators import JointCommand
from mimic.robot.registry import get_robot

T1 = get_robot("t1")


def test_sexp_nesting_and_atoms():
    assert parse_sexp(b"(a 1)(b (c 2.5) d)") == [[b"a", b"1"], [b"b", [b"c", b"2.5"], b"d"]]
    assert parse_sexp(b"  ") == []
    assert parse_sexp(b"(nd(nd)(nd TRF(SLT 1 0)))") == [
        [b"nd", [b"nd"], [b"nd", b"TRF", [b"SLT", b"1", b"0"]]]
    ]
    with pytest.raises(ValueError, match="unclosed"):
        parse_sexp(b"(a (b)")
    with pytest.raises(ValueError, match="unbalanced"):
        parse_sexp(b"(a))")


def test_messages_are_length_prefixed_and_arrive_whole():
    a, b = socket.socketpair()
    left, right = Connection(a, ("pair", 1)), Connection(b, ("pair", 2))
    try:
        left.send(b"(init T1 mimic 7)")
        left.send(b"x" * 100_000)
        assert right.receive() == b"(init T1 mimic 7)"
        assert right.receive() == b"x" * 100_000
        assert right.receive(timeout_s=0.01) is None
        a.sendall(b"\x00\x00\x00\x05(syn")  # a message cut in two
        assert right.receive(timeout_s=0.01) is None
        a.sendall(b")")
        assert right.receive_available() == [b"(syn)"]
        left.close(linger_s=0.0)
        with pytest.raises(LeagueConnectionError, match="closed the connection"):
            right.receive()
    finally:
        right.close(linger_s=0.0)


def test_addresses():
    assert parse_address("localhost:60000", "--server") == ("localhost", 60000)
    assert parse_address("60001", "--server") == ("127.0.0.1", 60001)
    for bad in ("localhost", "host:0", "host:port", "host:70000"):
        with pytest.raises(LeagueConnectionError, match="HOST:PORT"):
            parse_address(bad, "--server")


def test_wire_names_come_from_the_mjcf():
    names = wire_names(T1)
    assert names.model_name == "T1"
    assert names.effectors[T1.joint_index("Right_Knee_Pitch")] == "rle4"
    assert names.effectors[T1.joint_index("AAHead_yaw")] == "he1"
    assert names.joint_by_sensor["q_rlj4"] == "Right_Knee_Pitch"
    assert len(set(names.effectors)) == T1.num_joints
    k1 = get_robot("k1")
    assert wire_names(k1).joint_by_sensor["q_laj1"] == "ALeft_Shoulder_Pitch"
    with pytest.raises(LeagueError, match="not a league robot"):
        wire_names(get_robot("nao"))


def test_motor_commands_carry_degrees_and_the_robots_gains():
    names = wire_names(T1)
    q = T1.stand_pose()
    text = format_command(JointCommand.references(q), T1, names).decode()
    items = parse_sexp(text.encode())
    assert len(items) == T1.num_joints
    knee = T1.joint_index("Right_Knee_Pitch")
    name, q_deg, dq, kp, kd, tau = items[knee]
    assert name == b"rle4" and float(dq) == 0 and float(tau) == 0
    assert float(q_deg) == pytest.approx(math.degrees(q[knee]), abs=1e-4)
    assert float(kp) == T1.actuator.kp_nm_rad[knee] and float(kd) == T1.actuator.kd_nm_s_rad[knee]
    with pytest.raises(MimicError, match="PD motors"):
        format_command(JointCommand.speeds(np.zeros(T1.num_joints)), T1, names)
    with pytest.raises(MimicError, match="23 joints"):
        format_command(JointCommand.references(np.zeros(22)), T1, names)


def _perception_text(angles_deg) -> bytes:
    names = wire_names(T1)
    by_joint = {j: s for s, j in names.joint_by_sensor.items()}
    joints = "".join(
        f"(HJ (n {by_joint[j]})(ax {a})(vx 1.5))" for j, a in zip(T1.joint_names, angles_deg)
    )
    return (
        b"(time (now 12.34))(GS (t 0.0)(pm BeforeKickOff)(tl mimic)(sl 0)(sr 0))"
        b"(quat (n torso_quat) (q 0.707 0.0 0.0 -0.707))(pos (n torso_pos) (p -15.0 21.0 "
        b"0.673))(GYR (n torso_gyro) (rt 10.0 0.0 -20.0))(ACC (n torso_acc) (a 0.1 0.0 "
        b"9.81))" + joints.encode() + b"(See (B (pol 25.73 35.68 -2.2)))"
    )


def test_perceptions_in_the_robots_joint_order_and_units():
    angles = np.arange(T1.num_joints) * 2.5 - 20
    p = parse_perception(_perception_text(angles), T1, wire_names(T1))
    np.testing.assert_allclose(p.joint_angles_rad, np.radians(angles))
    np.testing.assert_allclose(p.joint_speeds_rad_s, math.radians(1.5))
    np.testing.assert_allclose(p.gyro_rad_s, np.radians([10.0, 0.0, -20.0]))
    np.testing.assert_allclose(p.accelerometer_m_s2, [0.1, 0.0, 9.81])
    assert np.linalg.norm(p.torso_quat_wxyz) == pytest.approx(1.0)
    np.testing.assert_allclose(p.torso_pos_m, [-15.0, 21.0, 0.673])
    assert p.time_s == 12.34 and p.play_mode == "BeforeKickOff"


def test_perceptions_of_another_robot_are_refused():
    text = _perception_text(np.zeros(T1.num_joints)).replace(b"(HJ (n q_rlj6)", b"(HJ (n x)")
    with pytest.raises(LeagueError, match="lack 1 t1 joints"):
        parse_perception(text, T1, wire_names(T1))
