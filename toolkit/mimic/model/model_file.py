"""The ``.mimic`` model file: a zip (numpy ``.npz``) holding the arrays and one JSON entry.

Entries:
  ``meta.json``   format tag and version, robot and its joint order, input kind and mapping,
                  network shape, preset, training metrics, source recording metadata,
                  toolkit version;
  ``params.npy``  (P,) float32 parameters in ``mimic.model.network.Layout`` order;
  ``output_mean.npy``, ``output_std.npy``  (N + 1,) output de-standardisation.
Files written before robots were data have no ``robot``: they are our NAO's.
A few kilobytes for the study's network; ``unzip -p model.mimic meta.json`` shows what it is.
"""

from __future__ import annotations

import io
import json
import zipfile
import zlib
from pathlib import Path

import numpy as np

from mimic import __version__
from mimic.errors import MimicError, ModelFileError
from mimic.files import atomic_output, input_file
from mimic.model.keys import CORRECTION_KEY
from mimic.model.motion_model import INPUT_PHASE, INPUT_TIME, MotionModel
from mimic.model.network import Layout
from mimic.model.windowed import WindowedModel
from mimic.robot.registry import DEFAULT_ROBOT, get_robot

__all__ = [
    "save_model",
    "load_model",
    "describe_model",
    "is_model_file",
    "looks_like_model_file",
    "FORMAT",
    "SUFFIX",
]

FORMAT = "mimic-motion-model"
FORMAT_VERSION = 1
SUFFIX = ".mimic"
_META = "meta.json"
_ZIP_MAGIC = b"PK\x03\x04"
#: What a damaged zip raises while reading: bad CRC, bad deflate data, cut-off entries.
_DAMAGE = (zipfile.BadZipFile, zlib.error, EOFError, OSError, NotImplementedError)
_RETRAIN = "train it again with 'mimic train RECORDING -o MODEL.mimic'"


def _array_bytes(a: np.ndarray) -> bytes:
    buf = io.BytesIO()
    np.save(buf, a, allow_pickle=False)
    return buf.getvalue()


def save_model(model: MotionModel, path: str | Path, *, overwrite: bool = True) -> Path:
    """Write ``model`` to ``path`` (parent folders created, written under a temporary name and
    moved into place, see ``mimic.files``); returns the path."""
    path = Path(path)
    meta = {
        "format": FORMAT,
        "format_version": FORMAT_VERSION,
        "toolkit_version": __version__,
        "motion": model.name,
        "robot": model.robot,
        "joint_names": list(model.joint_names),
        "outputs": list(model.joint_names) + ["ended"],
        "input_kind": model.input_kind,
        "input_offset_s": model.input_offset_s,
        "input_scale_per_s": model.input_scale_per_s,
        "period_s": model.period_s,
        "duration_s": model.duration_s,
        "layout": {
            "in_dim": model.layout.in_dim,
            "out_dim": model.layout.out_dim,
            "hidden": list(model.layout.hidden),
            "activation": "leaky_relu_0.3",
            "n_params": model.layout.n_params,
        },
        "preset": model.preset,
        "metrics": model.metrics,
        "source": model.metadata,
    }
    with atomic_output(path, overwrite=overwrite) as tmp:  # never a half-written model
        with zipfile.ZipFile(tmp, "w", compression=zipfile.ZIP_DEFLATED) as z:
            z.writestr(_META, json.dumps(meta, indent=1, default=_json_default))
            z.writestr("params.npy", _array_bytes(np.asarray(model.params, dtype=np.float32)))
            z.writestr(
                "output_mean.npy", _array_bytes(np.asarray(model.output_mean, dtype=np.float64))
            )
            z.writestr(
                "output_std.npy", _array_bytes(np.asarray(model.output_std, dtype=np.float64))
            )
    return path


def _json_default(value):
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    return str(value)


def _starts_as_zip(path: Path) -> bool:
    try:
        with open(path, "rb") as f:
            return f.read(len(_ZIP_MAGIC)) == _ZIP_MAGIC
    except OSError:
        return False


def looks_like_model_file(path: str | Path) -> bool:
    """True for a ``.mimic`` name or a zip file: something to read as a model (and to call a
    broken model file if it does not read), not as a recording."""
    path = Path(path)
    return path.suffix == SUFFIX or _starts_as_zip(path)


