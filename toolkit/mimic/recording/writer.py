"""Streaming MCAP writer for the recording layout (see ``mimic.recording.layout``).

Chunks are compressed (zstd) and closed every ``flush_period_s`` of recorded time, and the
file is flushed then, so a recording cut off by a crash or a kill loses at most that much.
Chunks carry CRCs of their data and the data section its CRC (readers check both).

Times: callers give simulated time from the start of the recording [ns]. Log times and
message header stamps are that plus the wall-clock time the recording started
(``start_wall_time_ns``, Unix epoch), so Rerun and Foxglove show the date it was made; the
``mimic`` metadata record keeps ``start_wall_time_ns``, so simulated time is
``log_time - start_wall_time_ns`` (``mimic.recording.reader`` gives times from the first
sample, for old files with log times from 0 too).

The file is written under a temporary name and moved into place when finished
(``mimic.files``); a recording stopped by Ctrl-C (``KeyboardInterrupt``) is finished, marked
interrupted, and kept; one stopped by another error is removed.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from mcap.well_known import MessageEncoding, SchemaEncoding
from mcap.writer import CompressionType, Writer

# mcap-ros2-support's CDR encoder generator (the one its own Writer uses).
from mcap_ros2._dynamic import serialize_dynamic

from mimic import __version__
from mimic.errors import MimicError, RecordingError
from mimic.files import PendingOutput
from mimic.recording import cdr
from mimic.recording import layout as L

__all__ = ["RecordingWriter"]


class RecordingWriter:
    """Writes one recording; a context manager (the file is finished on exit, even on error).

    Args:
        path: output ``.mcap`` file (parent folders are created).
        info: what the recording is (the ``mimic`` metadata record).
        urdf: robot description to publish once at t = 0 (None: none).
        flush_period_s: close the chunk and flush the file after this much recorded time [s].
        compression: ``zstd``, ``lz4`` or ``none``.
        start_wall_time_ns: wall-clock time of simulated time 0 [ns since the Unix epoch]
            (None: now).
        overwrite: replace an existing ``path`` when finished (False: refuse then, keeping
            the new file under its temporary name).
    """

    def __init__(
        self,
        path: str | Path,
        info: L.RecordingInfo,
        *,
        urdf: str | None = None,
        flush_period_s: float = 0.25,
        compression: str = "zstd",
        start_wall_time_ns: int | None = None,
        overwrite: bool = True,
    ) -> None:
        self.path = Path(path)
        kinds = {
            "zstd": CompressionType.ZSTD,
            "lz4": CompressionType.LZ4,
            "none": CompressionType.NONE,
        }
        if compression not in kinds:
            raise RecordingError(f"unknown compression {compression!r}; use zstd, lz4 or none")
        try:
            self._output = PendingOutput(self.path, overwrite=overwrite)
            self._file = open(self._output.tmp, "wb")
        except MimicError as err:
            raise RecordingError(str(err)) from None
        except OSError as err:
            self._output.discard()
            raise RecordingError(f"cannot write {self.path}: {err.strerror}") from None
        self.start_wall_time_ns = int(
            time.time_ns() if start_wall_time_ns is None else start_wall_time_ns
        )
        # A large chunk size: chunks are closed by time (flush_period_s), not by size.
        self._mcap = Writer(
            self._file,
            chunk_size=4 * 1024 * 1024,
            compression=kinds[compression],
            enable_crcs=True,
            enable_data_crcs=True,
        )
        self._mcap.start(profile="ros2", library=f"mimic {__version__}")
        self._schema_ids = {
            name: self._mcap.register_schema(name, SchemaEncoding.ROS2, text.encode())
            for name, text in L.SCHEMAS.items()
        }
        self._encoders = {
            name: serialize_dynamic(name, text)[name] for name, text in L.SCHEMAS.items()
        }
        self._channels: dict[str, tuple[int, str]] = {}
        self._sequence: dict[str, int] = {}
        self._flush_ns = int(flush_period_s * L.NS_PER_S)
        self._last_flush_ns = 0
        self.last_time_ns = 0
        self.info = info
        self._finished = False
        self._mcap.add_metadata(
            L.METADATA_NAME,
            {**info.to_metadata(), L.START_WALL_TIME_KEY: str(self.start_wall_time_ns)},
        )
        if urdf is not None:
            self.write(L.ROBOT_DESCRIPTION, 0, {"data": urdf})

    # --- generic ---------------------------------------------------------------------------
    def write(self, topic: str, time_ns: int, message: dict, schema: str | None = None) -> None:
        """Write one message (a dict shaped like the ROS 2 message) at simulated ``time_ns``
        [ns]; a ``header.stamp`` in it is the caller's (give ``stamp_ns(time_ns)``)."""
        name = schema or self._channels.get(topic, (0, L.TOPIC_SCHEMAS.get(topic)))[1]
        if name not in self._encoders:
            raise RecordingError(
                f"no schema for topic {topic}; pass schema= one of {', '.join(L.SCHEMAS)}"
            )
        self.write_cdr(topic, time_ns, self._encoders[name](message), name)

    def write_cdr(self, topic: str, time_ns: int, data: bytes, schema: str | None = None) -> None:
        """Write one already CDR-encoded message of ``schema`` (default: the topic's) at
        simulated ``time_ns`` [ns] (log time: ``stamp_ns(time_ns)``)."""
        if topic not in self._channels:
            name = schema or L.TOPIC_SCHEMAS[topic]
            channel_id = self._mcap.register_channel(
                topic, MessageEncoding.CDR, self._schema_ids[name]
            )
            self._channels[topic] = (channel_id, name)
            self._sequence[topic] = 0
        channel_id = self._channels[topic][0]
        time_ns = int(time_ns)
        stamp = self.stamp_ns(time_ns)
        self._mcap.add_message(
            channel_id,
            log_time=stamp,
            publish_time=stamp,
            data=data,
            sequence=self._sequence[topic],
        )
        self._sequence[topic] += 1
        self.last_time_ns = max(self.last_time_ns, time_ns)
        if time_ns - self._last_flush_ns >= self._flush_ns:
            self.flush()

    def stamp_ns(self, time_ns: int) -> int:
        """Wall-clock time [ns since the Unix epoch] of simulated ``time_ns`` [ns]."""
        return self.start_wall_time_ns + int(time_ns)

    def flush(self) -> None:
        """Close the current chunk and push everything written so far to the file."""
        self._mcap.flush()
        self._last_flush_ns = self.last_time_ns

    # --- typed helpers ---------------------------------------------------------------------
    def write_joints(
        self,
        time_ns: int,
        positions_rad: np.ndarray,
        velocities_rad_s: np.ndarray | None = None,
        *,
        topic: str = L.JOINT_STATES,
        names: Sequence[str] | None = None,
    ) -> None:
        """A JointState on ``topic``: (N,) positions [rad], optional (N,) speeds [rad/s],
        named ``names`` (default: the recording's ``info.joint_order``, its robot's order)."""
        names = self.info.joint_order if names is None else names
        if len(positions_rad) != len(names):  # another robot's vector: refuse, not corrupt
            raise RecordingError(
                f"{topic}: {len(positions_rad)} positions for {len(names)} "
                f"joints of the {self.info.robot}"
            )
        self.write_cdr(
            topic,
            time_ns,
            cdr.encode_joint_state(self.stamp_ns(time_ns), names, positions_rad, velocities_rad_s),
            "sensor_msgs/msg/JointState",
        )

    def write_ended(self, time_ns: int, ended: bool) -> None:
        """The motion-ended flag for the joint sample at ``time_ns``."""
        self.write_cdr(L.ENDED, time_ns, cdr.encode_bool(ended))

    def write_tf(
        self,
        time_ns: int,
        parents: Sequence[str],
        children: Sequence[str],
        pos_m: np.ndarray,
        quat_wxyz: np.ndarray,
    ) -> None:
        """One TFMessage: child poses (n, 3) [m] and (n, 4) quaternions in their parents."""
        self.write_cdr(
            L.TF,
            time_ns,
            cdr.encode_tf(self.stamp_ns(time_ns), parents, children, pos_m, quat_wxyz),
        )

    # --- ending ----------------------------------------------------------------------------
    def finish(self, *, interrupted: bool = False, **end_info: str) -> None:
        """Write the ``mimic.end`` record, the summary and the footer; close the file and
        move it into place."""
        if self._finished:
            return
        self._finished = True
        try:
            end = {
                "interrupted": "true" if interrupted else "false",
                "last_time_ns": str(self.last_time_ns),
                **{k: str(v) for k, v in end_info.items()},
            }
            self._mcap.add_metadata(L.END_METADATA_NAME, end)
            self._mcap.finish()
        except BaseException:
            self.abandon()
            raise
        self._file.close()
        self._output.commit()

    def abandon(self) -> None:
        """Close and remove the unfinished file (nothing is left under either name)."""
        self._finished = True
        try:
            self._file.close()
        finally:
            self._output.discard()

    def __enter__(self) -> RecordingWriter:
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        if exc_type is None or issubclass(exc_type, KeyboardInterrupt):
            self.finish(interrupted=exc_type is not None)
        elif not self._finished:
            self.abandon()
