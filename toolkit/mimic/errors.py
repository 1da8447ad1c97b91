"""Errors the toolkit raises for the user's input: each says what, where and what to do.

The CLI turns any ``MimicError`` into one line on stderr and a non-zero exit.
"""

from __future__ import annotations

__all__ = [
    "MimicError",
    "RecordingError",
    "ModelFileError",
    "MotionFileError",
    "DatasetError",
    "UnknownJointError",
]


class MimicError(Exception):
    """Base class of every error caused by bad input (files, options, names)."""

    exit_code = 2


class RecordingError(MimicError):
    """An MCAP recording that cannot be read or lacks what is needed."""


class ModelFileError(MimicError):
    """A model file that is missing, not a model, or made for another joint layout."""


class MotionFileError(MimicError):
    """A keyframe motion file with bad syntax or values, or an unknown motion name."""


class DatasetError(MimicError):
    """Training data that cannot make a dataset (empty, too short, NaN, wrong joints)."""


class UnknownJointError(MimicError, KeyError):
    """A joint name the robot does not have."""

    def __str__(self) -> str:  # KeyError quotes its message; we want a plain sentence.
        return str(self.args[0])
