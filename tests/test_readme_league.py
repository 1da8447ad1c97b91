"""The README's league quick start, run as it stands: a server of its own, a black-box
recording of the other team's walk, its copy learned step by step, played and tried.

Only what a test must change is changed: free ports for 60000/60001, one trial run per
variant, a shorter training, one round of fitting and a shorter play (the block's own figures come from the full
commands; ``docs/results.md``).
"""

from __future__ import annotations

import os
import re
import socket
import subprocess
import sys
from pathlib import Path

import polars as pl

REPO = Path(__file__).resolve().parents[1]


def readme_block(readme: str, heading: str) -> str:
    """The first bash block under ``heading`` (a README section title, ``## ...``)."""
    section = readme.split(heading, 1)[1]
    return re.search(r"```bash\n(.*?)```", section, re.S).group(1)


def league_block(readme: str) -> str:
    """The bash block under ``## Quick start: the league world``."""
    return readme_block(readme, "## Quick start: the league world")


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def shortened(block: str) -> str:
    aport, mport = _free_port(), _free_port()
    block = block.replace("60000", str(aport)).replace("60001", str(mport))
    block = block.replace("--runs 20", "--runs 1").replace("--duration 20", "--duration 6")
    return block.replace("--fit-in-sim 6", "--fit-in-sim 1 --epochs 1500")


def run_block(script: str, cwd: Path, timeout_s: float) -> subprocess.CompletedProcess:
    """A README block run by ``bash -e`` in ``cwd``, with this environment's commands first
    on the PATH (``mimic``, ``rcssservermj``)."""
    env = dict(os.environ)
    env["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{env.get('PATH', '')}"
    return subprocess.run(
        ["bash", "-e", "-c", script],
        cwd=cwd,
        env=env,
        capture_output=True,
        text=True,
        timeout=timeout_s,
    )


def test_the_readme_league_block_runs_as_it_stands(tmp_path):
    block = league_block((REPO / "README.md").read_text())
    assert "rcssservermj" in block and "--period steps" in block and "--fit-in-sim 6" in block
    done = run_block(shortened(block), tmp_path, timeout_s=900)
    said = done.stdout + done.stderr
    assert done.returncode == 0, said[-3000:]
    assert "Traceback" not in said
    assert "steps from the feet" in said and "walked" in said
    assert "fitted in the league-like world, 1 round " in said and "check walks" in said
    for made in ("out/seen.mcap", "models/seen_walk.mimic", "out/copy.mcap"):
        assert (tmp_path / made).is_file(), made
    runs = pl.read_parquet(tmp_path / "out" / "league_walk.parquet")
    assert runs.height == 2 and runs["world"].unique().to_list() == ["league"]