def _read_meta(path: Path) -> tuple[zipfile.ZipFile, dict]:
    try:
        input_file(path, "model file", "train one with 'mimic train RECORDING -o MODEL.mimic'")
    except MimicError as err:
        raise ModelFileError(str(err)) from None
    try:
        z = zipfile.ZipFile(path)
    except _DAMAGE as err:
        if _starts_as_zip(path):  # a model file cut off or damaged at its end
            raise ModelFileError(
                f"{path}: broken model file ({_damage(err)}: cut off or damaged); {_RETRAIN}"
            ) from None
        raise ModelFileError(
            f"{path}: not a mimic model file (not a zip archive); {_RETRAIN}"
        ) from None
    try:
        meta = json.loads(z.read(_META))
    except KeyError:
        z.close()
        raise ModelFileError(f"{path}: not a mimic model file (no {_META}); {_RETRAIN}") from None
    except (*_DAMAGE, json.JSONDecodeError, UnicodeDecodeError) as err:
        z.close()
        raise ModelFileError(
            f"{path}: broken model file ({_damage(err)} in {_META}); {_RETRAIN}"
        ) from None
    if not isinstance(meta, dict) or meta.get("format") != FORMAT:
        z.close()
        raise ModelFileError(f"{path}: not a mimic model file (no {FORMAT!r} tag)")
    return z, meta


def _damage(err: BaseException) -> str:
    """What is wrong, in a few words: ``bad CRC-32 of params.npy``, ``missing 'layout'``."""
    text = str(err).strip().splitlines()[0] if str(err).strip() else ""
    if isinstance(err, KeyError):
        return f"missing {text}"
    if isinstance(err, zipfile.BadZipFile):
        return text[:1].lower() + text[1:] if text else "damaged zip archive"
    return f"{type(err).__name__}: {text}"[:100] if text else type(err).__name__


def is_model_file(path: str | Path) -> bool:
    """True if ``path`` is a readable ``.mimic`` model file (checks the content, not the name)."""
    try:
        z, _ = _read_meta(Path(path))
    except ModelFileError:
        return False
    z.close()
    return True


def load_model(path: str | Path) -> MotionModel:
    """Read a model file.

    Raises:
        ModelFileError: missing file, not a model, a newer format, an unknown robot, or joints
            other than its robot's.
    """
    path = Path(path)
    z, meta = _read_meta(path)
    with z:
        _check_meta(path, meta)
        if int(meta.get("format_version", 0)) > FORMAT_VERSION:
            raise ModelFileError(
                f"{path}: model format {meta['format_version']} is newer than "
                f"this toolkit reads ({FORMAT_VERSION}); update mimic"
            )
        try:
            robot = get_robot(str(meta.get("robot", DEFAULT_ROBOT)))
        except MimicError as err:
            raise ModelFileError(f"{path}: {err}") from None
        names = tuple(meta.get("joint_names", ()))
        if names != robot.joint_names:
            raise ModelFileError(
                f"{path}: model made for a different joint layout ({len(names)} joints"
                f"{', first ' + names[0] if names else ''}); the {robot.name} has "
                f"{robot.num_joints} joints starting {robot.joint_names[0]}: retrain it on a "
                f"recording of the {robot.name}"
            )
        try:
            lay = meta["layout"]
            layout = Layout(
                in_dim=int(lay["in_dim"]),
                out_dim=int(lay["out_dim"]),
                hidden=tuple(int(h) for h in lay["hidden"]),
            )
            params = np.load(io.BytesIO(z.read("params.npy")), allow_pickle=False)
            mean = np.load(io.BytesIO(z.read("output_mean.npy")), allow_pickle=False)
            std = np.load(io.BytesIO(z.read("output_std.npy")), allow_pickle=False)
        except (KeyError, ValueError, TypeError, *_DAMAGE) as err:
            raise ModelFileError(
                f"{path}: broken model file ({_damage(err)}); {_RETRAIN}"
            ) from None
    if (
        params.shape != (layout.n_params,)
        or layout.out_dim != len(names) + 1
        or mean.shape != (layout.out_dim,)
        or std.shape != (layout.out_dim,)
    ):
        raise ModelFileError(f"{path}: damaged model file (array shapes do not match its layout)")
    model = MotionModel(
        layout,
        params,
        input_kind=meta["input_kind"],
        input_offset_s=float(meta["input_offset_s"]),
        input_scale_per_s=float(meta["input_scale_per_s"]),
        period_s=meta.get("period_s"),
        duration_s=float(meta.get("duration_s", 0.0)),
        output_mean=mean,
        output_std=std,
        preset=meta.get("preset", "?"),
        robot=robot.name,
        joint_names=names,
        metrics=meta.get("metrics", {}),
        metadata=meta.get("source", {}),
    )
    correction = model.metadata.get(CORRECTION_KEY)
    if isinstance(correction, dict) and "window_s" in correction:
        try:
            return WindowedModel.from_record(model, correction)
        except (KeyError, ValueError, TypeError) as err:
            raise ModelFileError(
                f"{path}: broken windowed correction ({err}); improve the model again"
            ) from None
    return model


