"""The README's get-up block: the shipped T1 back get-up, seen through a league server's
monitor, learned and searched step by step and tried in the league.

Every command parses and reads only what is shipped or made before it (cheap, always); the
first learns the recording's start posture (a real training, always); the whole block runs
as it stands in about 6 minutes on 2 cores, so that run is marked slow.
"""

from __future__ import annotations

import shlex
from pathlib import Path

import polars as pl
import pytest
from test_quickstart import _OUTPUTS, _parse
from test_readme_league import readme_block, run_block

REPO = Path(__file__).resolve().parents[1]
RECORDING = "recordings/t1_getup_back_seen.mcap"


def getup_block(readme: str) -> str:
    """The bash block under ``## Learning a get-up``."""
    return readme_block(readme, "## Learning a get-up")


def getup_commands(readme: str) -> list[str]:
    """The block's commands, continuation lines joined and comments removed."""
    joined = getup_block(readme).replace("\\\n", " ")
    commands = [line.split(" #", 1)[0].strip() for line in joined.splitlines()]
    return [c for c in commands if c and not c.startswith("#")]


def test_the_getup_block_uses_only_options_that_exist_and_files_made_before():
    from typer.main import get_command

    from mimic.cli.main import app

    commands = getup_commands((REPO / "README.md").read_text())
    assert [shlex.split(c)[1] for c in commands] == ["train", *["improve"] * 4, "trial"]
    group = get_command(app)
    made = {RECORDING}
    assert (REPO / RECORDING).is_file()
    for command in commands:
        _, params = _parse(group, shlex.split(command)[1:])
        for key, value in params.items():
            for v in value if isinstance(value, (list, tuple)) else [value]:
                if key in _OUTPUTS and v is not None:
                    assert Path(v).parts[0] == "models", command
                    made.add(Path(v).as_posix())
                elif isinstance(v, Path) or str(v).endswith((".mimic", ".mcap")):
                    assert Path(str(v)).as_posix() in made, (
                        f"{command}: {v} is made by no earlier command"
                    )


def test_the_getup_block_s_training_knows_the_copy_starts_on_its_back(tmp_path):
    from mimic.model.model_file import load_model

    first = getup_commands((REPO / "README.md").read_text())[0]
    _ship_recording(tmp_path)
    done = run_block(first, tmp_path, timeout_s=600)
    assert done.returncode == 0, done.stdout + done.stderr
    model = load_model(tmp_path / "models" / "getup.mimic")
    assert model.metadata["start_posture"] == "lying_back" and model.robot == "t1"
    assert 10.2 < model.duration_s < 10.3


@pytest.mark.slow
def test_the_getup_block_runs_as_it_stands_and_its_copy_stands(tmp_path):
    _ship_recording(tmp_path)
    block = getup_block((REPO / "README.md").read_text())
    block = block.replace("--disturb none", "--disturb none -o out/getup.parquet")
    done = run_block(block, tmp_path, timeout_s=3600)
    said = done.stdout + done.stderr
    assert done.returncode == 0, said[-3000:]
    assert "--follow: window from" in said and "--window auto:" in said
    runs = pl.read_parquet(tmp_path / "out" / "getup.parquet")
    stood = runs.group_by("variant").agg(pl.col("stood").sum())
    counts = dict(zip(stood["variant"], stood["stood"]))
    assert counts["getup_back"] == 10 and counts["getup_fs (learned)"] >= 9
    assert counts["getup (learned)"] == 0


def _ship_recording(clone: Path) -> None:
    """The shipped recording where a fresh clone holds it."""
    (clone / "recordings").mkdir()
    (clone / RECORDING).write_bytes((REPO / RECORDING).read_bytes())
