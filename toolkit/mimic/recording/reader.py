"""Reading recordings: front to back, so truncated files give back every complete chunk.

Files are scanned as a stream (never by seeking to the summary at the end), which makes a
finished file and one cut off by a crash read the same way; ``RecoveryReport`` says what a
damaged file lost. Joint tables come out as polars DataFrames in the recording's robot's joint
order (``RecordingInfo.robot``; files without metadata hold our NAO).

Log times are wall-clock times in new files and simulated times from 0 in older ones (see
``mimic.recording.layout``); ``Recording.time_origin_ns`` is the log time of simulated time 0,
and every time this module gives in seconds counts from it or from the first sample.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import polars as pl
from mcap.exceptions import McapError
from mcap.records import Channel, Footer, Message, Metadata, Schema
from mcap.stream_reader import StreamReader
from mcap_ros2.decoder import DecoderFactory

from mimic.errors import MimicError, RecordingError
from mimic.files import input_file
from mimic.geometry import quat_mul as _quat_mul
from mimic.geometry import rotate as _rotate
from mimic.recording import layout as L
from mimic.recording.layout import ENDED_COLUMN, TIME_COLUMN
from mimic.robot.model import RobotDescription, UnknownJointError
from mimic.robot.registry import DEFAULT_ROBOT, get_robot

__all__ = [
    "Recording",
    "TopicInfo",
    "RecoveryReport",
    "TfTrack",
    "read_recording",
    "read_joint_table",
    "read_tf",
    "world_poses",
    "describe_recording",
    "ENDED_COLUMN",
    "TIME_COLUMN",
]

_MAGIC = b"\x89MCAP0\r\n"


@dataclass(frozen=True)
class TopicInfo:
    """One topic: schema name, message count, first and last log time [ns]."""

    schema: str
    count: int
    first_ns: int
    last_ns: int


@dataclass(frozen=True)
class RecoveryReport:
    """How complete a file was.

    Attributes:
        complete: the footer was reached (the writer finished the file).
        messages_recovered: messages read from complete chunks.
        last_time_s: time of the last recovered message since the recording started [s].
        bytes_read: bytes of the file that made complete records.
        bytes_lost: bytes after them that could not be used (0 for a complete file).
        problem: what stopped the reading (empty when complete).
    """

    complete: bool
    messages_recovered: int
    last_time_s: float
    bytes_read: int
    bytes_lost: int
    problem: str = ""

    def summary(self) -> str:
        """One line for the user."""
        if self.complete:
            return f"complete ({self.messages_recovered} messages)"
        return (
            f"damaged or truncated file ({self.problem}): recovered "
            f"{self.messages_recovered} messages up to t = {self.last_time_s:.2f} s, "
            f"lost the last {self.bytes_lost} bytes"
        )


@dataclass
class Recording:
    """Everything in one file, read into memory (messages kept as raw CDR until decoded)."""

    path: Path
    info: L.RecordingInfo | None
    metadata: dict[str, dict[str, str]]
    topics: dict[str, TopicInfo]
    recovery: RecoveryReport
    # Log time of simulated time 0 [ns]: the wall-clock start of the recording, 0 in older
    # files, the first log time in files of other tools.
    time_origin_ns: int = 0
    _messages: dict[str, list[tuple[int, bytes]]] = field(repr=False, default_factory=dict)
    _schemas: dict[str, Schema] = field(repr=False, default_factory=dict)

    @property
    def robot(self) -> RobotDescription:
        """The robot whose joints the file holds (from its metadata; our NAO without it)."""
        return get_robot(self.info.robot if self.info is not None else DEFAULT_ROBOT)

    @property
    def duration_s(self) -> float:
        """Time from the first to the last joint sample (any topic if there is none) [s]."""
        topics = [t for t in L.JOINT_TOPICS if t in self.topics] or list(self.topics)
        if not topics:
            return 0.0
        first = min(self.topics[t].first_ns for t in topics)
        last = max(self.topics[t].last_ns for t in topics)
        return (last - first) / L.NS_PER_S

    @property
    def rate_hz(self) -> float:
        """Joint samples per second on the main joint topic (0 when unknown)."""
        topic = self.joint_topic(required=False)
        if topic is None or self.topics[topic].count < 2:
            return 0.0
        t = self.topics[topic]
        return (t.count - 1) * L.NS_PER_S / max(1, t.last_ns - t.first_ns)

    @property
    def interrupted(self) -> bool:
        """The recording was stopped early (Ctrl-C) or its file was cut off."""
        end = self.metadata.get(L.END_METADATA_NAME)
        return not self.recovery.complete or (end is not None and end.get("interrupted") == "true")

    def joint_topic(self, required: bool = True) -> str | None:
        """The topic a dataset learns from: references when present, else joint states."""
        for topic in (L.JOINT_REFERENCES, L.JOINT_STATES):
            if topic in self.topics:
                return topic
        if required:
            raise RecordingError(
                f"{self.path}: no joint topic ({', '.join(L.JOINT_TOPICS)}); "
                f"topics present: {', '.join(self.topics) or 'none'}"
            )
        return None

    def decoded(self, topic: str):
        """(log_time_ns, decoded message) pairs of ``topic``, in file order."""
        if topic not in self.topics:
            raise RecordingError(
                f"{self.path}: no topic {topic}; topics present: {', '.join(self.topics) or 'none'}"
            )
        schema = self._schemas[topic]
        decoder = DecoderFactory().decoder_for("cdr", schema)
        if decoder is None:
            raise RecordingError(f"{self.path}: cannot decode {topic} ({schema.name})")
        for time_ns, data in self._messages[topic]:
            yield time_ns, decoder(data)


def read_recording(path: str | Path) -> Recording:
    """Read a recording front to back, recovering what a truncated file still holds.

    Raises:
        RecordingError: missing file, a folder, or not an MCAP file at all.
    """

    try:
        path = input_file(path, "recording", "record one with 'mimic record'")
    except MimicError as err:
        raise RecordingError(str(err)) from None
    size = path.stat().st_size
    with open(path, "rb") as f:
        if f.read(len(_MAGIC)) != _MAGIC:
            raise RecordingError(
                f"{path}: not an MCAP file (it does not start with the MCAP "
                "magic bytes); record one with 'mimic record'"
            )
        f.seek(0)
        schemas: dict[int, Schema] = {}
        channels: dict[int, Channel] = {}
        messages: dict[str, list[tuple[int, bytes]]] = {}
        metadata: dict[str, dict[str, str]] = {}
        complete, problem, good_bytes, count, last_ns, first_ns = False, "", 0, 0, 0, None
        try:
            for record in StreamReader(f, validate_crcs=True).records:
                if isinstance(record, Schema):
                    schemas[record.id] = record
                elif isinstance(record, Channel):
                    channels[record.id] = record
                elif isinstance(record, Message):
                    topic = channels[record.channel_id].topic
                    messages.setdefault(topic, []).append((record.log_time, record.data))
                    count += 1
                    last_ns = max(last_ns, record.log_time)
                    first_ns = (
                        record.log_time if first_ns is None else min(first_ns, record.log_time)
                    )
                elif isinstance(record, Metadata):
                    metadata[record.name] = dict(record.metadata)
                elif isinstance(record, Footer):
                    complete = True
                good_bytes = f.tell()
        except (McapError, ValueError, KeyError, EOFError, OSError, MemoryError) as err:
            problem = type(err).__name__ if not str(err) else str(err).splitlines()[0][:80]
        except Exception as err:  # zstd/lz4/struct errors on a damaged tail
            problem = f"{type(err).__name__}: {str(err)[:80]}"
    if complete:
        good_bytes = size
    elif not problem:
        problem = "the file ends before its footer"
    topics, topic_schemas = {}, {}
    for channel in channels.values():
        msgs = messages.get(channel.topic, [])
        if not msgs:
            continue
        times = [t for t, _ in msgs]
        topic_schemas[channel.topic] = schemas[channel.schema_id]
        topics[channel.topic] = TopicInfo(
            schemas[channel.schema_id].name, len(msgs), min(times), max(times)
        )
    info = None
    if L.METADATA_NAME in metadata:
        try:
            info = L.RecordingInfo.from_metadata(metadata[L.METADATA_NAME])
        except (ValueError, TypeError):
            info = None
    origin = _time_origin_ns(metadata, first_ns)
    report = RecoveryReport(
        complete,
        count,
        (last_ns - origin) / L.NS_PER_S if count else 0.0,
        good_bytes,
        size - good_bytes,
        problem,
    )
    return Recording(path, info, metadata, topics, report, origin, messages, topic_schemas)


def _time_origin_ns(metadata: dict[str, dict[str, str]], first_ns: int | None) -> int:
    """Log time of simulated time 0: ``start_wall_time_ns`` when written, else 0 for our older
    files (log times from 0), else the first log time (files of other tools)."""
    ours = metadata.get(L.METADATA_NAME, {})
    try:
        return int(ours[L.START_WALL_TIME_KEY])
    except (KeyError, ValueError):
        return 0 if ours or first_ns is None else first_ns


def _as_recording(source: str | Path | Recording) -> Recording:
    return source if isinstance(source, Recording) else read_recording(source)


def read_joint_table(
    source: str | Path | Recording, topic: str | None = "/joint_states"
) -> pl.DataFrame:
    """The joint samples of ``topic`` as a table in our layout.

    Columns: ``time_s`` (float, from the first sample), the N joint names of the recording's
    robot in its order [rad], ``ended`` (0/1 float). JointState messages may name joints by
    the robot's names or their aliases (the NAO's simulator names hj1..rlj6), in any order.
    ``ended`` comes from
    the ``/ended`` topic; files without it get ended = 1 on the last row (as in the study).
    ``topic=None`` picks references when present, else joint states.

    Raises:
        RecordingError: no such topic (the message names those present), wrong joint names,
            NaN values, or time running backwards.
    """
    rec = _as_recording(source)
    robot = rec.robot
    topic = topic or rec.joint_topic()
    if topic not in rec.topics:
        raise RecordingError(
            f"{rec.path}: no joint topic {topic}; topics present: {', '.join(rec.topics) or 'none'}"
        )
    times, rows, perm, names = [], [], None, None
    for time_ns, msg in rec.decoded(topic):
        if names != list(msg.name):
            names = list(msg.name)
            try:
                perm = robot.resolve_joint_names(names)
            except UnknownJointError as err:
                unknown = [n for n in names if not robot.has_joint(n)]
                raise RecordingError(
                    f"{rec.path}: {topic} has wrong joint names ({err}); unknown names: "
                    f"{', '.join(unknown) or 'none'}"
                ) from None
        pos = np.asarray(msg.position, dtype=float)
        if len(pos) != len(names):
            raise RecordingError(
                f"{rec.path}: {topic} message at {time_ns / 1e9:.3f} s has "
                f"{len(pos)} positions for {len(names)} joint names"
            )
        times.append(time_ns)
        rows.append(pos[perm])
    values = np.array(rows, dtype=float).reshape(-1, robot.num_joints)
    t = np.array(times, dtype=np.int64)
    if np.isnan(values).any():
        row, col = np.argwhere(np.isnan(values))[0]
        raise RecordingError(
            f"{rec.path}: {topic} holds NaN (first: {robot.joint_names[col]} at "
            f"t = {(t[row] - t[0]) / 1e9:.3f} s)"
        )
    back = np.nonzero(np.diff(t) < 0)[0]
    if len(back):
        raise RecordingError(
            f"{rec.path}: time runs backwards in {topic} at t = {(t[back[0]] - t[0]) / 1e9:.3f} s"
        )
    ended = _ended_flags(rec, t)
    table = {TIME_COLUMN: (t - (t[0] if len(t) else 0)) / L.NS_PER_S}
    table.update({name: values[:, i] for i, name in enumerate(robot.joint_names)})
    table[ENDED_COLUMN] = ended
    return pl.DataFrame(table)


def _ended_flags(rec: Recording, times_ns: np.ndarray) -> np.ndarray:
    """(n,) 0/1 ended flag per joint sample: the latest /ended value at or before it."""
    ended = np.zeros(len(times_ns))
    if L.ENDED in rec.topics:
        pairs = [(t, 1.0 if m.data else 0.0) for t, m in rec.decoded(L.ENDED)]
        flag_t = np.array([p[0] for p in pairs], dtype=np.int64)
        flag_v = np.array([p[1] for p in pairs])
        idx = np.searchsorted(flag_t, times_ns, side="right") - 1
        ended = np.where(idx >= 0, flag_v[np.clip(idx, 0, None)], 0.0)
    elif len(ended):
        ended[-1] = 1.0
    return ended


@dataclass(frozen=True)
class TfTrack:
    """Poses of one frame over time in its parent frame.

    Attributes:
        parent: parent frame name.
        times_ns: (N,) log times [ns].
        pos_m: (N, 3) positions [m].
        quat_wxyz: (N, 4) orientations.
    """

    parent: str
    times_ns: np.ndarray
    pos_m: np.ndarray
    quat_wxyz: np.ndarray


def read_tf(source: str | Path | Recording, *, in_world: bool = True) -> dict[str, TfTrack]:
    """Frame poses from ``/tf``: as recorded (in their parents), or composed into ``world``.

    With ``in_world`` every frame whose chain reaches ``world`` is returned in the world frame
    (parent ``world``); frames of one TFMessage share their times, as our files write them.
    """
    rec = _as_recording(source)
    raw: dict[str, tuple[str, list, list, list]] = {}
    for time_ns, msg in rec.decoded(L.TF):
        for tr in msg.transforms:
            entry = raw.setdefault(tr.child_frame_id, (tr.header.frame_id, [], [], []))
            entry[1].append(time_ns)
            v, q = tr.transform.translation, tr.transform.rotation
            entry[2].append((v.x, v.y, v.z))
            entry[3].append((q.w, q.x, q.y, q.z))
    tracks = {
        child: TfTrack(
            parent, np.array(t, dtype=np.int64), np.array(p, dtype=float), np.array(q, dtype=float)
        )
        for child, (parent, t, p, q) in raw.items()
    }
    return world_poses(tracks) if in_world else tracks


def world_poses(tracks: dict[str, TfTrack]) -> dict[str, TfTrack]:
    """Compose parent-relative tracks into world-frame tracks (same times required)."""
    out: dict[str, TfTrack] = {}

    def resolve(name: str, depth: int = 0) -> TfTrack | None:
        if name in out:
            return out[name]
        track = tracks.get(name)
        if track is None or depth > 64:
            return None
        if track.parent == L.WORLD_FRAME:
            out[name] = track
            return track
        parent = resolve(track.parent, depth + 1)
        if parent is None or len(parent.times_ns) != len(track.times_ns):
            return None
        pos = parent.pos_m + _rotate(parent.quat_wxyz, track.pos_m)
        quat = _quat_mul(parent.quat_wxyz, track.quat_wxyz)
        out[name] = TfTrack(L.WORLD_FRAME, track.times_ns, pos, quat)
        return out[name]

    for name in tracks:
        resolve(name)
    return out


def describe_recording(path: str | Path) -> dict:
    """A JSON-ready summary of a recording (what ``mimic info`` prints)."""
    rec = read_recording(path)
    info = rec.info
    end = rec.metadata.get(L.END_METADATA_NAME, {})
    warnings = []
    if L.JOINT_STATES not in rec.topics:
        warnings.append(
            f"no {L.JOINT_STATES} topic: no joint angles to view or learn "
            f"(topics: {', '.join(sorted(rec.topics)) or 'none'})"
        )
    if info is None:
        warnings.append(
            f"no '{L.METADATA_NAME}' metadata record: not written by mimic, motion and rate unknown"
        )
    if not rec.recovery.complete:
        warnings.append(rec.recovery.summary())
    start = rec.metadata.get(L.METADATA_NAME, {}).get(L.START_WALL_TIME_KEY)
    return {
        "path": str(rec.path),
        "kind": "recording",
        "motion": info.motion if info else None,
        "robot": info.robot if info else DEFAULT_ROBOT,
        "world": info.world if info else None,
        "agent": info.agent if info else None,
        "team": info.team if info else None,
        "source": info.source if info else None,
        "cyclic": info.cyclic if info else None,
        "period_s": info.period_s if info else None,
        "seed": info.seed if info else None,
        "toolkit_version": info.toolkit_version if info else None,
        "duration_s": round(rec.duration_s, 6),
        "rate_hz": round(rec.rate_hz, 3) if rec.joint_topic(required=False) else None,
        "topics": {
            name: {"schema": t.schema, "messages": t.count}
            for name, t in sorted(rec.topics.items())
        },
        "interrupted": rec.interrupted,
        "complete": rec.recovery.complete,
        "recovery": rec.recovery.summary(),
        "bytes_lost": rec.recovery.bytes_lost,
        "end": {key: _typed(value) for key, value in end.items()},
        "extra": {key: _typed(value) for key, value in (info.extra if info else {}).items()},
        "started_at": _iso_time(int(start)) if start and start.isdigit() else None,
        "warnings": warnings,
    }


def _typed(text: str):
    """A metadata value (MCAP metadata holds strings) as JSON would have it: ``true`` and
    ``false`` as booleans, whole numbers as integers, other numbers as floats, else text."""
    if not isinstance(text, str):
        return text
    if text in ("true", "false"):
        return text == "true"
    for kind in (int, float):
        try:
            value = kind(text)
        except ValueError:
            continue
        return value if kind is int or (value == value and abs(value) != float("inf")) else text
    return text


def _iso_time(time_ns: int) -> str:
    """Wall-clock time [ns since the Unix epoch] as ISO 8601 UTC, to the second."""
    import datetime

    return datetime.datetime.fromtimestamp(time_ns / L.NS_PER_S, datetime.timezone.utc).isoformat(
        timespec="seconds"
    )