def _number(value, *, positive: bool = False, optional: bool = False) -> bool:
    """A finite number (JSON int or float, not a bool), > 0 if ``positive``; None if
    ``optional``."""
    if value is None:
        return optional
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return False
    return bool(np.isfinite(value)) and (value > 0 if positive else True)


def _check_meta(path: Path, meta: dict) -> None:
    """Every field ``load_model`` and ``describe_model`` read has the right type (an edited
    ``meta.json`` fails here, in one line naming the field).

    Raises:
        ModelFileError: a field missing or of the wrong type or range.
    """

    def bad(field: str, want: str) -> ModelFileError:
        shown = json.dumps(meta.get(field), default=str)
        shown = shown if len(shown) <= 40 else shown[:37] + "..."
        return ModelFileError(
            f"{path}: broken model file ({_META}: {field} must be {want}, got {shown}); {_RETRAIN}"
        )

    version = meta.get("format_version", 0)
    if isinstance(version, bool) or not isinstance(version, int):
        raise bad("format_version", "a whole number")
    if not isinstance(meta.get("robot", DEFAULT_ROBOT), str):
        raise bad("robot", "a robot name")
    names = meta.get("joint_names")
    if not isinstance(names, list) or not names or not all(isinstance(n, str) for n in names):
        raise bad("joint_names", "a list of joint names")
    if meta.get("input_kind") not in (INPUT_TIME, INPUT_PHASE):
        raise bad("input_kind", f"{INPUT_TIME!r} or {INPUT_PHASE!r}")
    for field in ("input_offset_s", "input_scale_per_s"):
        if not _number(meta.get(field)):
            raise bad(field, "a finite number")
    if not _number(meta.get("period_s"), positive=True, optional=True):
        raise bad("period_s", "a number of seconds > 0, or null")
    if "duration_s" in meta and not _number(meta["duration_s"]):
        raise bad("duration_s", "a finite number of seconds")
    layout = meta.get("layout")
    if (
        not isinstance(layout, dict)
        or not all(
            isinstance(layout.get(k), int) and not isinstance(layout.get(k), bool) and layout[k] > 0
            for k in ("in_dim", "out_dim")
        )
        or not isinstance(layout.get("hidden"), list)
        or not all(
            isinstance(h, int) and not isinstance(h, bool) and h > 0 for h in layout["hidden"]
        )
    ):
        raise bad("layout", "{in_dim, out_dim, hidden: [sizes]} of whole numbers > 0")
    for field in ("metrics", "source"):
        if not isinstance(meta.get(field, {}), dict):
            raise bad(field, "an object")
    per_joint = meta.get("metrics", {}).get("mae_rad_per_joint", {})
    if not isinstance(per_joint, dict) or not all(_number(v) for v in per_joint.values()):
        raise bad("metrics", "an object whose mae_rad_per_joint maps joints to numbers")
    if not isinstance(meta.get("preset", ""), str):
        raise bad("preset", "a preset name")


def describe_model(path: str | Path) -> dict:
    """What a model file is, as plain JSON-able data (for ``mimic info MODEL --json``).

    Raises:
        ModelFileError: as ``load_model``.
    """
    path = Path(path)
    model = load_model(path)
    z, meta = _read_meta(path)
    z.close()
    metrics = dict(meta.get("metrics", {}))
    return {
        "kind": "model",
        "path": str(path),
        "size_bytes": path.stat().st_size,
        "motion": model.name,
        "robot": model.robot,
        "num_joints": model.num_joints,
        "preset": model.preset,
        "input_kind": model.input_kind,
        "duration_s": model.duration_s,
        "period_s": model.period_s,
        "n_params": model.layout.n_params,
        "layout": meta["layout"],
        "joint_names": list(model.joint_names),
        "metrics": metrics,
        "source": meta.get("source", {}),
        "toolkit_version": meta.get("toolkit_version"),
    }
