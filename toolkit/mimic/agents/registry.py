"""Agents by name: the one registry every command reads (record, play, trial, improve).

A spec is text:

* a shipped motion of the robot (``kick_right``) or a motion file (``my_kick.txt``): our
  keyframe player;
* a behaviour (``walk``, ``other-team-walk``, ``other-team-kick``);
* a learned model (``kick.mimic``), optionally inside the balance layer
  (``kick.mimic+balance``);
* a parameter file (``walk.json``): an engine's parameters (``agents.params_file``), e.g.
  the other team's walk as ``mimic improve`` tuned it.

``agent_spec`` turns the text into a picklable ``AgentSpec`` (built again inside worker
processes); ``make_agent`` builds the agent at once. Behaviour modules are imported only when
their agent is asked for, so listing names is cheap.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from mimic.agents.balance import BalancedAgent
from mimic.agents.base import Agent
from mimic.agents.keyframe_player import KeyframePlayer
from mimic.agents.neural_player import NeuralPlayer
from mimic.agents.params_file import build_engine, load_params
from mimic.errors import MimicError
from mimic.model.model_file import load_model
from mimic.motion.files import list_motions, load_motion
from mimic.robot.registry import DEFAULT_ROBOT, get_robot

__all__ = [
    "AgentSpec",
    "agent_spec",
    "make_agent",
    "agent_names",
    "BEHAVIOURS",
    "ROBOT_BEHAVIOURS",
    "BALANCE_SUFFIX",
    "kick_ball_offset_m",
]

#: Behaviour name -> "module:factory" (a callable with no arguments returning an Agent).
BEHAVIOURS: dict[str, str] = {
    "walk": "mimic.agents.walk:make_walk_agent",
    "other-team-walk": "mimic.agents.other_team:make_walk",
    "other-team-kick": "mimic.agents.other_team:make_kick",
}
#: Robot -> behaviours that robot plays with a controller of its own (the T1's other team).
ROBOT_BEHAVIOURS: dict[str, dict[str, str]] = {
    "t1": {
        "other-team-walk": "mimic.agents.other_team_t1:make_walk",
        "other-team-kick": "mimic.agents.other_team_t1:make_kick",
        # A walk like a learned policy's: a velocity command toward a noisy target, a step
        # time that adapts every step (no two steps alike).
        "other-team-policy-walk": "mimic.agents.other_team_t1:make_policy_walk",
        # That walk with a learned policy's action jitter: its joints move as fast as a real
        # team's in a black-box recording.
        "other-team-jittery-walk": "mimic.agents.other_team_t1:make_jittery_walk",
    },
}
#: Behaviours whose factory takes a forward speed command [m/s] (``--vx``).
_COMMANDED = ("other-team-walk", "other-team-policy-walk", "other-team-jittery-walk")
#: Appended to a model path (``kick.mimic+balance``): play that model inside the balance layer.
BALANCE_SUFFIX = "+balance"


def _load(target: str, what: str) -> Callable:
    module_name, attr = target.split(":")
    try:
        module = importlib.import_module(module_name)
    except ModuleNotFoundError as err:
        if err.name and module_name.startswith(err.name):
            raise MimicError(
                f"{what} is not available: module {module_name} is missing from this installation"
            ) from None
        raise
    return getattr(module, attr)


@dataclass(frozen=True)
class AgentSpec:
    """An agent to build, as plain data (picklable for worker processes).

    Attributes:
        kind: ``motion`` (a keyframe motion by name or .txt path), ``model`` (a learned
            ``.mimic`` network), ``behaviour`` (``BEHAVIOURS``) or ``params`` (a .json
            parameter file of an engine, ``agents.params_file``).
        ref: the motion name, model path, behaviour name or parameter file path.
        robot: the robot the agent drives.
        balance: wrap a learned motion in the closed-loop balance layer.
        speed_rate: phase-rate multiplier for cyclic learned motions.
        speed_m_s: a commanded forward speed [m/s] for a learned walk (its phase rate follows
            it), or for a behaviour that takes one (the other team's walks); None: its own.
    """

    kind: str
    ref: str
    robot: str = DEFAULT_ROBOT
    balance: bool = False
    speed_rate: float = 1.0
    speed_m_s: float | None = None

    @property
    def label(self) -> str:
        """How tables name it: ``kick_right``, ``kick (learned) + balance``."""
        base = Path(self.ref).stem if self.kind in ("model", "params") else self.ref
        suffix = {"model": " (learned)", "params": " (params)"}.get(self.kind, "")
        return base + suffix + (" + balance" if self.balance else "")

    def build(self) -> Agent:
        """A fresh agent (call it inside the process that runs it)."""
        if self.speed_m_s is not None and self.kind in ("motion", "params"):
            raise MimicError(f"{self.label} takes no speed command (--vx); a learned walk does")
        if self.kind == "motion":
            return KeyframePlayer(load_motion(self.ref, self.robot))
        if self.kind == "model":
            agent = NeuralPlayer.from_file(self.ref, speed_m_s=self.speed_m_s)
            if self.speed_m_s is not None and not agent.model.cyclic:
                raise MimicError(
                    f"{self.label}: --vx commands a walk; this model is a one-shot motion"
                )
            if self.speed_rate != 1.0:
                agent.speed_rate = self.speed_rate
            if self.balance:
                agent = BalancedAgent(agent)
            return agent
        if self.kind == "params":
            return build_engine(*load_params(self.ref))
        target = ROBOT_BEHAVIOURS.get(self.robot, {}).get(self.ref) or BEHAVIOURS.get(self.ref)
        if self.speed_m_s is not None and self.ref not in _COMMANDED:
            raise MimicError(
                f"{self.ref} takes no speed command (--vx): {', '.join(_COMMANDED)} do"
            )
        if target is None:
            robots = [r for r, names in ROBOT_BEHAVIOURS.items() if self.ref in names]
            raise MimicError(
                f"{self.ref} is a behaviour of the {', '.join(r.upper() for r in robots)} only; "
                f"the robot here is the {self.robot.upper()} (pick it with --robot)"
            )
        factory = _load(target, f"agent {self.ref!r}")
        return factory() if self.speed_m_s is None else factory(self.speed_m_s)

    def check(self, robot: str | None = None) -> None:
        """Everything that can be checked before a run: the model file reads, and the
        agent can drive ``robot`` (default: the spec's). Raises ``MimicError``, one line."""

        self.build().check_robot(get_robot(robot or self.robot))

    def ball_offset_m(self) -> tuple[float, float]:
        """Where the kick wants the ball, relative to the torso (x forward, y left) [m]."""
        offset = kick_ball_offset_m(self.build())
        if offset is None:
            raise MimicError(
                f"{self.label}: no ball offset known for this kick; a kick motion "
                "file needs a 'ball_offset X Y' line"
            )
        return (float(offset[0]), float(offset[1]))


def agent_names(robot: str = DEFAULT_ROBOT) -> list[str]:
    """Every name ``agent_spec`` accepts besides files: shipped motions, then behaviours."""

    motions = list_motions(robot)
    behaviours = [*BEHAVIOURS, *ROBOT_BEHAVIOURS.get(robot, {})]
    return motions + [n for n in dict.fromkeys(behaviours) if n not in motions]


def agent_spec(
    text: str,
    *,
    robot: str = DEFAULT_ROBOT,
    balance: bool = False,
    speed_rate: float = 1.0,
    speed_m_s: float | None = None,
) -> AgentSpec:
    """Read an agent spec (see the module docstring).

    Raises:
        MimicError: unknown name, missing model file, ``+balance`` on something that is not
            a model.
    """
    if text.endswith(BALANCE_SUFFIX):
        text, balance = text[: -len(BALANCE_SUFFIX)], True
        if not text.endswith(".mimic"):
            raise MimicError(
                f"{text + BALANCE_SUFFIX!r}: the balance layer wraps learned "
                "motions only; give a .mimic model, e.g. kick.mimic+balance"
            )
    if text.endswith(".mimic"):
        path = Path(text)
        if path.is_dir():
            raise MimicError(f"{text!r} is a directory, not a model file; give a .mimic file")
        if not path.is_file():
            raise MimicError(f"model file {text!r} not found; train one with 'mimic train'")

        return AgentSpec("model", text, load_model(text).robot, balance, speed_rate, speed_m_s)
    if text.endswith(".json"):
        load_params(text)  # one clear line now for a missing or bad file
        return AgentSpec("params", text, robot, balance, speed_rate, speed_m_s)

    if text in list_motions(robot) or text.endswith(".txt"):
        if text.endswith(".txt") and not Path(text).is_file():
            raise MimicError(f"motion file {text!r} not found")
        return AgentSpec("motion", text, robot, balance, speed_rate, speed_m_s)
    if text in BEHAVIOURS or any(text in names for names in ROBOT_BEHAVIOURS.values()):
        return AgentSpec("behaviour", text, robot, balance, speed_rate, speed_m_s)
    raise MimicError(
        f"unknown agent {text!r}; motions: {', '.join(list_motions(robot))}; "
        f"behaviours: {', '.join(BEHAVIOURS)}; or a .mimic model file "
        "(optionally +balance) or a .json parameter file"
    )


def make_agent(text: str, *, robot: str = DEFAULT_ROBOT) -> Agent:
    """A fresh agent from its spec text (see ``agent_spec``) that can drive ``robot``.

    Raises:
        MimicError: bad spec, or an agent made for another robot.
    """

    agent = agent_spec(text, robot=robot).build()
    agent.check_robot(get_robot(robot))
    return agent


def kick_ball_offset_m(agent) -> tuple[float, float] | None:
    """Where ``agent``'s kick wants the ball (x forward, y left of the torso [m]), or None
    (not a kick): a model's, a balance layer's or a keyframe movement's ``ball_offset``."""
    offset = getattr(agent, "ball_offset_m", None)
    if offset is None:
        offset = getattr(getattr(agent, "movement", None), "ball_offset_m", None)
    return None if offset is None else (float(offset[0]), float(offset[1]))
