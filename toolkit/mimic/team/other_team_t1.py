"""The T1 other team (``agents.other_team_t1``) as a league team process: speaks only the
protocol.

Examples::

    python -m mimic.team.other_team_t1 --server localhost:60000 --team Others --player 2
    python -m mimic.team.other_team_t1 --server localhost:60000 --walk-s 8   # then stop
    python -m mimic.team.other_team_t1 --kick --server localhost:60000

Without ``--server`` it hosts a server of its own (as ``mimic play`` does). The walk stops on
command: after ``--walk-s`` seconds it ramps its steps down and stands (then the process ends);
without it the walk goes on for ``--seconds`` (default 60 s) or until Ctrl-C.
"""

from __future__ import annotations

import argparse
import sys

from mimic.agents.base import Agent, JointCommand
from mimic.agents.other_team_t1 import make_kick, make_walk
from mimic.errors import MimicError
from mimic.team.play import play
from mimic.world.base import Observation

__all__ = ["main", "StopAfter"]


class StopAfter(Agent):
    """Plays a walk and tells it to stop after ``walk_s`` seconds; done once it stands."""

    def __init__(self, walk, walk_s: float) -> None:
        super().__init__()
        self.walk, self.walk_s = walk, walk_s
        self.name, self.team, self.robot = walk.name, walk.team, walk.robot
        self.robot_only, self.period_s = walk.robot_only, walk.period_s
        self._t0_s: float | None = None

    def reset(self, obs: Observation) -> None:
        self.walk.reset(obs)
        self._t0_s, self.done = obs.time_s, False

    def act(self, obs: Observation) -> JointCommand:
        if obs.time_s - self._t0_s >= self.walk_s:
            self.walk.stop()
        command = self.walk.act(obs)
        self.done = self.walk.done
        return command


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="python -m mimic.team.other_team_t1", description=__doc__.split("\n\n")[0]
    )
    parser.add_argument("--server", help="the server's agent port HOST:PORT (default: host one)")
    parser.add_argument("--team", default="Others", help="team name (default: Others)")
    parser.add_argument("--player", type=int, default=1, help="shirt number 1-99 (default: 1)")
    parser.add_argument("--kick", action="store_true", help="kick instead of walking")
    parser.add_argument("--speed", type=float, help="walking speed [m/s] (default: the team's)")
    parser.add_argument("--walk-s", type=float, help="walk this long [s], then stop and stand")
    parser.add_argument(
        "--seconds", type=float, help="play this long [s] (default: until done, at most 60 s)"
    )
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the team process; returns the exit code (0 done or time up, 130 Ctrl-C)."""
    args = _parser().parse_args(argv)
    try:
        if args.kick:
            agent: Agent = make_kick()
        else:
            agent = make_walk(args.speed)
            if args.walk_s is not None:
                agent = StopAfter(agent, args.walk_s)
        result = play(
            agent,
            robot="t1",
            agent_address=args.server,
            team=args.team,
            player=args.player,
            seconds=args.seconds,
        )
    except MimicError as err:
        print(f"error: {err}", file=sys.stderr)
        return err.exit_code
    print(f"{args.team} #{args.player}: {result.end} after {result.cycles} cycles")
    if result.end == "interrupted":
        return 130
    return 1 if result.interrupted else 0


if __name__ == "__main__":
    sys.exit(main())
