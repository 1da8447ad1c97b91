"""Fast CDR (XCDR1, little endian) encoding of the few ROS 2 messages we write every cycle.

mcap-ros2-support's generic encoder walks the schema per field in Python; at 50 Hz with 24
transforms per TF message that cost more than the physics. These encoders write the same
bytes (checked against it in tests) with a handful of ``struct`` calls per message.
"""

from __future__ import annotations

import struct
from collections.abc import Sequence
from functools import lru_cache

import numpy as np

__all__ = ["encode_joint_state", "encode_tf", "encode_bool", "encode_string"]

_ENCAPSULATION = b"\x00\x01\x00\x00"  # CDR, little endian
_U32 = struct.Struct("<I")
_STAMP = struct.Struct("<iI")
_ZEROS = bytes(8)


class _Buffer:
    """Byte parts with CDR alignment counted from the end of the encapsulation header."""

    __slots__ = ("parts", "n")

    def __init__(self) -> None:
        self.parts: list[bytes] = [_ENCAPSULATION]
        self.n = 0

    def align(self, k: int) -> None:
        pad = -self.n % k
        if pad:
            self.parts.append(_ZEROS[:pad])
            self.n += pad

    def raw(self, data: bytes) -> None:
        self.parts.append(data)
        self.n += len(data)

    def u32(self, value: int) -> None:
        self.align(4)
        self.raw(_U32.pack(value))

    def stamp(self, time_ns: int) -> None:
        self.align(4)
        self.raw(_STAMP.pack(int(time_ns // 1_000_000_000), int(time_ns % 1_000_000_000)))

    def string(self, text: str) -> None:
        data = text.encode() + b"\0"
        self.u32(len(data))
        self.raw(data)

    def f64_array(self, values: np.ndarray | None) -> None:
        n = 0 if values is None else len(values)
        self.u32(n)
        if n:
            self.align(8)
            self.raw(np.asarray(values, dtype="<f8").tobytes())

    def f64(self, values: np.ndarray) -> None:
        self.align(8)
        self.raw(np.asarray(values, dtype="<f8").tobytes())

    def bytes(self) -> bytes:
        return b"".join(self.parts)


@lru_cache(maxsize=32)
def _joint_state_names(names: tuple[str, ...], frame_id: str) -> tuple[bytes, int]:
    """Bytes after the stamp up to the position array (constant per name list), and the
    body offset they end at."""
    b = _Buffer()
    b.raw(bytes(8))  # the stamp, written per message
    b.string(frame_id)
    b.u32(len(names))
    for name in names:
        b.string(name)
    return b"".join(b.parts[2:]), b.n


def encode_joint_state(
    time_ns: int,
    names: Sequence[str],
    position: np.ndarray,
    velocity: np.ndarray | None = None,
    frame_id: str = "",
) -> bytes:
    """sensor_msgs/msg/JointState with an empty effort array."""
    middle, n = _joint_state_names(tuple(names), frame_id)
    b = _Buffer()
    b.stamp(time_ns)
    b.parts.append(middle)
    b.n = n
    b.f64_array(position)
    b.f64_array(velocity)
    b.f64_array(None)
    return b.bytes()


@lru_cache(maxsize=8)
def _tf_layout(parents: tuple[str, ...], children: tuple[str, ...]):
    """A TFMessage template with zeroed stamps and poses, and the byte indices of both."""
    b = _Buffer()
    b.u32(len(children))
    stamps, poses = [], []
    for parent, child in zip(parents, children):
        b.align(4)
        stamps.append(b.n)
        b.raw(bytes(8))
        b.string(parent)
        b.string(child)
        b.align(8)
        poses.append(b.n)
        b.raw(bytes(56))  # translation xyz, rotation xyzw: 7 float64
    head = len(_ENCAPSULATION)
    stamp_idx = head + np.array(stamps)[:, None] + np.arange(8)
    pose_idx = head + np.array(poses)[:, None] + np.arange(56)
    return b.bytes(), stamp_idx, pose_idx


def encode_tf(
    time_ns: int,
    parents: Sequence[str],
    children: Sequence[str],
    pos_m: np.ndarray,
    quat_wxyz: np.ndarray,
) -> bytes:
    """tf2_msgs/msg/TFMessage: one TransformStamped per child, all at ``time_ns``."""
    template, stamp_idx, pose_idx = _tf_layout(tuple(parents), tuple(children))
    out = np.frombuffer(template, dtype=np.uint8).copy()
    stamp = np.frombuffer(
        _STAMP.pack(int(time_ns // 1_000_000_000), int(time_ns % 1_000_000_000)), dtype=np.uint8
    )
    out[stamp_idx] = stamp
    q = np.asarray(quat_wxyz, dtype=float)
    poses = np.concatenate([np.asarray(pos_m, dtype=float), q[:, 1:], q[:, :1]], axis=1)
    out[pose_idx] = np.ascontiguousarray(poses, dtype="<f8").view(np.uint8).reshape(-1, 56)
    return out.tobytes()


def encode_bool(value: bool) -> bytes:
    """std_msgs/msg/Bool."""
    return _ENCAPSULATION + (b"\x01" if value else b"\x00")


def encode_string(text: str) -> bytes:
    """std_msgs/msg/String."""
    b = _Buffer()
    b.string(text)
    return b.bytes()
