"""Recordings in MCAP: the layout, writing, reading (with recovery), recording agents, and
the import of the study's text files. See ``mimic.recording.layout`` for the topics."""

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
