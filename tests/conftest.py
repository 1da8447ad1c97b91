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


@pytest.fixture(scope="session")
def policy_walk_recording(tmp_path_factory) -> Path:
    """The T1 other team's policy-like walk, recorded in our world for 12 s (joint states
    and /tf), black-box: what step-phase learning and the fit in simulation learn from."""
    from typer.testing import CliRunner

    from mimic.cli.main import app

    out = tmp_path_factory.mktemp("policy_walk") / "policy.mcap"
    said = CliRunner().invoke(
        app,
        [
            "record", "other-team-policy-walk", "--robot", "t1", "--duration", "12",
            "--observe-only", "-o", str(out),
        ],
    )  # fmt: skip
    assert said.exit_code == 0, said.output
    return out
