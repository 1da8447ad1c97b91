"""`mimic record`, `mimic info`, `mimic import`: exit codes, one-line errors, Ctrl-C safety."""

import json
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from _learn_helpers import PAPER_DATA as PAPER  # noqa: E402
from typer.testing import CliRunner

from mimic.cli.main import app
from mimic.recording.reader import read_joint_table, read_recording

runner = CliRunner()


def test_record_then_info_json(tmp_path):
    out = tmp_path / "stand.mcap"
    result = runner.invoke(app, ["record", "stand", "-o", str(out), "--duration", "1"])
    assert result.exit_code == 0, result.output
    result = runner.invoke(app, ["info", str(out), "--json"])
    assert result.exit_code == 0
    summary = json.loads(result.output)
    assert summary["motion"] == "stand" and summary["duration_s"] == pytest.approx(1.0)
    assert summary["topics"]["/joint_states"]["messages"] == 51
    assert summary["complete"] and not summary["interrupted"]


@pytest.mark.parametrize(
    "args, message",
    [
        (["record", "moonwalk", "-o", "x.mcap"], "unknown agent 'moonwalk'"),
        (["record", "stand"], "-o FILE.mcap"),
        (["info", "missing.mcap"], "no such file"),
        (["import", "missing.txt", "-o", "x.mcap"], "cannot read the file"),
    ],
)
def test_bad_input_is_one_line_and_nonzero(tmp_path, monkeypatch, args, message):
    monkeypatch.chdir(tmp_path)  # undone after the test, unlike os.chdir
    result = runner.invoke(app, args)
    assert result.exit_code != 0
    assert message in result.output
    assert "Traceback" not in result.output


def test_info_on_a_text_file(tmp_path):
    bad = tmp_path / "bad.mcap"
    bad.write_text("not a recording")
    result = runner.invoke(app, ["info", str(bad)])
    assert result.exit_code == 2 and "not an MCAP file" in result.output


def test_import_paper_kick(tmp_path):
    src = PAPER / "kick_itandroids.txt"
    if not src.exists():
        pytest.skip(f"study data not found at {PAPER}")
    out = tmp_path / "kick.mcap"
    result = runner.invoke(app, ["import", str(src), "-o", str(out)])
    assert result.exit_code == 0, result.output
    assert "/joint_references" in result.output
    assert len(read_joint_table(out, topic="/joint_references")) == 77


def test_ctrl_c_leaves_a_valid_file(tmp_path):
    out = tmp_path / "long.mcap"
    mimic = Path(sys.executable).with_name("mimic")
    cmd = [str(mimic)] if mimic.exists() else [sys.executable, "-m", "mimic.cli.main"]
    proc = subprocess.Popen(
        cmd + ["record", "stand", "-o", str(out), "--duration", "600"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    deadline = time.monotonic() + 60

    def written() -> int:  # the recording is written under a temporary name until it ends
        return sum(p.stat().st_size for p in tmp_path.glob("long.partial-*.mcap"))

    while time.monotonic() < deadline and written() < 20_000:
        time.sleep(0.1)  # wait until the recording is under way (a few chunks written)
    time.sleep(1.0)
    proc.send_signal(signal.SIGINT)
    _, stderr = proc.communicate(timeout=60)
    assert proc.returncode == 130, stderr
    assert "interrupted" in stderr and "Traceback" not in stderr
    assert not list(tmp_path.glob("*.partial-*")), "moved into place"
    rec = read_recording(out)
    assert rec.recovery.complete and rec.interrupted
    table = read_joint_table(rec)
    assert 0.5 < table["time_s"][-1] < 600
    assert rec.recovery.last_time_s == pytest.approx(table["time_s"][-1])
