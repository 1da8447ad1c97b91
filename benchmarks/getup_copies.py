"""Get-ups learned black-box (issue 35): our T1 ``getup_front``/``getup_back`` seen through a
hosted league server's monitor, our NAO's seen through ``/joint_states`` in our world, learned
with ``mimic train`` and tried against the originals in ``mimic trial getup``.

    python benchmarks/getup_copies.py [--out DIR] [--robot t1|nao] [--side front|back]
        [--runs 10] [--seed 1000 [--seed 3000 ...]] [--budget B] [--workers 2]

Each step is what a user would type (``shared.record_black_box`` stands for the two
processes of the README's league block: the motion played on a server while ``mimic record
--server`` records it from the monitor stream):

1. Record: the T1 lying on its front (back) on a server mimic hosts, playing the get-up while
   ``mimic record --server`` records it (seed 0); the NAO with ``mimic record getup_front
   --observe-only`` (reached angles only). The window is the get-up: from the recording's
   first sample to the time the agent played.
2. ``mimic train REC --end E --target reached`` (the study's method) and ``mimic train REC
   --end E`` (compensated, the default for observed angles): the models know they start
   lying (``start_posture``, from the torso at the window's start).
3. ``mimic improve COPY.mimic --objective getup --budget B --episodes E --seed 3``: the
   compensated copy's time warp, per-leg-joint offsets and gains searched on get-up trial
   episodes, the T1's in our world made league-like (``--world league-like``: the league's
   solver and command delay; E 4, B 100), the NAO's in ours (E 16, B 200, ``--pick mean``:
   its copies stand in 85-95 % of runs as compensated, so a candidate is scored on 16 draws
   of the start noise and the search writes its final mean, not its luckiest candidate;
   ``--validate 0``: the trial below is the validation).
   The objective scores runs that stay down in stages (how high the torso rose, how far it
   turned to face the ground, how long it was upright), so the T1's back copy, which sits
   up and falls back as compensated, is searched into rolling onto its front. The T1's front
   copy then gets its stand searched (``mimic improve IMPROVED.mimic --window auto --seed
   4``, below; docs/getups.md, "The front get-up's stand": a fresh recording's copy rose and
   toppled in the hold), and so does the copy of a second whole-motion search (``--seed
   5``); ``mimic trial getup STAND AGAIN_STAND --keep-best KEPT`` keeps the one that stood
   more often in 20 league runs at the development seed 13500 (then the faster). The back
   copy gets a chain (docs/getups.md, "The stand window placed by the copy's own runs"): a
   second whole-motion search (``--seed 5``; it brought
   recording C's copy upright, not R1's or R2's), then a search over the stand alone,
   ``mimic improve AGAIN.mimic --window auto --seed 4``: the window from just before the
   copy is first upright in its own runs (or highest, if never upright) to its end, placed
   by ``mimic improve`` itself. Each search: ``--budget`` evaluations. Beside it, the
   second search's copy fitted until it follows its recording after its roll
   (``mimic improve AGAIN.mimic --follow REC --budget 24 --episodes 3 --seed 3``;
   docs/getups.md, "Following the recording": fitted on the joints alone and with the
   recording's torso pitch on the hips, then, for a copy that does not rise, both with a
   1 s front each run mends for itself, kept only if it follows further; the fit that
   follows further kept), and that copy's stand searched (``--window auto --seed 4``). The
   same chain then runs again from the compensated copy on other seeds (searches 6 and 7,
   follow 6, stand 8), and ``--keep-best`` keeps one of the three stands searched (after the
   second search, after the follow, the second chain's) as for the front.
4. ``mimic trial getup --compare ORIGINAL REACHED COMPENSATED IMPROVED --runs R --seed S``:
   the T1 in the league's simulation (``--world league``) and in ours, the NAO in ours; one
   table per ``--seed`` given (the copies are learned once).

Seeds: development used trial seeds 0-999 (the T1's back get-up: league-like trial seeds 0-5;
the kept copy: league seed 13500) and improve seeds 3-5 (the NAO's search settings: improve
seed 11 too); the reported tables use ``--seed`` (default 1000; docs/getups.md says which
seeds were reported), whose episodes nothing in development played.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from shared import mimic, record_black_box

from mimic.agents.registry import agent_spec
from mimic.episode import Scene

#: Longest a get-up plays while recorded [s] (the T1's back get-up takes 10.3 s).
PLAY_S = 14.0
#: The improve search's seed (development), the stand window's and the second whole-motion
#: search's (the T1's back get-up).
IMPROVE_SEED, WINDOW_SEED, AGAIN_SEED = 3, 4, 5
#: The improve search per robot: (episodes per candidate, default budget, what it writes).
#: The NAO's copies fall back from their squat in 5-15 % of runs as compensated, which 4
#: episodes cannot tell apart, and the best candidate of many that stood in all their
#: episodes is the luckiest (and fastest), not the surest: the NAO's search scores each
#: candidate on 16 episodes and writes the optimiser's final mean (docs/getups.md); its
#: episodes are cheap (0.1-0.3 s each).
SEARCH = {"t1": (4, 100, "best"), "nao": (16, 200, "mean")}
#: The back get-up's second chain: the seeds of its two whole-motion searches, its follow
#: and its stand.
SECOND_CHAIN_SEEDS = (6, 7, 6, 8)
#: The T1's copies kept: the best of two chains over this many league runs at this seed.
KEEP_RUNS, KEEP_SEED = 20, 13500
#: ``mimic improve --follow`` on the T1's back copy after its two whole-motion searches:
#: rounds and runs per round (docs/getups.md, "Following the recording").
FOLLOW_ROUNDS, FOLLOW_RUNS = 24, 3


def record(robot: str, side: str, out: Path) -> tuple[Path, float]:
    """The get-up recorded black-box; (recording, the window's end [s])."""
    path = out / f"{robot}_{side}.mcap"
    motion = f"getup_{side}"
    if robot == "t1":
        agent = agent_spec(motion, robot="t1").build()
        scene = Scene(robot_xy_m=(-1.0, 0.0), posture=f"lying_{side}", settle_s=0.5)
        played_s = record_black_box(agent, scene, path, 0, PLAY_S, 0, 2.0)
        return path, round(played_s, 2)
    mimic("record", motion, "--robot", robot, "--observe-only", "-o", str(path), "--force")
    return path, 0.0  # our recorder stops when the motion ends


def learn(
    robot: str, side: str, rec: Path, end_s: float, out: Path, budget: int | None, workers: int
) -> list[str]:
    """The copies' files: reached, compensated, improved, then the T1's steps after the search
    (front: the stands of one and of two searches, and the kept one; back: the second search,
    its stand, the followed copy and its stand, the second chain's stand, and the kept one)."""
    window = ["--end", str(end_s)] if end_s else []
    topic = [] if robot == "t1" else ["--topic", "/joint_states"]
    reached, compensated = out / f"{robot}_{side}_reached.mimic", out / f"{robot}_{side}.mimic"
    improved = out / f"{robot}_{side}_improved.mimic"
    mimic("train", str(rec), *window, *topic, "--target", "reached", "-o", str(reached), "--force")
    mimic("train", str(rec), *window, *topic, "-o", str(compensated), "--force")
    world = "league-like" if robot == "t1" else "mujoco"
    episodes, default_budget, pick = SEARCH[robot]
    budget = default_budget if budget is None else budget
    search = [
        "--objective", "getup", "--robot", robot, "--world", world, "--episodes",
        str(episodes), "--validate", "0", "--pick", pick, "--workers", str(workers),
    ]  # fmt: skip

    def whole(start: Path, to: Path, seed: int) -> None:
        """``mimic improve START`` over the whole motion."""
        mimic(
            "improve", str(start), *search, "--budget", str(budget), "--seed", str(seed),
            "-o", str(to), "--force",
        )  # fmt: skip

    def follow(start: Path, to: Path, seed: int) -> None:
        """``mimic improve START --follow REC``: fitted until it follows its recording."""
        lines = mimic(
            "improve", str(start), "--objective", "getup", "--robot", robot, "--world", world,
            "--follow", str(rec), "--budget", str(FOLLOW_ROUNDS), "--episodes",
            str(FOLLOW_RUNS), "--seed", str(seed), "-o", str(to), "--force",
        )  # fmt: skip
        print("\n".join(line for line in lines if line.startswith("--follow")), flush=True)

    def search_stand(copy: Path, to: Path, seed: int = WINDOW_SEED) -> None:
        """``mimic improve COPY --window auto``: the copy's stand searched."""
        lines = mimic(
            "improve", str(copy), *search, "--window", "auto", "--budget", str(budget),
            "--seed", str(seed), "-o", str(to), "--force",
        )  # fmt: skip
        print("\n".join(line for line in lines if line.startswith("--window auto")), flush=True)

    whole(compensated, improved, IMPROVE_SEED)
    copies = [str(reached), str(compensated), str(improved)]
    if robot != "t1":
        return copies
    again = out / f"{robot}_{side}_improved_again.mimic"
    whole(improved, again, AGAIN_SEED)
    kept = out / f"{robot}_{side}_kept.mimic"
    if side == "front":
        # The whole-motion search's copy can rise and topple in the hold (docs/getups.md,
        # "The front get-up's stand"): its stand is searched, as the back get-up's is, after
        # one search and after two; the trial keeps the one that stands more.
        stand = out / f"{robot}_{side}_stand.mimic"
        again_stand = out / f"{robot}_{side}_again_stand.mimic"
        search_stand(improved, stand)
        search_stand(again, again_stand)
        keep_best(robot, [stand, again_stand], kept, workers)
        return copies + [str(stand), str(again_stand), str(kept)]
    stand = out / f"{robot}_{side}_improved_stand.mimic"
    search_stand(again, stand)
    followed = out / f"{robot}_{side}_followed.mimic"
    followed_stand = out / f"{robot}_{side}_followed_stand.mimic"
    follow(again, followed, IMPROVE_SEED)
    search_stand(followed, followed_stand)
    # The same chain again from the compensated copy, on other seeds (docs/getups.md,
    # "A second chain"): one chain's copy of a recording can stand 4-6 of 10 where the
    # other's stands 10 of 10; the trial keeps the better.
    first, second, fitted, fitted_stand = (
        out / f"{robot}_{side}_chain2_{step}.mimic"
        for step in ("improved", "again", "followed", "followed_stand")
    )
    seeds = SECOND_CHAIN_SEEDS
    whole(compensated, first, seeds[0])
    whole(first, second, seeds[1])
    follow(second, fitted, seeds[2])
    search_stand(fitted, fitted_stand, seeds[3])
    keep_best(robot, [stand, followed_stand, fitted_stand], kept, workers)
    return copies + [
        str(again), str(stand), str(followed), str(followed_stand), str(fitted_stand), str(kept)
    ]  # fmt: skip


def keep_best(robot: str, candidates: list[Path], kept: Path, workers: int) -> None:
    """``mimic trial getup A B --keep-best KEPT``: the copy that stood more often (then the
    faster) in ``KEEP_RUNS`` league runs at the development seed ``KEEP_SEED``."""
    lines = mimic(
        "trial", "getup", *map(str, candidates), "--robot", robot, "--world", "league",
        "--runs", str(KEEP_RUNS), "--seed", str(KEEP_SEED), "--workers", str(workers),
        "--disturb", "none", "--keep-best", str(kept), "--force",
    )  # fmt: skip
    print("\n".join(lines), flush=True)


def trial(robot: str, side: str, copies: list[str], world: str, seed: int, args, out: Path) -> None:
    table = out / f"{robot}_{side}_{world}_{seed}.parquet"
    print(f"trial seed {seed}:", flush=True)
    lines = mimic(
        "trial", "getup", "--compare", f"getup_{side}", *copies, "--robot", robot, "--world",
        world, "--runs", str(args.runs), "--seed", str(seed), "--workers",
        str(args.workers), "-o", str(table), "--force", "--disturb", "none",
    )  # fmt: skip
    print("\n".join(lines), flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("out/getup_copies"))
    parser.add_argument("--robot", choices=("t1", "nao"), action="append")
    parser.add_argument("--side", choices=("front", "back"), action="append")
    parser.add_argument("--runs", type=int, default=10)
    parser.add_argument("--seed", type=int, action="append", help="trial seed (repeatable)")
    parser.add_argument("--budget", type=int, help="default: T1 100, NAO 200")
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    for robot in args.robot or ("t1", "nao"):
        for side in args.side or ("front", "back"):
            rec, end_s = record(robot, side, args.out)
            print(f"recorded {robot} getup_{side}: {rec} (window 0-{end_s or 'end'} s)")
            copies = learn(robot, side, rec, end_s, args.out, args.budget, args.workers)
            worlds = ("league", "mujoco") if robot == "t1" else ("mujoco",)
            for world in worlds:
                for seed in args.seed or (1000,):
                    trial(robot, side, copies, world, seed, args, args.out)


if __name__ == "__main__":
    main()
