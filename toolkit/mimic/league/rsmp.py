"""RSMP, the monitor protocol: frames of the scene graph, full or as a diff.

A frame is ``((RSMP 1 0)((gt 1 0)TIME)((sg 1 0)full|diff NODE)((gs 1 0)...)((ge 1 0)...))``.
The scene graph follows the MuJoCo body tree: a body is ``(nd TRF(SLT m0..m15) GEOMS...
CHILD_BODIES...)`` with its transform relative to its parent body (a column-major 4x4 matrix,
rounded to 4 decimals); a robot sits under ``(nd DSC(agent TEAM UNUM) BODY)``, the ball under
``(nd DSC(ball) BODY)``. A full frame carries everything; a diff frame has the same nodes in
the same order, bare (``(nd ...)``), with ``TRF`` only on nodes whose transform moved by more
than 0.005 since it was last sent. ``SceneState`` keeps the scene as of the last frame: a full
frame replaces it, a diff frame updates it in place, node by node.

The same frames are the lines of a game log (``rcssservermj --logfile``).

Frames are untrusted input: ``SceneState.apply`` never raises for what a frame holds. A frame
that does not parse, or holds a bad number (an SLT that is not 16 finite numbers, a time or a
shirt number that is not one) or a list where a name belongs, is skipped whole and counted
(``skipped``); the scene stays as it was.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from mimic.league.protocol import parse_sexp
from mimic.league.untrusted import text_of

__all__ = ["SceneNode", "SceneState", "PlayerNode", "is_rsmp", "RSMP_PREFIX", "slt_matrix"]

#: How every RSMP frame starts.
RSMP_PREFIX = b"((RSMP"


def is_rsmp(head: bytes) -> bool:
    """Whether a message or file starting with ``head`` is RSMP (leading blanks ignored)."""
    return head.lstrip().startswith(RSMP_PREFIX)


#: The latest server time a frame may carry [s] (a year; beyond it the stamp is garbage).
_MAX_TIME_S = 3.2e7
#: The highest shirt number a frame may carry.
_MAX_PLAYER = 999
#: Errors a malformed frame raises while read; it is then skipped.
_BAD_FRAME = (
    ValueError,
    TypeError,
    AttributeError,
    IndexError,
    KeyError,
    OverflowError,
    RecursionError,  # nodes nested deeper than Python's stack
)


def _slt(item: list) -> np.ndarray:
    """The 16 numbers of an ``(SLT ...)`` item; ValueError unless exactly 16 finite ones."""
    if len(item) != 17 or not all(isinstance(v, bytes) for v in item[1:]):
        raise ValueError("an SLT is 16 numbers")
    slt = np.array([float(v) for v in item[1:]])
    if not np.isfinite(slt).all():
        raise ValueError("an SLT number is not finite")
    return slt


def _kind(node: list) -> str:
    return text_of(node[1]) if len(node) > 1 and isinstance(node[1], bytes) else ""


def slt_matrix(slt: np.ndarray) -> np.ndarray:
    """(4, 4) homogeneous transform from the 16 SLT numbers (column-major)."""
    return slt.reshape(4, 4).T


class SceneNode:
    """One node of the scene graph.

    Attributes:
        kind: ``TRF`` (a transform: a body or a geom offset), ``DSC`` (a description: agent,
            ball), ``SMN`` (a shape) or ``""``.
        slt: (16,) the transform's SLT numbers (TRF nodes), else None.
        desc: the DSC descriptions or SMN attributes, as parsed lists.
        children: child nodes in frame order.
    """

    __slots__ = ("kind", "slt", "desc", "children")

    def __init__(
        self, kind: str, slt: np.ndarray | None, desc: list, children: list[SceneNode]
    ) -> None:
        self.kind, self.slt, self.desc, self.children = kind, slt, desc, children

    @classmethod
    def from_sexp(cls, node: list) -> SceneNode:
        """A node and everything below it. Raises ValueError (or another of a malformed
        frame's errors) for a bad SLT or a list where a name belongs."""
        kind = _kind(node)
        slt, desc, children = None, [], []
        for item in node[2 if kind else 1 :]:
            if not isinstance(item, list) or not item:
                continue
            if item[0] == b"nd":
                children.append(cls.from_sexp(item))
            elif item[0] == b"SLT":
                slt = _slt(item)
            else:
                desc.append(item)
        return cls(kind, slt, desc, children)

    def update(self, diff: list) -> bool:
        """Apply a diff node (same shape as this node); False if the shapes differ (nothing
        is changed then). Raises ValueError for a bad SLT (nothing is changed either)."""
        updates: list[tuple[SceneNode, np.ndarray]] = []
        if not self._diff(diff, updates):
            return False
        for node, slt in updates:
            node.slt = slt
        return True

    def _diff(self, diff: list, updates: list[tuple[SceneNode, np.ndarray]]) -> bool:
        """The transforms a diff node sets, into ``updates``; False if the shapes differ."""
        kind = _kind(diff)
        k = 0
        for item in diff[2 if kind else 1 :]:
            if not isinstance(item, list) or not item:
                continue
            if item[0] == b"nd":
                if k >= len(self.children) or not self.children[k]._diff(item, updates):
                    return False
                k += 1
            elif item[0] == b"SLT":
                updates.append((self, _slt(item)))
        return k == len(self.children)

    def find_load(self) -> str | None:
        """The first ``(load PATH)`` of a shape below this node (a full frame's), or None."""
        for item in self.desc:
            if item and item[0] == b"load" and len(item) > 1 and isinstance(item[1], bytes):
                return text_of(item[1])
        for child in self.children:
            found = child.find_load()
            if found is not None:
                return found
        return None


@dataclass(frozen=True)
class PlayerNode:
    """A robot on the field: its team, number, robot model (``T1``) and where it sits in the
    scene graph (child indices from the root to its DSC node)."""

    team: str
    player: int
    model: str
    path: tuple[int, ...]


@dataclass
class SceneState:
    """The scene as of the last frame applied (see the module docstring).

    Attributes:
        root: the scene graph (None before the first full frame).
        time_s: server time of the last frame [s].
        frames: frames applied; skipped: diff frames that could not be applied (before the
            first full frame, or not matching it) and frames that did not parse.
        players: the robots of the last full frame.
        ball_path: child indices of the ball's DSC node.
        game: the last ``gs`` section's fields (play mode, teams, score) as text.
    """

    root: SceneNode | None = None
    time_s: float = float("nan")
    frames: int = 0
    skipped: int = 0
    players: tuple[PlayerNode, ...] = ()
    ball_path: tuple[int, ...] | None = None
    game: dict[str, str] = field(default_factory=dict)

    def apply(self, message: bytes) -> bool:
        """Apply one frame; True if the scene is now valid (a full frame seen, diffs fit).

        Never raises for what the frame holds: a malformed frame is skipped (``skipped``)
        and leaves the scene as it was."""
        try:
            return self._apply(message)
        except _BAD_FRAME:
            self.skipped += 1
            return False

    def _apply(self, message: bytes) -> bool:
        try:
            top = parse_sexp(message)
        except ValueError:
            self.skipped += 1
            return False
        if (
            not top
            or not isinstance(top[0], list)
            or not top[0]
            or top[0][0] != [b"RSMP", b"1", b"0"]
        ):
            self.skipped += 1
            return False
        # Read every section first; change the scene only once the whole frame has been read.
        time_s, graph, game = None, None, None
        for section in top[0][1:]:
            if not isinstance(section, list) or not section or not isinstance(section[0], list):
                continue
            name = section[0][0] if section[0] else b""
            if name == b"gt" and len(section) > 1:
                time_s = float(section[1])
                if not 0.0 <= time_s < _MAX_TIME_S:
                    raise ValueError(f"server time {time_s!r} out of range")
            elif name == b"sg" and len(section) > 2:
                graph = (section[1], section[2])
            elif name == b"gs":
                game = {
                    text_of(item[0]): " ".join(text_of(v) for v in item[1:])
                    for item in section[1:]
                    if isinstance(item, list) and item
                }
        ok = True
        if graph is not None:
            ok = self._apply_graph(*graph)
        if time_s is not None:
            self.time_s = time_s
        if game is not None:
            self.game = game
        if ok:
            self.frames += 1
        else:
            self.skipped += 1
        return ok

    def _apply_graph(self, mode: bytes, node: list) -> bool:
        if not isinstance(node, list):
            raise ValueError("a scene graph is a node")
        if mode == b"full":
            root = SceneNode.from_sexp(node)
            players, ball = _index(root)
            self.root, self.players, self.ball_path = root, players, ball
            return True
        if self.root is None:
            return False
        if not self.root.update(node):
            self.root = None  # out of step: wait for the next full frame
            self.players = ()
            return False
        return True

    @property
    def valid(self) -> bool:
        return self.root is not None

    def node(self, path: tuple[int, ...]) -> SceneNode:
        """The node at ``path`` (child indices from the root)."""
        node = self.root
        for k in path:
            node = node.children[k]
        return node

    def player(self, team: str, player: int) -> PlayerNode | None:
        """The robot ``team`` #``player``, or None if it is not on the field."""
        return next((p for p in self.players if p.team == team and p.player == player), None)

    def ball_pos_m(self) -> np.ndarray | None:
        """(3,) ball centre in the field frame [m], or None without a ball."""
        if self.ball_path is None or self.root is None:
            return None
        ball = self.node(self.ball_path)
        if not ball.children or ball.children[0].slt is None:
            return None
        return ball.children[0].slt[12:15].copy()


def _index(root: SceneNode) -> tuple[tuple[PlayerNode, ...], tuple[int, ...] | None]:
    """The robots (sorted by team and number) and the ball's path in a full frame's graph.

    Raises:
        ValueError: a shirt number that is not a whole number 0..999, or a name that is a
            list.
    """
    players, ball = [], None
    for path, node in _walk(root, ()):
        if node.kind != "DSC":
            continue
        for item in node.desc:
            if item and item[0] == b"agent" and len(item) >= 3 and node.children:
                load = node.children[0].find_load() or ""
                model = load.split("/")[1] if load.startswith("models/") else ""
                if not isinstance(item[2], bytes) or not item[2].isdigit():
                    raise ValueError(f"shirt number {item[2]!r:.20} is not a whole number")
                number = int(item[2])
                if number > _MAX_PLAYER:
                    raise ValueError(f"shirt number {number} out of range")
                players.append(PlayerNode(text_of(item[1]), number, model, path))
            elif item == [b"ball"]:
                ball = path
    return tuple(sorted(players, key=lambda p: (p.team, p.player))), ball


def _walk(node: SceneNode, path: tuple[int, ...]):
    """(path, node) of every node below ``node``, depth first; agents are not entered."""
    yield path, node
    if node.kind == "DSC":
        return
    for k, child in enumerate(node.children):
        yield from _walk(child, (*path, k))
