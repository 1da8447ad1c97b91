"""Files are never lost or replaced silently (#31, section 2): an output is never an input,
one command writes a file at a time, outputs get a plain file's mode, and SIGTERM leaves no
worker processes behind. (The league commands' cases are in test_league_outputs.py.)"""

from __future__ import annotations

import os
import signal
import stat
import subprocess
import sys
import time
from pathlib import Path

import pytest
from _cli_helpers import one_line_error
from _learn_helpers import joint_frame, smooth_motion
from typer.testing import CliRunner

from mimic.cli.main import app
from mimic.files import OutputError, PendingOutput, atomic_output, check_output
from mimic.learn.dataset import dataset_from_frame
from mimic.learn.presets import FAST
from mimic.learn.train import TrainConfig, train_model
from mimic.model.model_file import save_model

runner = CliRunner()
_one_line_error = one_line_error


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """A short recording and a small model of it."""
    d = tmp_path_factory.mktemp("inputs")
    rec = d / "stand.mcap"
    result = runner.invoke(app, ["record", "stand", "-o", str(rec), "--duration", "0.5"])
    assert result.exit_code == 0, result.output
    t, q = smooth_motion(30)
    meta = {"motion": "wave", "team": "mimic", "ball_offset_m": [0.15, -0.05]}  # a "kick"
    ds = dataset_from_frame(joint_frame(t, q), metadata=meta)
    model = save_model(train_model(ds, TrainConfig(FAST, seed=0, epochs=20)), d / "wave.mimic")
    return {"rec": rec, "model": model}


@pytest.mark.parametrize(
    "args",
    [
        ["train", "{rec}", "-o", "{rec}", "--epochs", "5", "--force"],
        ["view", "{rec}", "--save", "{rec}", "--force"],
        ["view", "{rec}", "--model", "{model}", "--save", "{model}", "--force"],
        ["export", "{model}", "-o", "{model}", "--force"],
        ["record", "--model", "{model}", "-o", "{model}", "--duration", "0.1", "--force"],
        ["improve", "{model}", "--objective", "kick", "--budget", "4", "-o", "{model}", "--force"],
        ["trial", "kick", "{model}", "--minutes", "1", "-o", "{model}", "--force"],
    ],
)
def test_force_never_replaces_an_input(files, args):
    before = {k: p.read_bytes() for k, p in files.items()}
    result = runner.invoke(app, [a.format(**files) for a in args])
    _one_line_error(result, 2, "is also an input of this command")
    assert {k: p.read_bytes() for k, p in files.items()} == before


def test_an_input_named_another_way_is_the_same_file(files, tmp_path):
    link = tmp_path / "link.mimic"
    link.symlink_to(files["model"])
    with pytest.raises(OutputError, match="also an input"):
        check_output(link, force=True, inputs=[files["model"]])
    dotted = files["model"].parent / "." / files["model"].name
    with pytest.raises(OutputError, match="also an input"):
        check_output(dotted, force=True, inputs=[files["model"]])
    check_output(tmp_path / "other.mimic", force=True, inputs=[files["model"], None])


@pytest.mark.parametrize("umask", [0o022, 0o027, 0o077, 0o002])
def test_outputs_get_the_mode_a_plain_open_gives(tmp_path, umask):
    old = os.umask(umask)
    try:
        with open(tmp_path / "plain.txt", "w") as f:
            f.write("x")
        with atomic_output(tmp_path / "atomic.csv") as tmp:
            tmp.write_text("x")
        pending = PendingOutput(tmp_path / "pending.mcap")
        partial_mode = stat.S_IMODE(pending.tmp.stat().st_mode)  # a killed command's too
        pending.commit()
        result = runner.invoke(
            app, ["record", "stand", "-o", str(tmp_path / "rec.mcap"), "--duration", "0.1"]
        )
        assert result.exit_code == 0, result.output
    finally:
        os.umask(old)
    want = stat.S_IMODE((tmp_path / "plain.txt").stat().st_mode)
    assert want == 0o666 & ~umask
    assert partial_mode == want
    for name in ("atomic.csv", "pending.mcap", "rec.mcap"):
        assert stat.S_IMODE((tmp_path / name).stat().st_mode) == want, name


def test_one_writer_per_output(tmp_path):
    """While one command holds an output, another is refused at once, naming its pid; the
    claim leaves nothing behind, and one held by a process that died does not block."""
    from mimic.files import claim_output

    target = tmp_path / "sub" / "x.mcap"
    holder = subprocess.Popen(
        [
            sys.executable,
            "-c",
            "import sys, time; from mimic.files import claim_output\n"
            f"with claim_output({str(target)!r}):\n"
            "    print('held', flush=True); time.sleep(60)",
        ],
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        assert holder.stdout.readline().strip() == "held"
        with pytest.raises(
            OutputError, match=f"being written by another command .pid {holder.pid}"
        ):
            check_output(target, force=True)
        with pytest.raises(OutputError, match="being written by another command"):
            PendingOutput(target)
        result = runner.invoke(
            app, ["record", "stand", "-o", str(target), "--duration", "0.1", "--force"]
        )
        _one_line_error(result, 2, "being written by another command")
    finally:
        holder.kill()
        holder.wait()
    # A killed holder's lock file is left, but it holds nothing.
    with claim_output(target):
        with atomic_output(target) as tmp:  # the same process may write what it claimed
            tmp.write_text("mine")
    assert target.read_text() == "mine"
    assert sorted(p.name for p in target.parent.iterdir()) == ["x.mcap"]


def _children(pid: int) -> set[int]:
    out = set()
    for p in Path("/proc").iterdir():
        if p.name.isdigit():
            try:
                ppid = int((p / "stat").read_text().rsplit(")", 1)[1].split()[1])
            except (OSError, IndexError, ValueError):
                continue
            if ppid == pid:
                out.add(int(p.name))
    return out


@pytest.mark.skipif(not Path("/proc").is_dir(), reason="needs /proc")
def test_sigterm_to_a_trial_leaves_no_worker_or_resource_tracker(tmp_path):
    mimic = Path(sys.executable).with_name("mimic")
    command = [str(mimic)] if mimic.exists() else [sys.executable, "-m", "mimic.cli.main"]
    trial = subprocess.Popen(
        command + ["trial", "walk", "--runs", "40", "--workers", "2"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        cwd=tmp_path,
    )
    children: set[int] = set()
    try:
        deadline = time.monotonic() + 120
        while len(_children(trial.pid)) < 2 and time.monotonic() < deadline:
            time.sleep(0.2)  # a pool worker and the resource tracker
        children = _children(trial.pid)
        assert len(children) >= 2, "the trial started no worker"
        time.sleep(2)  # the worker is at work
        trial.send_signal(signal.SIGTERM)
        _, err = trial.communicate(timeout=120)
        assert trial.returncode == 143, err
        assert "Traceback" not in err
        deadline = time.monotonic() + 30
        while any(Path(f"/proc/{c}").exists() for c in children):
            assert time.monotonic() < deadline, "workers left running after SIGTERM"
            time.sleep(0.2)
    finally:
        if trial.poll() is None:
            trial.kill()
            trial.wait()
        for child in children | _children(trial.pid):
            try:
                os.kill(child, signal.SIGKILL)  # what SIGTERM left (parent 1 by now)
            except ProcessLookupError:
                pass
