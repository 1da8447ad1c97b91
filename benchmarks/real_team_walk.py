"""Learn a walk that never repeats, black-box, and try the copies in the league: one command.

    python benchmarks/real_team_walk.py [--agent other-team-policy-walk] [--out DIR]
        [--runs 20] [--seed 59] [--workers 2] [--disturb none game]

Every step is a command a user types (the README's "Learn a walk that never repeats"):

1. ``rcssservermj --no-render --sync --no-realtime`` on free ports; ``mimic record --server``
   records team ``others`` #2 from the monitor stream while ``mimic play AGENT --server``
   plays it for 25 s from where the server puts it (a real team's client plays here instead:
   ``--agent`` names any agent ``mimic play`` takes; for a team of your own, record it with
   the first two commands and pass ``--recording``).
2. ``mimic train`` four ways on its steady part (4-24 s): the study's method (time in,
   the reached angles), one fixed period found in the angles (``--period auto --symmetric``),
   each step timed on its own (``--period steps --symmetric``), and that with its references
   fitted in a simulation of the copy (``--fit-in-sim 6``). A way that refuses the recording
   is a row of its own, with its reason.
3. ``mimic trial walk --compare AGENT COPIES --world league --robot t1 --runs R --seed S
   --disturb LEVEL`` for each level (``DIR/walk_LEVEL.parquet``): 10 m from a standing
   start, the copies inside the balance layer (the study's without).

It also prints what the recording shows of the walk: its steps (count, mean, spread) and its
joint speeds, and what the fit did. Development used trial seeds 0, 1 and 7 (the first
measurement, before the start ramp in proportion to the step and the rate limit), episode
seeds 0-5 and 1000-1007, and the recordings of trial seeds 47 and 53 (the fit). Each version
of the walk and the copy was measured once on a seed of its own (11, 23, 31, 47, 53, then
the default 59; the balance layer's yaw damping, developed on episode seeds 0-7 and 100-115
with the recordings of seeds 47, 53, 59 and 61, on 83 and again on 59; docs/real-team-walk.md).
``--agent other-team-jittery-walk`` (the stand-in with a learned policy's action jitter): the
learning's robustness to jitter was developed on trial seeds 131-133 and measured on 151.
"""

from __future__ import annotations

import argparse
import os
import socket
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

MIMIC = str(Path(sys.executable).with_name("mimic"))
SERVER = str(Path(sys.executable).with_name("rcssservermj"))
#: How long the walk plays, and the steady part the copies learn [s of the recording].
PLAY_S, START_S, END_S = 25.0, 4.0, 24.0
#: The ways to learn it: (name, model file, ``mimic train`` options, the trial's variant).
WAYS = (
    ("the study's method", "study.mimic", ("--target", "reached"), ""),
    ("one fixed period", "fixed.mimic", ("--period", "auto", "--symmetric"), "+balance"),
    ("each step on its own", "steps.mimic", ("--period", "steps", "--symmetric"), "+balance"),
    (
        "each step, fitted in simulation",
        "fitted.mimic",
        ("--period", "steps", "--symmetric", "--fit-in-sim", "6"),
        "+balance",
    ),
)


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _run(*args: str, check: bool = True) -> subprocess.CompletedProcess:
    print("$ " + " ".join(args), flush=True)
    env = {**os.environ, "COLUMNS": "200"}
    done = subprocess.run(args, capture_output=True, text=True, env=env)
    if check and done.returncode != 0:
        sys.exit(f"failed: {done.stderr.strip() or done.stdout.strip()}")
    return done


def record(agent: str, out: Path) -> Path:
    """Steps 1: the agent played on a server of its own, recorded black-box."""
    seen = out / "seen.mcap"
    aport, mport = _free_port(), _free_port()
    server = subprocess.Popen(
        [SERVER, "--no-render", "--sync", "--no-realtime", "--aport", str(aport),
         "--mport", str(mport)],
        cwd=out, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
    )  # fmt: skip
    try:
        time.sleep(2.0)
        recorder = subprocess.Popen(
            [MIMIC, "record", "--server", f"localhost:{mport}", "--team", "others", "--player",
             "2", "-o", str(seen), "--force"],
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
        )  # fmt: skip
        time.sleep(1.0)
        _run(
            MIMIC, "play", agent, "--server", f"localhost:{aport}", "--team", "others",
            "--player", "2", "--seconds", str(PLAY_S),
        )  # fmt: skip
        said, _ = recorder.communicate(timeout=60)
        if recorder.returncode != 0:
            sys.exit(f"mimic record failed: {said.strip()}")
        print(said.strip().splitlines()[-1])
    finally:
        server.terminate()
        server.wait(timeout=30)
    return seen


def joint_speeds(seen: Path) -> str:
    """The recording's joint speeds over its steady part: 99th percentile and largest [rad/s]."""
    from mimic.learn.dataset import cut_dataset, dataset_from_file

    ds = cut_dataset(dataset_from_file(seen, "/joint_states"), START_S, END_S)
    speed = np.abs(np.diff(ds.angles_rad, axis=0)) / np.diff(ds.time_s)[:, None]
    return (
        f"joint speeds (25 Hz differences): 99th percentile {np.percentile(speed, 99):.1f} "
        f"rad/s, largest {speed.max():.1f} rad/s"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--agent", default="other-team-policy-walk")
    parser.add_argument("--recording", type=Path, help="learn this recording instead of step 1")
    parser.add_argument("--out", type=Path, default=Path("real_team_walk"))
    parser.add_argument("--runs", type=int, default=20)
    parser.add_argument("--seed", type=int, default=59)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument(
        "--disturb",
        nargs="+",
        default=["none"],
        help="trial disturbance levels, one table each (none: the published tables)",
    )
    args = parser.parse_args()
    if args.runs < 1 or args.workers < 1:
        sys.exit("--runs and --workers must be >= 1")
    args.out.mkdir(parents=True, exist_ok=True)
    seen = args.recording or record(args.agent, args.out)
    print(joint_speeds(seen))
    variants, refused = [args.agent], []
    for name, model, how, suffix in WAYS:
        path = args.out / model
        done = _run(
            MIMIC, "train", str(seen), "--start", str(START_S), "--end", str(END_S), *how,
            "-o", str(path), "--force", check=False,
        )  # fmt: skip
        lines = (done.stdout + done.stderr).splitlines()
        if done.returncode != 0:
            refused.append(f"{name}: refused: {lines[-1] if lines else done.returncode}")
            continue
        said = ("steps from the feet", "fitted in the", "check walks")
        print("\n".join(f"  {line}" for line in lines if any(s in line for s in said)))
        variants.append(f"{path}{suffix}")
    for level in args.disturb:
        trial = _run(
            MIMIC, "trial", "walk", "--compare", *variants, "--world", "league", "--robot", "t1",
            "--runs", str(args.runs), "--seed", str(args.seed), "--workers", str(args.workers),
            "-o", str(args.out / f"walk_{level}.parquet"), "--force", "--disturb", level,
        )  # fmt: skip
        print(trial.stdout)
    print("\n".join(refused))


if __name__ == "__main__":
    main()
