"""The MCAP recording layout: topics, frames, message schemas and self-describing metadata.

A recording holds ROS 2 messages (CDR) so that Rerun and Foxglove open it as it is:

| topic | schema | what |
|---|---|---|
| ``/joint_states`` | sensor_msgs/msg/JointState | angles [rad], speeds [rad/s] seen, every cycle |
| ``/joint_references`` | sensor_msgs/msg/JointState | references [rad] our controller sent (own agents) |
| ``/ended`` | std_msgs/msg/Bool | the motion-ended flag, one per joint sample (true from the end on) |
| ``/tf`` | tf2_msgs/msg/TFMessage | the link tree (``world`` -> ``torso`` -> ..., as in the URDF), the ball |
| ``/robot_description`` | std_msgs/msg/String | the URDF twin, once at t = 0 |

Times are integer nanoseconds. MCAP log times and message header stamps are wall-clock times
(Unix epoch): the moment the recording started (``start_wall_time_ns`` in the ``mimic``
record) plus the simulated time since then, so viewers show the date it was made. Older
files (no ``start_wall_time_ns``) have log times from 0; readers handle both and give times
from the first sample. The metadata record ``mimic`` (written first) says what the
recording is, including its robot: joint messages hold that robot's joints (N of them, its
order); ``mimic.end`` (written when the file is finished) says how it ended, with
``last_time_ns`` in simulated time.

Joint tables read from a recording (``mimic.recording.reader.read_joint_table``) have the
columns ``TIME_COLUMN``, the robot's joint names in its order, and ``ENDED_COLUMN``.
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, field

from mimic.robot.registry import DEFAULT_ROBOT, get_robot
from mimic.world.base import CYCLE_S

__all__ = [
    "JOINT_STATES",
    "JOINT_REFERENCES",
    "ENDED",
    "TF",
    "ROBOT_DESCRIPTION",
    "JOINT_TOPICS",
    "WORLD_FRAME",
    "BALL_FRAME",
    "METADATA_NAME",
    "END_METADATA_NAME",
    "TIME_COLUMN",
    "ENDED_COLUMN",
    "RecordingInfo",
    "SCHEMAS",
    "NS_PER_S",
    "START_WALL_TIME_KEY",
]

JOINT_STATES = "/joint_states"
JOINT_REFERENCES = "/joint_references"
ENDED = "/ended"
TF = "/tf"
ROBOT_DESCRIPTION = "/robot_description"
#: Topics that hold one value per joint of the recording's robot in each message.
JOINT_TOPICS = (JOINT_STATES, JOINT_REFERENCES)

#: TF root frame: the field frame (origin centre spot, x toward the opponent goal, z up).
WORLD_FRAME = "world"
BALL_FRAME = "ball"
#: Name of the MCAP metadata record describing the recording / finishing it.
METADATA_NAME = "mimic"
END_METADATA_NAME = "mimic.end"
NS_PER_S = 1_000_000_000
#: Key in the ``mimic`` record: wall-clock time of simulated time 0 [ns since the Unix epoch].
START_WALL_TIME_KEY = "start_wall_time_ns"

#: Joint-table columns: seconds from the first sample, and the motion-ended flag (0/1).
TIME_COLUMN = "time_s"
ENDED_COLUMN = "ended"
#: The metadata key older files name their robot with (``nao_type0``: our NAO).
_LEGACY_ROBOT_KEY = "robot_model"


@dataclass(frozen=True)
class RecordingInfo:
    """What a recording is; stored as the ``mimic`` MCAP metadata record (all values text)."""

    # Motion or behaviour name, e.g. ``kick_right`` or ``walk``.
    motion: str
    # Agent that produced it (its ``name``), or the importer (``paper:<file>``).
    agent: str
    # ``mimic`` (our code) or ``other_team`` (only observed).
    team: str = "mimic"
    # ``reference`` when the file holds commanded references, ``observed`` when only reached angles.
    source: str = "observed"
    # Agent cycle [s].
    cycle_s: float = CYCLE_S
    # The robot the joint values belong to (a ``mimic.robot.registry`` name).
    robot: str = DEFAULT_ROBOT
    # The world it moved in: ``nao`` (our MuJoCo world) or ``league`` (RCSSServerMJ).
    world: str = "nao"
    # Joint order of every JointState message (empty: the robot's own order).
    joint_order: tuple[str, ...] = ()
    # Toolkit version that wrote the file.
    toolkit_version: str = ""
    # Seed of the simulation run.
    seed: int = 0
    # Period [s] of a cyclic motion (the recording holds whole periods), or None.
    period_s: float | None = None
    # Ball position relative to the robot (robot frame: x forward, y left) [m], or None.
    ball_offset_m: tuple[float, float] | None = None
    # How the robot started: ``standing``, ``lying_front`` or ``lying_back`` (get-ups).
    start_posture: str = "standing"
    # Anything else worth keeping (text values).
    extra: dict[str, str] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if not self.joint_order:  # frozen: set once, here
            object.__setattr__(self, "joint_order", get_robot(self.robot).joint_names)

    @property
    def cyclic(self) -> bool:
        return self.period_s is not None

    @property
    def control_rate_hz(self) -> float:
        """Agent control rate [Hz] (derived from the cycle, written for other readers)."""
        return 1.0 / self.cycle_s

    def to_metadata(self) -> dict[str, str]:
        """The MCAP metadata map (string keys and values; lists and numbers as JSON)."""
        d = asdict(self)
        extra = d.pop("extra")
        out = {k: v if isinstance(v, str) else json.dumps(v) for k, v in d.items()}
        out["cyclic"] = json.dumps(self.cyclic)
        out["control_rate_hz"] = json.dumps(self.control_rate_hz)
        out.update({f"extra.{k}": str(v) for k, v in extra.items()})
        return out

    @classmethod
    def from_metadata(cls, data: dict[str, str]) -> RecordingInfo:
        """Inverse of ``to_metadata``; unknown keys go into ``extra``."""
        kwargs, extra = {}, {}
        for key, text in data.items():
            if key.startswith("extra."):
                extra[key.removeprefix("extra.")] = text
            elif key in cls.__dataclass_fields__:
                kwargs[key] = text if key in _TEXT_FIELDS else json.loads(text)
        if "robot" not in kwargs and _LEGACY_ROBOT_KEY in data:
            # Older files: ``robot_model: nao_type0``; the registry knows the alias.
            kwargs["robot"] = get_robot(data[_LEGACY_ROBOT_KEY]).name
        if "joint_order" in kwargs:
            kwargs["joint_order"] = tuple(kwargs["joint_order"])
        if kwargs.get("ball_offset_m") is not None:
            kwargs["ball_offset_m"] = tuple(kwargs["ball_offset_m"])
        return cls(**kwargs, extra=extra)


_TEXT_FIELDS = {
    "motion",
    "agent",
    "team",
    "source",
    "robot",
    "world",
    "toolkit_version",
    "start_posture",
}

_TIME = """MSG: builtin_interfaces/Time
int32 sec
uint32 nanosec
"""
_HEADER = """MSG: std_msgs/Header
builtin_interfaces/Time stamp
string frame_id
"""
_SEP = "=" * 80 + "\n"

#: ROS 2 message definitions (datatype -> concatenated .msg text), as rosbag2 writes them.
SCHEMAS: dict[str, str] = {
    "sensor_msgs/msg/JointState": (
        "std_msgs/Header header\nstring[] name\nfloat64[] position\nfloat64[] velocity\n"
        "float64[] effort\n" + _SEP + _HEADER + _SEP + _TIME
    ),
    "tf2_msgs/msg/TFMessage": (
        "geometry_msgs/TransformStamped[] transforms\n"
        + _SEP
        + "MSG: geometry_msgs/TransformStamped\nstd_msgs/Header header\nstring child_frame_id\n"
        "Transform transform\n"
        + _SEP
        + "MSG: geometry_msgs/Transform\nVector3 translation\nQuaternion rotation\n"
        + _SEP
        + "MSG: geometry_msgs/Vector3\nfloat64 x\nfloat64 y\nfloat64 z\n"
        + _SEP
        + "MSG: geometry_msgs/Quaternion\nfloat64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n"
        + _SEP
        + _HEADER
        + _SEP
        + _TIME
    ),
    "std_msgs/msg/String": "string data\n",
    "std_msgs/msg/Bool": "bool data\n",
}

#: Schema of each topic we write.
TOPIC_SCHEMAS: dict[str, str] = {
    JOINT_STATES: "sensor_msgs/msg/JointState",
    JOINT_REFERENCES: "sensor_msgs/msg/JointState",
    ENDED: "std_msgs/msg/Bool",
    TF: "tf2_msgs/msg/TFMessage",
    ROBOT_DESCRIPTION: "std_msgs/msg/String",
}
