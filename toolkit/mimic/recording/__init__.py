"""Recordings in MCAP: the layout, writing, reading (with recovery), recording agents, the
import of the study's text files, and another team's league player recorded from the monitor
stream (``blackbox``) or a game log (``game_log``). See ``mimic.recording.layout`` for the
topics."""

from mimic.recording.layout import RecordingInfo
from mimic.recording.reader import (
    Recording,
    RecoveryReport,
    TfTrack,
    describe_recording,
    read_joint_table,
    read_recording,
    read_tf,
)
from mimic.recording.writer import RecordingWriter

__all__ = [
    "RecordingInfo",
    "RecordingWriter",
    "Recording",
    "RecoveryReport",
    "TfTrack",
    "read_recording",
    "read_joint_table",
    "read_tf",
    "describe_recording",
]
