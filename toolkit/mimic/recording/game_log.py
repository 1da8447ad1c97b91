"""Game logs: ``rcssservermj --logfile`` writes every monitor frame as one line of RSMP.

``import_game_log`` turns one player of a log into a recording (the same decoding as the live
monitor, ``recording.blackbox``); ``import_game_log_all`` writes one recording per player. A log
cut off or still being written yields every complete frame (a partial last line is skipped).

A log is untrusted input: a malformed line is skipped and counted, a line longer than
``MAX_MESSAGE_BYTES`` too, and a team name becomes a file name only through ``safe_stem`` (never
a path outside the output folder).
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

from mimic.files import check_outputs
from mimic.league.decode import PlayerDecoder
from mimic.league.errors import GameLogError, LeagueError, PlayerNotFoundError
from mimic.league.rsmp import PlayerNode, SceneState, is_rsmp
from mimic.league.untrusted import MAX_MESSAGE_BYTES, safe_stem
from mimic.recording.blackbox import BlackBoxResult, describe_players, robot_of, who
from mimic.recording.player_writer import PlayerWriter

__all__ = [
    "is_game_log",
    "read_frames",
    "import_game_log",
    "import_game_log_all",
    "log_players",
    "player_file_names",
]

_HEAD_BYTES = 64


def is_game_log(path: str | Path) -> bool:
    """Whether ``path`` starts like an RCSSServerMJ game log (an RSMP frame)."""
    try:
        with open(path, "rb") as f:
            return is_rsmp(f.read(_HEAD_BYTES))
    except OSError:
        return False


def read_frames(path: str | Path) -> Iterator[bytes]:
    """The frames of a game log, one per line, in order.

    Raises:
        GameLogError: the file is missing or is not a game log.
    """
    path = Path(path)
    if not path.is_file():
        raise GameLogError(f"{path}: no such file")
    if not is_game_log(path):
        raise GameLogError(
            f"{path} is not an RCSSServerMJ game log (it does not start with "
            "an RSMP frame, '((RSMP 1 0)...'); write one with "
            "'rcssservermj --logfile FILE'"
        )
    with open(path, "rb") as f:
        while line := f.readline(MAX_MESSAGE_BYTES + 1):
            if len(line) > MAX_MESSAGE_BYTES and not line.endswith(b"\n"):
                while (rest := f.readline(1 << 20)) and not rest.endswith(b"\n"):
                    pass  # skip the rest of an overlong line
                yield b""  # not a frame: counted as skipped
            elif line.strip():
                yield line


def _scenes(path: str | Path) -> Iterator[SceneState]:
    state = SceneState()
    for frame in read_frames(path):
        if state.apply(frame):
            yield state


def log_players(path: str | Path) -> tuple[PlayerNode, ...]:
    """Every robot that shows in a log's full frames (first sighting of each)."""
    seen: dict[tuple[str, int], PlayerNode] = {}
    last = None
    for state in _scenes(path):
        if state.players is not last:  # changes only with full frames
            last = state.players
            for p in state.players:
                seen.setdefault((p.team, p.player), p)
    return tuple(sorted(seen.values(), key=lambda p: (p.team, p.player)))


def import_game_log(
    log_path: str | Path, out_path: str | Path, team: str, player: int, *, robot: str | None = None
) -> BlackBoxResult:
    """Write ``team`` #``player`` of a game log as a recording.

    Raises:
        GameLogError: not a game log. PlayerNotFoundError: the player is not in it (the
            message names those who are); no file is written then.
    """
    results = _import(log_path, {(team, player): Path(out_path)}, robot, every=False)
    if not results:
        raise PlayerNotFoundError(
            f"{who(team, player)} is not in {log_path}; players in it: "
            f"{describe_players(log_players(log_path))}"
        )
    return results[0]


def player_file_names(players: tuple[PlayerNode, ...]) -> dict[tuple[str, int], str]:
    """``TEAM_N.mcap`` for each player, the team name made safe (``safe_stem``); two names
    that become the same get ``-2``, ``-3``, ... so no file is written twice."""
    names: dict[tuple[str, int], str] = {}
    taken: set[str] = set()
    for p in players:
        base = f"{safe_stem(p.team)}_{p.player}"
        name, k = f"{base}.mcap", 1
        while name.lower() in taken:  # case-insensitive file systems too
            k += 1
            name = f"{base}-{k}.mcap"
        taken.add(name.lower())
        names[(p.team, p.player)] = name
    return names


def import_game_log_all(
    log_path: str | Path, out_dir: str | Path, *, robot: str | None = None, force: bool = False
) -> list[BlackBoxResult]:
    """One recording per player of a game log: ``OUT_DIR/TEAM_N.mcap`` (``player_file_names``:
    always inside ``out_dir``). Every output is checked before any is written.

    Raises:
        GameLogError: not a game log, or no players in it.
        OutputError: an output exists (and not ``force``) or cannot be written.
    """
    out_dir = Path(out_dir)
    if out_dir.exists() and not out_dir.is_dir():
        raise GameLogError(f"--all writes one file per player into a folder; {out_dir} is a file")
    players = log_players(log_path)
    if not players:
        raise GameLogError(f"{log_path} holds no players")
    outputs = {key: out_dir / name for key, name in player_file_names(players).items()}
    check_outputs(outputs.values(), force=force, inputs=[log_path])
    results = _import(log_path, outputs, robot, every=True)
    if not results:
        raise GameLogError(f"{log_path} holds no players mimic can decode")
    return results


def _import(
    log_path, outputs: dict[tuple[str, int], Path], robot: str | None, *, every: bool
) -> list[BlackBoxResult]:
    """One pass over the log; ``outputs``: the players wanted and their files (``every``:
    all the log's players, those of robots mimic does not know left out)."""
    decoders: dict[tuple[str, int], PlayerDecoder] = {}
    writers: dict[tuple[str, int], PlayerWriter] = {}
    skipped: dict[tuple[str, int], int] = {}
    ignored: set[tuple[str, int]] = set()
    state = SceneState()
    try:
        for frame in read_frames(log_path):
            if not state.apply(frame):
                for key in decoders:
                    skipped[key] += 1
                continue
            for node in state.players:
                key = (node.team, node.player)
                if key not in decoders:
                    if key not in outputs or key in ignored:
                        continue
                    try:
                        description = robot_of(node, robot, who(*key))
                    except LeagueError:
                        if not every:
                            raise
                        ignored.add(key)  # --all: a robot mimic does not know is left out
                        continue
                    decoders[key] = PlayerDecoder(description)
                    skipped[key] = 0
                sample = decoders[key].decode(state.node(node.path), state.time_s)
                if sample is None:
                    skipped[key] += 1
                    continue
                if key not in writers:
                    writers[key] = PlayerWriter(
                        outputs[key],
                        decoders[key].robot,
                        *key,
                        "game_log",
                        str(log_path),
                        sample.time_s,
                    )
                writers[key].write(sample, state.ball_pos_m())
    except BaseException:
        # A failed import leaves every target as it was: the log can be imported again.
        for writer in writers.values():
            writer.abandon()
        raise
    results = []
    for (team, number), writer in writers.items():
        writer.finish(interrupted=False, reason="end of log")
        results.append(
            BlackBoxResult(
                writer.path,
                writer.robot.name,
                team,
                number,
                writer.samples,
                writer.duration_s,
                False,
                "end of log",
                skipped[(team, number)],
            )
        )
    return results
