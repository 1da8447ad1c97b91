"""Try mimic as a new user would: a fresh clone, (optionally) a fresh venv, then every command of
the README's quick start, in order.

    python scripts/new_user.py                   # clone HEAD to a temp folder, run the quick start
    python scripts/new_user.py --venv            # ... in a fresh venv made there (pip install -e .)
    python scripts/new_user.py --minutes 30      # with the README's own trial lengths

Trial lengths are shortened (``--minutes 0.1`` by default; ``--minutes 0`` keeps the README's),
trials run with one worker and ``mimic bench train`` with a short baseline; everything else runs
as written. A ``rerun FILE.mcap`` line (it opens a viewer) runs as ``rerun mcap convert``, the
same importer without a window. ``tests/test_quickstart.py`` runs the same steps on a copy of
the working tree, so the README and the code cannot drift apart.

Exit status: 0 when every command succeeded; else the first failing command's.
"""

from __future__ import annotations

import argparse
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

__all__ = [
    "quickstart_commands",
    "shortened",
    "run_quickstart",
    "tracked_files",
    "copy_tree",
    "main",
]

REPO = Path(__file__).resolve().parents[1]


def quickstart_commands(readme: str) -> list[str]:
    """The commands of the README's ``## Quick start`` bash block, comments removed."""
    section = readme.split("## Quick start", 1)[1]
    block = re.search(r"```bash\n(.*?)```", section, re.S)
    if block is None:
        raise ValueError("README: no ```bash block under '## Quick start'")
    commands = []
    for line in block.group(1).splitlines():
        line = line.split(" #", 1)[0].strip() if not line.lstrip().startswith("#") else ""
        if line:
            commands.append(line)
    return commands


def shortened(command: str, minutes: float) -> str:
    """``command`` with short trials (``--minutes``, one worker) and a short benchmark;
    ``rerun FILE.mcap`` becomes ``rerun mcap convert FILE.mcap -o FILE.rrd`` (no window)."""
    words = shlex.split(command)
    if words[:1] == ["rerun"] and len(words) == 2 and words[1].endswith(".mcap"):
        return shlex.join(
            ["rerun", "mcap", "convert", words[1], "-o", words[1][: -len(".mcap")] + "_rerun.rrd"]
        )
    if minutes <= 0 or words[:1] != ["mimic"]:
        return command
    if words[1:3] == ["bench", "train"]:
        return shlex.join(words + ["--baseline-epochs", "200", "--batch", "2"])
    if words[1] in ("trial", "paper", "demo"):
        out = []
        skip = False
        for w in words:
            if skip:
                skip = False
                continue
            if w == "--minutes":
                skip = True
                continue
            out.append(w)
        return shlex.join(out + ["--minutes", f"{minutes:g}", "--workers", "1"])
    return command


def run_quickstart(
    workdir: Path, *, minutes: float = 0.1, env: dict | None = None, log=print
) -> list[tuple[str, int, str]]:
    """Run the quick start of ``workdir/README.md`` in ``workdir``, stopping at the first failure
    (a ``--ray`` command refused for want of the optional ray extra is not one).

    Returns:
        (command as run, exit status, its output) for each command run.
    """
    env = dict(os.environ if env is None else env)
    env.setdefault("RERUN_ANALYTICS", "off")
    env.setdefault("COLUMNS", "80")
    results = []
    for command in quickstart_commands((workdir / "README.md").read_text()):
        run = shortened(command, minutes)
        log(f"$ {run}")
        start = time.monotonic()
        proc = subprocess.run(run, shell=True, cwd=workdir, env=env, capture_output=True, text=True)
        output = proc.stdout + proc.stderr
        log(f"  exit {proc.returncode} after {time.monotonic() - start:.0f} s")
        results.append((run, proc.returncode, output))
        if proc.returncode != 0:
            log(output)
            if not ray_extra_missing(run, output):  # the quick start says Ray is optional
                break
    return results


def ray_extra_missing(command: str, output: str) -> bool:
    """Whether ``command`` was refused only because the optional ray extra is not installed."""
    return "--ray" in command.split() and output.strip().splitlines() == [
        'error: --ray needs the ray extra: pip install -e ".[ray]"'
    ]


def tracked_files(repo: Path = REPO) -> list[str]:
    """Paths (relative, with /) of the files a clone of ``repo`` holds: what git tracks, or,
    outside a git checkout, every file but hidden ones and the ignored outputs."""
    try:
        listed = (
            subprocess.run(
                ["git", "-C", str(repo), "ls-files", "-z"], check=True, capture_output=True
            )
            .stdout.decode()
            .split("\0")
        )
        return [n for n in listed if n and (repo / n).is_file()]
    except (OSError, subprocess.CalledProcessError):
        skip = {"out", "models", "build", "__pycache__"}
        return [
            p.relative_to(repo).as_posix()
            for p in repo.rglob("*")
            if p.is_file()
            and not any(
                part.startswith(".") or part in skip or part.endswith(".egg-info")
                for part in p.relative_to(repo).parts
            )
        ]


def copy_tree(dest: Path, repo: Path = REPO) -> Path:
    """The files a clone of ``repo`` holds (``tracked_files``), as they are in its working
    tree, copied to ``dest``."""
    for name in tracked_files(repo):
        (dest / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(repo / name, dest / name)
    return dest


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--minutes",
        type=float,
        default=0.1,
        help="simulated minutes per trial (0: as the README says)",
    )
    parser.add_argument(
        "--venv",
        action="store_true",
        help="make a fresh venv in the clone and pip install -e . there",
    )
    parser.add_argument("--keep", action="store_true", help="keep the clone afterwards")
    args = parser.parse_args(argv)
    root = Path(tempfile.mkdtemp(prefix="mimic-new-user-"))
    clone = root / "mimic"
    subprocess.run(["git", "clone", "--quiet", str(REPO), str(clone)], check=True)
    env = dict(os.environ)
    if args.venv:
        venv = clone / ".venv"
        subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
        subprocess.run([str(venv / "bin" / "pip"), "install", "-q", "-e", str(clone)], check=True)
        env["PATH"] = f"{venv / 'bin'}{os.pathsep}{env.get('PATH', '')}"
        env.pop("PYTHONPATH", None)
    results = run_quickstart(clone, minutes=args.minutes, env=env)
    failed = [r for r in results if r[1] != 0]
    print(
        f"{len(results) - len(failed)} of {len(quickstart_commands((clone / 'README.md').read_text()))}"
        f" quick-start commands ran" + (f"; failed: {failed[0][0]}" if failed else "")
    )
    if args.keep:
        print(f"kept {clone}")
    else:
        shutil.rmtree(root, ignore_errors=True)
    return failed[0][1] if failed else 0


if __name__ == "__main__":
    sys.exit(main())
