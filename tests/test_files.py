"""`mimic.files` and `mimic.options`: outputs appear whole or not at all; inputs and option
values fail with one clear line."""

from __future__ import annotations

import math

import pytest

from mimic import options
from mimic.errors import MimicError
from mimic.files import (
    OutputError,
    PendingOutput,
    atomic_output,
    check_output,
    check_outputs,
    input_file,
)


def test_atomic_output_appears_only_when_complete(tmp_path):
    target = tmp_path / "sub" / "table.csv"
    with atomic_output(target) as tmp:
        assert tmp.parent == target.parent and tmp.suffix == ".csv" and ".partial-" in tmp.name
        tmp.write_text("half")
        assert not target.exists()
    assert target.read_text() == "half" and list(target.parent.iterdir()) == [target]


def test_a_failed_write_keeps_the_old_file_and_leaves_nothing_else(tmp_path):
    target = tmp_path / "good.rrd"
    target.write_text("good")
    with pytest.raises(RuntimeError):
        with atomic_output(target) as tmp:
            tmp.write_text("stub")
            raise RuntimeError("failed half way")
    assert target.read_text() == "good" and list(tmp_path.iterdir()) == [target]


def test_without_overwrite_a_file_that_appeared_meanwhile_is_kept(tmp_path):
    target = tmp_path / "model.mimic"
    pending = PendingOutput(target, overwrite=False)
    pending.tmp.write_text("new")
    target.write_text("written by another command")
    with pytest.raises(OutputError, match="appeared while this command ran") as err:
        pending.commit()
    assert target.read_text() == "written by another command"
    assert pending.tmp.read_text() == "new" and str(pending.tmp) in str(err.value)


def test_check_output_refuses_existing_files_and_folders(tmp_path):
    (tmp_path / "x.mcap").write_text("x")
    with pytest.raises(OutputError, match=r"x.mcap exists; pass --force"):
        check_output(tmp_path / "x.mcap")
    assert check_output(tmp_path / "x.mcap", force=True) == tmp_path / "x.mcap"
    with pytest.raises(OutputError, match="is a directory"):
        check_output(tmp_path, force=True)
    check_output(tmp_path / "new" / "dir" / "y.rrd")
    assert not (tmp_path / "new").exists(), "a check creates nothing"
    (tmp_path / "file").write_text("in the way")
    with pytest.raises(OutputError, match="cannot create the folder"):
        check_output(tmp_path / "file" / "sub" / "y.rrd")
    with pytest.raises(OutputError, match="given for two outputs"):
        check_outputs([tmp_path / "a.csv", None, tmp_path / "." / "a.csv"])


def test_input_file_names_folders_and_missing_files(tmp_path):
    with pytest.raises(MimicError, match="is a directory, not a recording"):
        input_file(tmp_path, "recording")
    with pytest.raises(MimicError, match="no such file; record one"):
        input_file(tmp_path / "nope.mcap", "recording", "record one")
    with pytest.raises(MimicError, match="no such model file"):
        input_file(tmp_path / "nope.mimic", "model file")


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf, 0.0, -1.0, "x"])
def test_finite_rejects_nan_infinity_and_out_of_range(value):
    with pytest.raises(options.OptionError, match=r"--minutes must be a finite number > 0") as err:
        options.finite(value, "--minutes", above=0)
    assert "\n" not in str(err.value)


def test_option_ranges():
    assert options.finite(None, "--warmup", at_least=0) is None
    assert options.finite(0.0, "--warmup", at_least=0) == 0.0
    assert options.seed(0) == 0 and options.seed(options.MAX_SEED) == options.MAX_SEED
    for bad in (-5, options.MAX_SEED + 1, True):
        with pytest.raises(options.OptionError, match="--seed must be a whole number"):
            options.seed(bad)
    assert options.workers(None) is None and options.workers(2) == 2
    for bad in (0, -3):
        with pytest.raises(options.OptionError, match="--workers must be a whole number >= 1"):
            options.workers(bad)
