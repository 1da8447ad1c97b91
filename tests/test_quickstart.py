"""The README's quick start: every command, in order, on a copy of the repository as a fresh
clone holds it, through the installed `mimic` and `rerun` commands (trials shortened to 0.1
simulated minutes and one worker; see ``scripts/new_user.py``).

The full run trains five networks and runs a benchmark (about two minutes on two cores), so it
is marked slow (``python -m pytest -m slow``); a parse of every command, checking that each
file it reads is shipped or made by an earlier command, always runs.
"""

from __future__ import annotations

import importlib.util
import os
import shutil
import sys
from pathlib import Path

import polars as pl
import pytest

REPO = Path(__file__).resolve().parents[1]


def _new_user():
    spec = importlib.util.spec_from_file_location("new_user", REPO / "scripts" / "new_user.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_quick_start_commands_are_read_from_the_readme():
    new_user = _new_user()
    commands = new_user.quickstart_commands((REPO / "README.md").read_text())
    assert commands[0] == "mimic --help" and len(commands) >= 10
    assert all(c.startswith(("mimic ", "rerun ")) for c in commands)
    assert (
        new_user.shortened("mimic trial kick a b --minutes 30 -o x", 0.1)
        == "mimic trial kick a b -o x --minutes 0.1 --workers 1"
    )
    assert (
        new_user.shortened("rerun out/k.mcap", 0.1)
        == "rerun mcap convert out/k.mcap -o out/k_rerun.rrd"
    )


#: Options that name a file a command writes; every other path or model variant is an input.
_OUTPUTS = {"out", "onnx", "save", "save_old"}


def _parse(group, words: list[str]):
    """(command name, parsed parameters) of ``mimic WORDS``, through click's own parser:
    an unknown option or a bad value raises ``click.UsageError``."""

    def rest(c) -> list[str]:  # what a group leaves for its subcommand
        return [*getattr(c, "_protected_args", getattr(c, "protected_args", [])), *c.args]

    ctx = group.make_context("mimic", list(words))
    name, cmd, args = group.resolve_command(ctx, rest(ctx))
    while hasattr(cmd, "resolve_command"):  # trial kick, bench train
        sub = cmd.make_context(name, args, parent=ctx)
        name, cmd, args = cmd.resolve_command(sub, rest(sub))
    return name, cmd.make_context(name, args, parent=ctx).params


def test_quick_start_uses_only_options_that_exist_and_files_made_before():
    """Cheap and always run: each command parses, and each file it reads is shipped or made
    by an earlier command (the full run is ``test_readme_quick_start_runs_in_order...``)."""
    import shlex

    from typer.main import get_command

    from mimic.cli.main import app
    from mimic.pipeline import paper_outputs

    new_user = _new_user()
    made = set(new_user.tracked_files(REPO))
    group = get_command(app)
    for command in new_user.quickstart_commands((REPO / "README.md").read_text()):
        words = shlex.split(command)
        if words[0] == "rerun":
            assert words[1] in made, f"{command}: {words[1]} is made by no earlier command"
            continue
        if "--help" in words:
            continue
        name, params = _parse(group, words[1:])
        if name == "paper":
            made |= {p.as_posix() for p in paper_outputs(params["out"])}
        for key, value in params.items():
            values = value if isinstance(value, (list, tuple)) else [value]
            for v in values:
                text = str(v).removesuffix("+balance")
                if key in _OUTPUTS and v is not None:
                    made.add(Path(v).as_posix())
                elif isinstance(v, Path) or text.endswith((".mimic", ".mcap")):
                    assert Path(text).as_posix() in made, (
                        f"{command}: {text} is made by no earlier command"
                    )


def test_quick_start_writes_only_under_out_and_models():
    """The quick start says it writes into out/ and models/: every file a command of it names
    as an output is there, none in the repository's root (#31: walk.json, improve.rrd)."""
    import shlex

    from typer.main import get_command

    from mimic.cli.main import app

    group = get_command(app)
    outputs = []
    for command in _new_user().quickstart_commands((REPO / "README.md").read_text()):
        words = shlex.split(command)
        if words[0] == "rerun" or "--help" in words:
            continue
        _, params = _parse(group, words[1:])
        outputs += [Path(v) for k, v in params.items() if k in _OUTPUTS and v is not None]
    assert outputs
    for path in outputs:
        assert not path.is_absolute() and path.parts[0] in ("out", "models"), path


@pytest.mark.slow
def test_readme_quick_start_runs_in_order_on_a_fresh_copy(tmp_path):
    new_user = _new_user()
    clone = new_user.copy_tree(tmp_path / "mimic")
    shipped = {p.name: p.read_bytes() for p in (clone / "recordings").glob("*.mcap")}
    env = dict(os.environ)
    env["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{env.get('PATH', '')}"
    if shutil.which("rerun", path=env["PATH"]) is None:
        pytest.skip("the rerun command is not installed")
    results = new_user.run_quickstart(clone, minutes=0.1, env=env, log=lambda line: None)
    commands = new_user.quickstart_commands((clone / "README.md").read_text())
    # Without the optional ray extra, the Ray command must refuse in one line that says how to
    # install it (the quick start's comment says so too); with it, it must run.
    ray_missing = importlib.util.find_spec("ray") is None

    def refused_for_ray(cmd: str, out: str) -> bool:
        return ray_missing and new_user.ray_extra_missing(cmd, out)

    failed = [
        f"$ {cmd}\n{out}"
        for cmd, code, out in results
        if code != 0 and not refused_for_ray(cmd, out)
    ]
    assert not failed, failed[0]
    assert len(results) == len(commands)
    assert all("Traceback" not in out for _, _, out in results)
    # What the quick start says it makes is there; the shipped recordings are untouched.
    for made in (
        "out/kick_right.mcap",
        "out/kick.rrd",
        "models/kick_right.mimic",
        "out/kick_right.onnx",
        "out/kick.parquet",
        "models/other_team_walk.mimic",
        "out/paper/walk_trial.parquet",
        "out/walk.json",
        "out/improve.rrd",
    ):
        assert (clone / made).is_file(), made
    assert {p.name: p.read_bytes() for p in (clone / "recordings").glob("*.mcap")} == shipped
    assert not list(clone.rglob("*.partial-*"))
    kick = pl.read_parquet(clone / "out" / "kick.parquet")
    assert set(kick["variant"]) == {"kick_right", "kick_right (learned)"}
