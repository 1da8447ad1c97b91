"""What is being tried: a picklable description of an agent, built inside worker processes."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from mimic.agents.base import Agent
from mimic.errors import MimicError

__all__ = ["AgentSpec", "parse_agent_spec", "BALANCE_SUFFIX"]

#: Appended to a model path (``kick.mimic+balance``): try that model inside the balance layer.
BALANCE_SUFFIX = "+balance"


@dataclass(frozen=True)
class AgentSpec:
    """An agent to put on trial.

    Attributes:
        kind: ``motion`` (our keyframe motion by name or .txt path), ``model`` (a learned
            ``.mimic`` network), or ``agent`` (a registry name such as ``other-team-walk``).
        ref: the motion name, model path or registry name.
        balance: wrap a learned motion in the closed-loop balance layer.
        speed_rate: phase-rate multiplier for cyclic learned motions.
    """

    kind: str
    ref: str
    balance: bool = False
    speed_rate: float = 1.0

    @property
    def label(self) -> str:
        base = Path(self.ref).stem if self.kind == "model" else self.ref
        suffix = " (learned)" if self.kind == "model" else ""
        return base + suffix + (" + balance" if self.balance else "")

    def build(self) -> Agent:
        """A fresh agent (call inside the process that runs it)."""
        if self.kind == "motion":
            from mimic.agents.keyframe_player import KeyframePlayer
            from mimic.motion.files import load_motion
            return KeyframePlayer(load_motion(self.ref))
        if self.kind == "model":
            from mimic.agents.neural_player import NeuralPlayer
            agent = NeuralPlayer.from_file(self.ref)
            if self.speed_rate != 1.0:
                agent.speed_rate = self.speed_rate
            if self.balance:
                from mimic.agents.balance import BalancedAgent
                agent = BalancedAgent(agent)
            return agent
        from mimic.agents.registry import make_agent
        return make_agent(self.ref)

    def ball_offset_m(self) -> tuple[float, float]:
        """Where the kick wants the ball, relative to the torso (x forward, y left) [m]."""
        offset = None
        if self.kind == "motion":
            from mimic.motion.files import load_motion
            offset = getattr(load_motion(self.ref), "ball_offset_m", None)
        elif self.kind == "model":
            from mimic.learn.model_file import load_model
            offset = load_model(self.ref).metadata.get("ball_offset_m")
        else:
            offset = getattr(self.build(), "ball_offset_m", None)
        if offset is None:
            raise MimicError(f"{self.label}: no ball offset known for this kick; a kick motion "
                             "file needs a 'ball_offset X Y' line")
        return (float(offset[0]), float(offset[1]))


def parse_agent_spec(text: str, *, balance: bool = False, speed_rate: float = 1.0) -> AgentSpec:
    """``kick_right`` / ``path.txt`` -> motion, ``*.mimic`` -> model, ``other-team-*`` /
    other registry names -> agent. ``model.mimic+balance`` wraps that model in the balance
    layer, so one table can hold a model with and without it."""
    if text.endswith(BALANCE_SUFFIX):
        text, balance = text[:-len(BALANCE_SUFFIX)], True
        if not text.endswith(".mimic"):
            raise MimicError(f"{text + BALANCE_SUFFIX!r}: the balance layer wraps learned "
                             "motions only; give a .mimic model, e.g. kick.mimic+balance")
    if text.endswith(".mimic"):
        if not Path(text).is_file():
            raise MimicError(f"model file {text!r} not found; train one with 'mimic train'")
        return AgentSpec("model", text, balance, speed_rate)
    from mimic.motion.files import list_motions
    if text in list_motions() or text.endswith(".txt"):
        return AgentSpec("motion", text, balance, speed_rate)
    from mimic.agents.registry import agent_names
    if text in agent_names():
        return AgentSpec("agent", text, balance, speed_rate)
    raise MimicError(f"unknown motion, model or agent {text!r}; motions: "
                     f"{', '.join(list_motions())}; agents: {', '.join(agent_names())}; "
                     "or a .mimic model file")
