"""One league player's decoded poses as a recording in our layout.

``/joint_states`` (the robot's own joint names, positions only), ``/tf`` (every link in its
parent, the root and the ball under ``world``), ``/robot_description`` (the robot's URDF) and
the ``mimic`` metadata: world ``league``, robot, team, source (``monitor`` or ``game_log``),
the player's number, where the frames came from and the server time of the first sample
(``extra.start_server_time_s``). Times are the server clock's, from the first sample.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from mimic import __version__
from mimic.league.decode import PlayerSample
from mimic.recording import layout as L
from mimic.recording.writer import RecordingWriter
from mimic.robot.model import RobotDescription

__all__ = ["PlayerWriter", "FLUSH_PERIOD_S"]

#: Close a chunk and flush the file after this much recorded time [s]: a recording cut off
#: by a crash or a kill loses at most that much.
FLUSH_PERIOD_S = 0.2
_MS = 1_000_000


class PlayerWriter:
    """Writes one player's samples (a context manager; finished on exit, even on error).

    Args:
        path: output ``.mcap`` file.
        robot: the player's robot.
        team, player: who it is.
        source: ``monitor`` (a live stream) or ``game_log``.
        origin: where the frames came from (server address or log file), kept in metadata.
        start_time_s: server time of the first sample [s] (t = 0 in the recording).
    """

    def __init__(
        self,
        path: str | Path,
        robot: RobotDescription,
        team: str,
        player: int,
        source: str,
        origin: str,
        start_time_s: float,
        flush_period_s: float = FLUSH_PERIOD_S,
    ) -> None:
        self.robot = robot
        info = L.RecordingInfo(
            motion=f"{team}_{player}",
            agent="league player",
            team=team,
            source=source,
            robot=robot.name,
            world="league",
            joint_order=robot.joint_names,
            toolkit_version=__version__,
            extra={
                "player": str(player),
                "origin": origin,
                "start_server_time_s": f"{start_time_s:.3f}",
            },
        )
        self.writer = RecordingWriter(path, info, urdf=robot.urdf(), flush_period_s=flush_period_s)
        self.path = Path(path)
        self.children = [link.name for link in robot.links] + [L.BALL_FRAME]
        self.parents = [link.parent or L.WORLD_FRAME for link in robot.links] + [L.WORLD_FRAME]
        self.samples = 0
        self._first_ms = int(round(start_time_s * 1000))
        self._last_ms = -1

    @property
    def duration_s(self) -> float:
        return max(0, self._last_ms) / 1000.0

    def elapsed_s(self, sample: PlayerSample) -> float:
        """Time of ``sample`` in the recording [s]."""
        return (int(round(sample.time_s * 1000)) - self._first_ms) / 1000.0

    def write(self, sample: PlayerSample, ball_pos_m: np.ndarray | None) -> bool:
        """Write one sample (and the ball); False for a sample not after the last one."""
        t_ms = int(round(sample.time_s * 1000)) - self._first_ms
        if t_ms <= self._last_ms:  # a frame again, or the clock ran back (server restart)
            return False
        t_ns = t_ms * _MS
        self.writer.write_joints(t_ns, sample.joint_angles_rad)
        pos, quat = sample.link_pos_m, sample.link_quat_wxyz
        if ball_pos_m is not None:
            pos = np.vstack([pos, ball_pos_m])
            quat = np.vstack([quat, [1.0, 0.0, 0.0, 0.0]])
            children, parents = self.children, self.parents
        else:
            children, parents = self.children[:-1], self.parents[:-1]
        self.writer.write_tf(t_ns, parents, children, pos, quat)
        self._last_ms = t_ms
        self.samples += 1
        return True

    def finish(self, *, interrupted: bool, reason: str) -> None:
        """Finish the file; ``reason`` (why it ended) goes into the ``mimic.end`` record."""
        self.writer.finish(interrupted=interrupted, samples=self.samples, reason=reason)

    def abandon(self) -> None:
        """Remove the unfinished file: an existing file of that name stays as it was."""
        self.writer.abandon()

    def __enter__(self) -> PlayerWriter:
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        self.finish(
            interrupted=exc_type is not None, reason="error" if exc_type is not None else "done"
        )
