"""Shared fixtures."""

import shutil
import sys
from pathlib import Path

import pytest


@pytest.fixture(scope="session")
def rerun_cli() -> str:
    """Path of the installed `rerun` command (the one beside this Python first)."""
    beside = Path(sys.executable).parent / "rerun"
    found = str(beside) if beside.exists() else shutil.which("rerun")
    if found is None:
        pytest.skip("the rerun binary is not installed")
    return found
