"""Parameter files: an engine's parameters as JSON, played by file name like a motion or model.

    {"format": "mimic-agent-params", "format_version": 1, "agent": "other-team-walk",
     "params": {"step_cycles": 8, "speed_m_s": 0.58, "servo": {"gain": 0.4}, ...},
     "provenance": {...}}

``agent`` names an engine in ``PARAM_ENGINES``; ``params`` holds the fields of its frozen
parameter dataclass (nested dataclasses as objects; fields left out keep their defaults).
``provenance`` is free-form (``mimic improve`` records its search and validation there).
``mimic improve other-team-walk ... -o walk.json`` writes one, and every command that takes an
agent takes ``walk.json`` (``mimic trial walk --compare other-team-walk walk.json``).
"""

from __future__ import annotations

import dataclasses
import importlib
import json
import math
from pathlib import Path

from mimic.agents.base import Agent
from mimic.errors import MimicError
from mimic.files import atomic_output

__all__ = [
    "PARAM_ENGINES",
    "FORMAT",
    "ParamsFileError",
    "params_to_dict",
    "params_from_dict",
    "default_params",
    "build_engine",
    "save_params",
    "load_params",
]

FORMAT = "mimic-agent-params"
FORMAT_VERSION = 1
#: Engine name -> ("module:ParamsDataclass", "module:AgentClass taking the params").
PARAM_ENGINES: dict[str, tuple[str, str]] = {
    "other-team-walk": (
        "mimic.agents.other_team.params:WalkParams",
        "mimic.agents.other_team.walk:OtherTeamWalk",
    ),
}


class ParamsFileError(MimicError):
    """A parameter file that is missing, not one, or names an unknown engine or field."""


def _attr(target: str):
    module, name = target.split(":")
    return getattr(importlib.import_module(module), name)


def _engine(agent: str) -> tuple[type, type]:
    if agent not in PARAM_ENGINES:
        raise ParamsFileError(f"no parameter engine {agent!r}; engines: {', '.join(PARAM_ENGINES)}")
    params_cls, agent_cls = PARAM_ENGINES[agent]
    return _attr(params_cls), _attr(agent_cls)


def default_params(agent: str):
    """The engine's own parameters (its dataclass defaults)."""
    return _engine(agent)[0]()


def build_engine(agent: str, params) -> Agent:
    """A fresh agent of engine ``agent`` playing ``params``."""
    return _engine(agent)[1](params)


def params_to_dict(params) -> dict:
    """Fields of a (nested) parameter dataclass as JSON-able data."""
    return {
        f.name: (params_to_dict(v) if dataclasses.is_dataclass(v) else v)
        for f in dataclasses.fields(params)
        for v in [getattr(params, f.name)]
    }


def params_from_dict(cls: type, data: dict, where: str = "params"):
    """``cls`` with the fields in ``data`` (nested dataclasses from nested objects).

    Raises:
        ParamsFileError: unknown field, or a value of the wrong type or not finite.
    """
    if not isinstance(data, dict):
        raise ParamsFileError(f"{where}: expected an object of {cls.__name__} fields")
    fields = {f.name: f for f in dataclasses.fields(cls)}
    defaults = cls()
    values = {}
    for name, value in data.items():
        if name not in fields:
            raise ParamsFileError(
                f"{where}: {cls.__name__} has no field {name!r}; fields: {', '.join(fields)}"
            )
        default = getattr(defaults, name)
        if dataclasses.is_dataclass(default):
            values[name] = params_from_dict(type(default), value, f"{where}.{name}")
        elif isinstance(default, int) and not isinstance(default, bool):
            if not isinstance(value, int) or isinstance(value, bool):
                raise ParamsFileError(f"{where}.{name}: expected an integer, got {value!r}")
            values[name] = value
        else:
            if (
                not isinstance(value, (int, float))
                or isinstance(value, bool)
                or not math.isfinite(value)
            ):
                raise ParamsFileError(f"{where}.{name}: expected a finite number, got {value!r}")
            values[name] = float(value)
    return dataclasses.replace(defaults, **values)


def save_params(agent: str, params, path: str | Path, provenance: dict | None = None) -> Path:
    """Write a parameter file (to a temporary name first, then moved into place)."""
    _engine(agent)

    path = Path(path)
    doc = {
        "format": FORMAT,
        "format_version": FORMAT_VERSION,
        "agent": agent,
        "params": params_to_dict(params),
        "provenance": provenance or {},
    }
    with atomic_output(path) as tmp:
        tmp.write_text(json.dumps(doc, indent=1) + "\n")
    return path


def load_params(path: str | Path) -> tuple[str, object]:
    """(engine name, its parameters) from a parameter file.

    Raises:
        ParamsFileError: missing file, not a parameter file, unknown engine or field.
    """
    path = Path(path)
    if not path.is_file():
        raise ParamsFileError(f"parameter file {str(path)!r} not found")
    try:
        doc = json.loads(path.read_text())
    except (json.JSONDecodeError, UnicodeDecodeError) as err:
        raise ParamsFileError(f"{path}: not a parameter file ({err})") from None
    if not isinstance(doc, dict) or doc.get("format") != FORMAT:
        raise ParamsFileError(f"{path}: not a parameter file (no {FORMAT!r} format tag)")
    if int(doc.get("format_version", 0)) > FORMAT_VERSION:
        raise ParamsFileError(
            f"{path}: parameter format {doc['format_version']} is newer than "
            f"this toolkit reads ({FORMAT_VERSION}); update mimic"
        )
    agent = str(doc.get("agent"))
    params_cls, _ = _engine(agent)
    return agent, params_from_dict(params_cls, doc.get("params", {}), f"{path}: params")
