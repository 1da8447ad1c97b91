"""Import of the study's ``::`` text files (the authors' published joint tables).

Format (see ``shared/paper-data/README.md``): fields separated by ``::``, one header row, one
row per 20 ms cycle; an optional leading ``distance`` column (the kick family), ``timestep``
[s], the NAO's joints [rad] in the study's order, and an optional ``hasEnded`` flag (0/1).
The study's files are NAO data: everything here uses the NAO's description explicitly.

Joint names: theirs -> ours (``PAPER_TO_CANONICAL``). Their "shoulder yaw" is our shoulder
roll, their "arm roll" our elbow yaw, their "arm yaw" our elbow roll, "foot" is "ankle".
One header of ut_walk.txt is misspelt (``leftHipYawPitc``); it is accepted.

Signs (``PAPER_SIGNS``, ours = sign * theirs). Their angles follow their agent's convention
(close to the real NAO), ours the simulator's perceptors. Evidence, from every published file
(1697 rows), counting samples beyond our joint stops by more than 3 deg for each choice:

* pitch joints (rotations about the robot's right-pointing axis, RSG +X): shoulder, hip,
  knee and ankle pitch flip (-1): their stand is shoulder +90, hip -30, knee +60, ankle -30
  deg; ours is shoulder -90, hip +30, knee -60, ankle +30. Counts (keep / flip): knee left
  1401 / 554 (the rest are the kick's 186 deg targets beyond the stop), right 1314 / 0;
  ankle pitch left 860 / 224, right 653 / 24. Head pitch turns about the same axis, so it
  flips too (the data cannot tell: ut_walk's -45 deg neck pitch sits on either stop).
* shoulder roll (their shoulder yaw): keep. Left 0 / 719, right 0 / 736; the study's +20 deg
  on the left fits our left_shoulder_roll range -1..95 deg.
* elbow roll (their arm yaw): keep. Left 3 / 24, right 0 / 27.
* hip yaw-pitch: left flips, right keeps. Left 247 / 0, right 25 / 549. The simulator gives
  both hips the range -90..1 deg while their file holds mirrored signs (left +, right -);
  with these signs both sides agree with our mirror table (same sign left and right).
* elbow yaw (their arm roll), hip roll, ankle roll, head yaw: keep. The counts are 0 / 0
  (ranges are symmetric or the values small); hip and ankle roll turn about the forward axis
  in both conventions (NAO and simulator: positive rolls the left leg outward), the elbow yaw
  values (-90 deg left, +90 right) match our mirror table either way.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import polars as pl

from mimic import __version__
from mimic.errors import RecordingError
from mimic.recording import layout as L
from mimic.recording.layout import ENDED_COLUMN, TIME_COLUMN
from mimic.recording.writer import RecordingWriter
from mimic.robot.registry import get_robot

__all__ = [
    "PAPER_TO_CANONICAL",
    "PAPER_SIGNS",
    "STUDY_ROBOT",
    "read_paper_table",
    "import_paper_file",
    "default_topic",
]

#: The robot of every study file (whatever the default robot of other commands is).
STUDY_ROBOT = "nao"
_SIDES = {"left": "left", "right": "right"}
_PART = {  # their joint (without side) -> our joint (without side)
    "ShoulderPitch": "shoulder_pitch",
    "ShoulderYaw": "shoulder_roll",
    "ArmRoll": "elbow_yaw",
    "ArmYaw": "elbow_roll",
    "HipYawPitch": "hip_yaw_pitch",
    "HipRoll": "hip_roll",
    "HipPitch": "hip_pitch",
    "KneePitch": "knee_pitch",
    "FootPitch": "ankle_pitch",
    "FootRoll": "ankle_roll",
}
#: Their column name -> our canonical joint name.
PAPER_TO_CANONICAL: dict[str, str] = {
    "neckYaw": "head_yaw",
    "neckPitch": "head_pitch",
    **{f"{side}{part}": f"{side}_{ours}" for side in _SIDES for part, ours in _PART.items()},
    "leftHipYawPitc": "left_hip_yaw_pitch",  # ut_walk.txt's header typo
}
_FLIP = {
    "head_pitch",
    "left_shoulder_pitch",
    "right_shoulder_pitch",
    "left_hip_yaw_pitch",
    *(f"{s}_{p}" for s in _SIDES for p in ("hip_pitch", "knee_pitch", "ankle_pitch")),
}
#: Our canonical joint name -> sign with ours = sign * theirs (evidence in the module doc).
PAPER_SIGNS: dict[str, float] = {
    n: (-1.0 if n in _FLIP else 1.0) for n in get_robot(STUDY_ROBOT).joint_names
}


def default_topic(path: str | Path) -> str:
    """Where a file's joints belong: references for their keyframe kicks and the network
    outputs (``kick*``, ``*learned*`` except ``server_joints*``), else reached joint states."""
    name = Path(path).name
    if name.startswith("server_joints"):
        return L.JOINT_STATES
    if name.startswith("kick") or "learned" in name:
        return L.JOINT_REFERENCES
    return L.JOINT_STATES


def _parse(path: Path) -> tuple[list[str], np.ndarray]:
    if path.is_dir():
        raise RecordingError(f"{path}: is a directory, not a study joint table")
    try:
        lines = [ln.rstrip("\r\n") for ln in path.read_text().splitlines() if ln.strip()]
    except (OSError, UnicodeDecodeError) as err:
        raise RecordingError(f"{path}: cannot read the file ({err})") from None
    if len(lines) < 2 or "::" not in lines[0]:
        raise RecordingError(
            f"{path}: not a study joint table (expected a '::'-separated header row and data rows)"
        )
    header = [h.strip() for h in lines[0].split("::")]
    rows = []
    for lineno, line in enumerate(lines[1:], 2):
        fields = line.split("::")
        if len(fields) != len(header):
            raise RecordingError(f"{path}:{lineno}: {len(fields)} fields, header has {len(header)}")
        try:  # an empty field (the kick family's last flag) reads as NaN
            rows.append([float(x) if x.strip() else math.nan for x in fields])
        except ValueError:
            raise RecordingError(f"{path}:{lineno}: a field is not a number") from None
    return header, np.array(rows)


def read_paper_table(path: str | Path, *, distance_m: float | None = None) -> pl.DataFrame:
    """A study file as a table in our layout (``time_s``, the NAO's joints in its order and our
    signs [rad], ``ended``). The kick family holds many kicks: pick one with ``distance_m``
    (the table then also has no ``distance`` column); without it the first kick is taken.

    Raises:
        RecordingError: unreadable file, unknown or missing joint columns.
    """
    path = Path(path)
    names = get_robot(STUDY_ROBOT).joint_names
    header, data = _parse(path)
    if "timestep" not in header:
        raise RecordingError(f"{path}: no 'timestep' column; columns: {', '.join(header)}")
    if "distance" in header:
        dist = data[:, header.index("distance")]
        choice = dist[0] if distance_m is None else distance_m
        keep = np.isclose(dist, choice)
        if not keep.any():
            raise RecordingError(
                f"{path}: no kick for distance {distance_m} m; distances: "
                f"{', '.join(f'{d:g}' for d in np.unique(dist))}"
            )
        data = data[keep]
    known = {h: PAPER_TO_CANONICAL[h] for h in header if h in PAPER_TO_CANONICAL}
    unknown = [
        h for h in header if h not in known and h not in ("timestep", "distance", "hasEnded")
    ]
    missing = [n for n in names if n not in known.values()]
    if unknown or missing:
        raise RecordingError(
            f"{path}: unknown columns: {', '.join(unknown) or 'none'}; "
            f"joints missing: {', '.join(missing) or 'none'}"
        )
    column = {ours: header.index(theirs) for theirs, ours in known.items()}
    table = {TIME_COLUMN: data[:, header.index("timestep")]}
    for name in names:
        table[name] = PAPER_SIGNS[name] * data[:, column[name]]
    ended = np.zeros(len(data))
    if "hasEnded" in header:
        ended = np.nan_to_num(data[:, header.index("hasEnded")], nan=0.0)
    ended[-1] = 1.0  # the last row ends the motion (the kick family leaves it blank)
    table[ENDED_COLUMN] = (ended > 0.5).astype(float)
    bad = [n for n in names if np.isnan(table[n]).any()]
    if bad:
        raise RecordingError(f"{path}: empty joint values in {', '.join(bad)}")
    return pl.DataFrame(table)


def import_paper_file(
    path: str | Path,
    out_path: str | Path,
    *,
    topic: str | None = None,
    distance_m: float | None = None,
    overwrite: bool = True,
) -> L.RecordingInfo:
    """Write a study file as a recording in our layout (joints on ``topic``, default by file:
    ``default_topic``), with ``/ended`` and the robot description. Returns its info.

    The recording is written under a temporary name and moved into place when complete;
    ``overwrite`` False refuses to replace an existing ``out_path``."""
    path = Path(path)
    robot = get_robot(STUDY_ROBOT)
    topic = topic or default_topic(path)
    if topic not in L.JOINT_TOPICS:
        raise RecordingError(f"topic must be one of {', '.join(L.JOINT_TOPICS)}, got {topic}")
    table = read_paper_table(path, distance_m=distance_m)
    times = table[TIME_COLUMN].to_numpy()
    if np.any(np.diff(times) < 0):
        raise RecordingError(f"{path}: time runs backwards")
    values = table.select(robot.joint_names).to_numpy()
    info = L.RecordingInfo(
        motion=path.stem,
        agent=f"paper:{path.name}",
        team="other_team",
        robot=robot.name,
        source="reference" if topic == L.JOINT_REFERENCES else "observed",
        toolkit_version=__version__,
        extra={
            "imported_from": path.name,
            "sign_convention": "mimic.recording.paper_import",
            **({"distance_m": f"{distance_m:g}"} if distance_m is not None else {}),
        },
    )
    t0 = times[0]
    with RecordingWriter(out_path, info, urdf=robot.urdf(), overwrite=overwrite) as writer:
        for t, row, ended in zip(times, values, table[ENDED_COLUMN].to_numpy()):
            t_ns = int(round((t - t0) * L.NS_PER_S))
            writer.write_joints(t_ns, row, topic=topic)
            writer.write_ended(t_ns, bool(ended))
    return info
