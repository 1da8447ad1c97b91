"""What ``mimic improve`` can change, as a search space and a way back to an agent and a file.

* a keyframe motion (a shipped name or a ``.txt`` file): the angles of the chosen joints in
  every keyframe [rad], every step time [s] and the speed rate; written as a motion file;
* a learned model (``.mimic``, optionally ``+balance``): a time warp and per-joint offsets and
  gains (``improve.correction``), and inside the balance layer its tilt gains too (the model
  file then carries them); written as a model file;
* an engine's parameters (``other-team-walk`` or a ``.json`` parameter file): the floats of
  its parameter dataclass; written as a parameter file (``agents.params_file``).

``Target.spec(z)`` gives a candidate as a picklable spec with ``robot``, ``label``, ``build()``
and ``ball_offset_m()``, the interface the trial episodes use (``AgentSpec``'s), so candidates
run in the trial episodes unchanged, in worker processes or on Ray.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from mimic.agents.balance import BalancedAgent, with_balance_gains
from mimic.agents.base import Agent
from mimic.agents.keyframe_player import KeyframePlayer
from mimic.agents.neural_player import NeuralPlayer
from mimic.agents.params_file import (
    PARAM_ENGINES,
    build_engine,
    default_params,
    load_params,
    save_params,
)
from mimic.agents.registry import agent_spec
from mimic.errors import MimicError
from mimic.files import atomic_output
from mimic.improve.correction import (
    WINDOW_RAMP_S,
    WindowedModel,
    corrected_model,
    windowed_model,
)
from mimic.improve.space import Space
from mimic.model.model_file import load_model, save_model
from mimic.motion.files import format_motion, load_motion
from mimic.motion.keyframe import KeyframeStep, Movement
from mimic.robot.registry import get_robot

__all__ = [
    "Target",
    "MotionTarget",
    "ModelTarget",
    "ParamsTarget",
    "load_target",
    "resolve_joints",
    "WALK_SEARCH",
]


# --- candidate specs (what the trial episodes build agents from) -------------------------------


@dataclass(frozen=True, eq=False)
class MovementSpec:
    """A keyframe motion held in memory."""

    movement: Any
    label: str

    @property
    def robot(self) -> str:
        return self.movement.robot

    def build(self) -> Agent:

        return KeyframePlayer(self.movement)

    def ball_offset_m(self) -> tuple[float, float]:
        if self.movement.ball_offset_m is None:
            raise MimicError(
                f"{self.label}: the motion has no 'ball_offset X Y' line; a kick "
                "objective needs one"
            )
        return tuple(float(v) for v in self.movement.ball_offset_m)


@dataclass(frozen=True, eq=False)
class ModelSpec:
    """A learned model held in memory, optionally inside the balance layer."""

    model: Any
    label: str
    balance: bool = False

    @property
    def robot(self) -> str:
        return self.model.robot

    def build(self) -> Agent:

        agent = NeuralPlayer(self.model)
        if self.balance:
            agent = BalancedAgent(agent)
        return agent

    def ball_offset_m(self) -> tuple[float, float]:
        offset = self.model.metadata.get("ball_offset_m")
        if offset is None:
            raise MimicError(
                f"{self.label}: the model knows no ball offset (its recording "
                "was not of a kick); a kick objective needs one"
            )
        return (float(offset[0]), float(offset[1]))


@dataclass(frozen=True, eq=False)
class ParamsSpec:
    """An engine playing parameters held in memory."""

    agent: str
    params: Any
    label: str
    robot: str = "nao"

    def build(self) -> Agent:

        return build_engine(self.agent, self.params)

    def ball_offset_m(self) -> tuple[float, float]:
        offset = getattr(self.build(), "ball_offset_m", None)
        if offset is None:
            raise MimicError(f"{self.label}: not a kick (no ball offset)")
        return (float(offset[0]), float(offset[1]))


# --- targets -----------------------------------------------------------------------------------


def resolve_joints(robot: str, joints: str) -> list[int]:
    """Joint indices for ``legs`` (hip, knee and ankle joints), ``all`` or a comma-separated
    list of names.

    Raises:
        MimicError: an unknown joint name (the message lists the robot's joints).
    """

    desc = get_robot(robot)
    if joints == "all":
        return list(range(desc.num_joints))
    if joints == "legs":
        return [
            i
            for i, n in enumerate(desc.joint_names)
            if any(part in n.lower() for part in ("hip", "knee", "ankle"))
        ]
    indices = []
    for name in (n.strip() for n in joints.split(",") if n.strip()):
        try:
            indices.append(desc.joint_index(name))
        except (KeyError, ValueError, MimicError):
            raise MimicError(
                f"--joints: {robot} has no joint {name!r}; its joints: "
                f"{', '.join(desc.joint_names)} (or 'legs', 'all')"
            ) from None
    if not indices:
        raise MimicError("--joints is empty; give 'legs', 'all' or joint names")
    return sorted(set(indices))


class Target(ABC):
    """A thing to improve: a search space, candidates as specs, results as files."""

    #: ``motion``, ``model`` or ``params``.
    kind: str
    #: Suffix of the file ``write`` produces.
    suffix: str

    def __init__(self, text: str, space: Space, label: str) -> None:
        self.text, self.space, self.label = text, space, label

    @abstractmethod
    def spec(self, z: np.ndarray, label: str | None = None):
        """The candidate at search point z (d,) as a picklable spec."""

    @abstractmethod
    def write(self, z: np.ndarray, path: Path, provenance: dict) -> Path:
        """Write the candidate at z as the file every command accepts; returns the path."""

    def baseline(self):
        """The target as it is (z = 0)."""
        return self.spec(np.zeros(self.space.dim), label=self.label)


def _atomic_write(path: Path, text: str) -> Path:

    with atomic_output(path) as tmp:
        tmp.write_text(text)
    return path


class MotionTarget(Target):
    """A keyframe motion: chosen joints' angles per keyframe, step times and speed rate.

    Scales: 0.05 rad per angle (bounds +-0.35 rad inside the joint stops), a fifth of each
    step time (0.3x..2x), 0.05 of speed rate (0.5..2).
    """

    kind, suffix = "motion", ".txt"

    def __init__(self, text: str, movement, joints: str = "legs") -> None:

        robot = get_robot(movement.robot)
        self.movement, self.joints = movement, resolve_joints(movement.robot, joints)
        names, base, scale, lower, upper = [], [], [], [], []
        for k, step in enumerate(movement.steps):
            for j in self.joints:
                spec = robot.joints[j]
                a = float(step.angles_rad[j])
                names.append(f"step{k}.{spec.name}")
                base.append(a)
                scale.append(0.05)
                lower.append(min(a, max(spec.lower_rad, a - 0.35)))
                upper.append(max(a, min(spec.upper_rad, a + 0.35)))
        for k, step in enumerate(movement.steps):
            t = float(step.time_s)
            names.append(f"step{k}.time_s")
            base.append(t)
            scale.append(max(0.2 * t, 0.01))
            lower.append(0.3 * t)
            upper.append(2.0 * t + 0.05)
        names.append("speed_rate")
        base.append(float(movement.speed_rate))
        scale.append(0.05)
        lower.append(min(0.5, movement.speed_rate))
        upper.append(max(2.0, movement.speed_rate))
        super().__init__(text, Space(tuple(names), base, scale, lower, upper), movement.name)

    def movement_at(self, z: np.ndarray):

        v = self.space.values(z)
        n_steps, n_j = len(self.movement.steps), len(self.joints)
        angles = v[: n_steps * n_j].reshape(n_steps, n_j)
        times = v[n_steps * n_j : n_steps * n_j + n_steps]
        steps = []
        for k, step in enumerate(self.movement.steps):
            a = np.array(step.angles_rad, dtype=float)
            a[self.joints] = angles[k]
            steps.append(KeyframeStep(a, float(times[k])))
        m = self.movement
        return Movement(
            m.name, tuple(steps), float(v[-1]), m.ball_offset_m, m.start_posture, m.robot
        )

    def spec(self, z, label=None):
        return MovementSpec(self.movement_at(z), label or f"{self.label} (improved)")

    def write(self, z, path, provenance):

        header = "".join(f"# {line}\n" for line in _provenance_lines(provenance))
        return _atomic_write(Path(path), header + format_motion(self.movement_at(z)))


#: The balance layer's tilt gains a ``+balance`` model target searches: field -> (scale,
#: lower, upper), in the field's units (``agents.balance.BalanceGains``). The T1's kick copies
#: stand or fall on the roll gain (0.23-2.0 tried by hand, docs/tuning-notes.md).
BALANCE_SEARCH: dict[str, tuple[float, float, float]] = {
    "pitch": (0.1, 0.0, 2.0),
    "roll": (0.25, 0.0, 3.0),
    "pitch_rate_s": (0.02, 0.0, 0.3),
    "roll_rate_s": (0.05, 0.0, 0.5),
    "limit_rad": (0.05, 0.1, 0.6),
}


class ModelTarget(Target):
    """A learned model: time warp, per-joint offsets and gains (``improve.correction``), and
    inside the balance layer its tilt gains.

    Parameters: ``time_rate`` (scale 0.05, 0.7..1.4), ``offset.<joint>`` [rad] (scale 0.03,
    +-0.25 rad) and ``gain.<joint>`` (scale 0.05, 0.5..1.5) for the chosen joints (default:
    the legs: 1 + 12 + 12 = 25 parameters on the NAO); with ``balance``, ``balance.<gain>``
    (``BALANCE_SEARCH``) from the gains the layer would use around the model as it is. The
    model file written carries the gains found (``model.keys.BALANCE_GAINS_KEY``), so
    ``OUT.mimic+balance`` plays with them. With ``window_s`` (a one-shot model) the offsets
    and gains act only within that window [s of the motion] (``improve.correction``'s
    windowed correction, kept exact in the model file).
    """

    kind, suffix = "model", ".mimic"

    def __init__(
        self,
        text: str,
        model,
        balance: bool = False,
        joints: str = "legs",
        window_s: tuple[float, float] | None = None,
    ) -> None:
        self.model, self.balance = model, balance
        if window_s is None and isinstance(model, WindowedModel):
            raise MimicError(
                f"{Path(text).name} is corrected in a window (--window); improve it in "
                "another window (--window START,END or auto), not over the whole motion"
            )
        if window_s is not None:
            lo, hi = (float(v) for v in window_s)
            if model.cyclic or not 0 <= lo < hi:
                raise MimicError(
                    f"--window {lo:g} {hi:g}: a window of a one-shot model's time, from >= 0 "
                    f"to a later time ({Path(text).name} is "
                    f"{'cyclic' if model.cyclic else f'{model.duration_s:.2f} s long'})"
                )
            # A window to the motion's end (or past it) holds its correction to the last pose.
            end = model.duration_s + WINDOW_RAMP_S
            window_s = (lo, end if hi >= model.duration_s - 1e-9 else hi)
        self.window_s = window_s
        self.joints = resolve_joints(model.robot, joints)
        names = [model.joint_names[j] for j in self.joints]
        params = [
            ("time_rate", 1.0, 0.05, 0.7, 1.4),
            *((f"offset.{n}", 0.0, 0.03, -0.25, 0.25) for n in names),
            *((f"gain.{n}", 1.0, 0.05, 0.5, 1.5) for n in names),
        ]
        if balance:
            gains = self._layer_gains()
            for field, (scale, lower, upper) in BALANCE_SEARCH.items():
                value = float(getattr(gains, field))
                params.append(
                    (f"balance.{field}", value, scale, min(lower, value), max(upper, value))
                )
        names_, base, scale, lower, upper = zip(*params)
        super().__init__(
            text,
            Space(names_, base, scale, lower, upper),
            Path(text.removesuffix("+balance")).stem
            + " (learned)"
            + (" + balance" if balance else ""),
        )

    def _layer_gains(self):
        """The tilt gains the balance layer uses around the model as it is."""

        return BalancedAgent(NeuralPlayer(self.model)).gains

    def model_at(self, z: np.ndarray, provenance: dict | None = None):

        v = self.space.values(z)
        n, d = len(self.model.joint_names), len(self.joints)
        offsets, gains = np.zeros(n), np.ones(n)
        offsets[self.joints] = v[1 : 1 + d]
        gains[self.joints] = v[1 + d : 1 + 2 * d]
        if self.window_s is not None:
            model = windowed_model(
                self.model, float(v[0]), self.window_s, offsets, gains, provenance=provenance
            )
        else:
            model = corrected_model(self.model, float(v[0]), offsets, gains, provenance=provenance)
        if not self.balance:
            return model
        own = {
            name.removeprefix("balance."): float(value)
            for name, value in zip(self.space.names, v)
            if name.startswith("balance.")
        }
        return with_balance_gains(model, own)

    def spec(self, z, label=None):
        return ModelSpec(self.model_at(z), label or f"{self.label} (improved)", self.balance)

    def baseline(self):
        return ModelSpec(self.model, self.label, self.balance)

    def write(self, z, path, provenance):

        return save_model(self.model_at(z, provenance), Path(path))


#: The other team's walk: parameter -> (scale, lower, upper), in the parameter's units.
#: The cycles per step (an integer), the start-up bend and the arm pose stay as they are.
WALK_SEARCH: dict[str, tuple[float, float, float]] = {
    "speed_m_s": (0.03, 0.35, 0.95),
    "max_step_m": (0.01, 0.06, 0.20),
    "step_ramp_m": (0.001, 0.002, 0.02),
    "walk_height_m": (0.005, 0.14, 0.20),
    "step_height_m": (0.005, 0.03, 0.12),
    "swing_fraction": (0.03, 0.5, 0.95),
    "swing_trapezoid": (0.1, 0.0, 1.0),
    "foot_spread_m": (0.005, -0.03, 0.03),
    "sway_m": (0.003, 0.0, 0.03),
    "foot_x_m": (0.005, -0.06, 0.03),
    "lean_rad": (0.01, -0.1, 0.2),
    "pitch_gain": (0.05, 0.0, 1.5),
    "roll_gain": (0.05, 0.0, 1.5),
    "pitch_rate_gain": (0.005, 0.0, 0.1),
    "roll_rate_gain": (0.005, 0.0, 0.1),
    "hip_share": (0.05, 0.0, 1.0),
    "yaw_gain": (0.03, 0.0, 1.0),
    "line_gain": (0.05, 0.0, 2.0),
    "max_turn_rad": (0.01, 0.01, 0.15),
    "servo.gain": (0.03, 0.2, 1.0),
    "servo.feedforward": (0.03, 0.0, 1.0),
}
#: Search tables per engine (``agents.params_file.PARAM_ENGINES``).
ENGINE_SEARCH = {"other-team-walk": WALK_SEARCH}


def _get(params, path: str) -> float:
    for part in path.split("."):
        params = getattr(params, part)
    return float(params)


def _set(params, path: str, value: float):
    import dataclasses

    head, _, rest = path.partition(".")
    if not rest:
        return dataclasses.replace(params, **{head: value})
    return dataclasses.replace(params, **{head: _set(getattr(params, head), rest, value)})


class ParamsTarget(Target):
    """An engine's parameters (``WALK_SEARCH`` for the other team's walk: 21 floats)."""

    kind, suffix = "params", ".json"

    def __init__(self, text: str, agent: str, params, robot: str = "nao") -> None:
        self.agent, self.params, self.robot = agent, params, robot
        table = ENGINE_SEARCH[agent]
        names = tuple(table)
        base = np.array([_get(params, n) for n in names])
        scale = np.array([table[n][0] for n in names])
        lower = np.minimum([table[n][1] for n in names], base)
        upper = np.maximum([table[n][2] for n in names], base)
        label = agent if text == agent else Path(text).stem + " (params)"
        super().__init__(text, Space(names, base, scale, lower, upper), label)

    def params_at(self, z: np.ndarray):
        params = self.params
        for name, value in zip(self.space.names, self.space.values(z)):
            params = _set(params, name, float(value))
        return params

    def spec(self, z, label=None):
        return ParamsSpec(
            self.agent, self.params_at(z), label or f"{self.label} (improved)", self.robot
        )

    def baseline(self):
        return ParamsSpec(self.agent, self.params, self.label, self.robot)

    def write(self, z, path, provenance):

        return save_params(self.agent, self.params_at(z), Path(path), provenance)


def _provenance_lines(provenance: dict) -> list[str]:
    lines = ["improved by mimic improve"]
    for key, value in provenance.items():
        if isinstance(value, dict):  # the parameters: the motion below holds them
            continue
        if isinstance(value, float):
            value = f"{value:.4g}" if math.isfinite(value) else str(value)
        lines.append(f"{key}: {value}")
    return lines


def load_target(
    text: str,
    *,
    joints: str = "legs",
    robot: str = "nao",
    window_s: tuple[float, float] | None = None,
) -> Target:
    """The target named by ``text`` (an agent spec, see ``agents.registry``); ``window_s``
    (a learned one-shot model only): its correction acts within that window [s].

    Raises:
        MimicError: unknown name, missing or bad file, or an agent that has nothing to search
            (our walk engine, the other team's kick).
    """

    spec = agent_spec(text, robot=robot)
    if window_s is not None and spec.kind != "model":
        raise MimicError(f"--window corrects a learned model (.mimic), not {text!r}")
    if spec.kind == "motion":
        return MotionTarget(text, load_motion(spec.ref, spec.robot), joints)
    if spec.kind == "model":
        return ModelTarget(text, load_model(spec.ref), spec.balance, joints, window_s)
    engine = spec.kind == "params" or (spec.ref in PARAM_ENGINES and spec.ref in ENGINE_SEARCH)
    if engine and spec.robot != "nao":  # the parameter engines are the NAO's
        raise MimicError(
            f"cannot improve {text!r} on the {spec.robot}: engine parameters are searched for "
            f"the NAO only; improve a motion or a learned model of the {spec.robot} instead"
        )
    if spec.kind == "params":
        agent, params = load_params(spec.ref)
        return ParamsTarget(text, agent, params, spec.robot)
    if engine:
        return ParamsTarget(text, spec.ref, default_params(spec.ref), spec.robot)
    raise MimicError(
        f"cannot improve {text!r}: it has no parameters to search; targets: a "
        "keyframe motion (name or .txt), a learned model (.mimic), "
        f"{', '.join(ENGINE_SEARCH)} or a .json parameter file"
    )
