"""ONNX export of a motion model, built directly with ``onnx.helper``.

Graph: input ``time_s`` (T, 1) float32 = seconds from the motion start; output ``outputs``
(T, N + 1) float32 = the robot's N joint references [rad] in its order + the ended flag (the
width is the model's); both carry these meanings as ONNX doc strings. The input mapping is
inside the graph:

* time models: x = (time_s - offset) * scale (Sub, Mul);
* cyclic (phase) models: the input is still time [s]; the graph computes
  angle = time_s * 2 pi / period and x = [sin(angle), cos(angle)] (Mul, Sin, Cos, Concat),
  so any time (also past the first period) gives the looping motion.

Then MatMul/Add/LeakyRelu(0.3) x2, MatMul/Add, and the output de-standardisation (Mul, Add).
``metadata_props`` hold ``robot`` (its registry name), ``num_joints``, ``joint_names`` (JSON
list, output order), ``outputs``, ``motion``, ``input_kind``, ``period_s``, ``duration_s``,
``preset`` and ``toolkit_version``.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from mimic import __version__
from mimic.errors import MimicError
from mimic.files import atomic_output
from mimic.model.motion_model import INPUT_PHASE, MotionModel
from mimic.model.network import LEAKY_SLOPE
from mimic.model.windowed import WindowedModel

__all__ = ["model_to_onnx", "export_onnx", "output_doc", "OPSET", "INPUT_DOC"]

#: ONNX opset used (LeakyRelu, Sin, Cos are all in opset 7+).
OPSET = 17
#: Doc string of the graph's input.
INPUT_DOC = (
    "time_s: (T, 1) float32, seconds from the motion start; cyclic motions loop, so "
    "any time is valid"
)


def output_doc(model: MotionModel) -> str:
    """Doc string of the graph's output: what each of its columns is."""
    return (
        f"outputs: (T, {model.layout.out_dim}) float32; columns 0..{len(model.joint_names) - 1}"
        f": joint references [rad] in this order: {', '.join(model.joint_names)}; column "
        f"{len(model.joint_names)}: the motion-ended flag (> 0.5: the motion has ended)"
    )


def model_to_onnx(model: MotionModel):
    """An ``onnx.ModelProto`` computing ``model.predict`` for a batch of times."""
    if isinstance(model, WindowedModel):
        raise MimicError(
            f"{model.name}: a model improved over a time window (mimic improve --window) "
            "plays its correction in mimic only; ONNX export takes a model without one"
        )
    import onnx
    from onnx import TensorProto, helper, numpy_helper

    def const(name: str, value) -> onnx.TensorProto:
        return numpy_helper.from_array(np.asarray(value, dtype=np.float32), name)

    nodes, inits = [], []
    if model.input_kind == INPUT_PHASE:
        inits.append(const("angle_per_s", [2.0 * math.pi / model.period_s]))
        nodes += [
            helper.make_node("Mul", ["time_s", "angle_per_s"], ["angle"]),
            helper.make_node("Sin", ["angle"], ["sin_angle"]),
            helper.make_node("Cos", ["angle"], ["cos_angle"]),
            helper.make_node("Concat", ["sin_angle", "cos_angle"], ["x0"], axis=1),
        ]
    else:
        inits += [
            const("input_offset_s", [model.input_offset_s]),
            const("input_scale_per_s", [model.input_scale_per_s]),
        ]
        nodes += [
            helper.make_node("Sub", ["time_s", "input_offset_s"], ["t_shift"]),
            helper.make_node("Mul", ["t_shift", "input_scale_per_s"], ["x0"]),
        ]
    layers = model.layout.layers(np.asarray(model.params, dtype=np.float32))
    h = "x0"
    for i, (w, b) in enumerate(layers):
        inits += [const(f"W{i}", w), const(f"b{i}", b)]
        nodes += [
            helper.make_node("MatMul", [h, f"W{i}"], [f"m{i}"]),
            helper.make_node("Add", [f"m{i}", f"b{i}"], [f"h{i}"]),
        ]
        h = f"h{i}"
        if i < len(layers) - 1:
            nodes.append(helper.make_node("LeakyRelu", [h], [f"a{i}"], alpha=LEAKY_SLOPE))
            h = f"a{i}"
    inits += [const("output_std", model.output_std), const("output_mean", model.output_mean)]
    nodes += [
        helper.make_node("Mul", [h, "output_std"], ["y_scaled"]),
        helper.make_node("Add", ["y_scaled", "output_mean"], ["outputs"]),
    ]
    graph = helper.make_graph(
        nodes,
        f"mimic_{model.name}",
        [
            helper.make_tensor_value_info(
                "time_s", TensorProto.FLOAT, ["T", 1], doc_string=INPUT_DOC
            )
        ],
        [
            helper.make_tensor_value_info(
                "outputs",
                TensorProto.FLOAT,
                ["T", model.layout.out_dim],
                doc_string=output_doc(model),
            )
        ],
        inits,
        doc_string=f"mimic motion network for {model.name!r} ({model.input_kind} input, "
        f"{model.layout.n_params} parameters, preset {model.preset})",
    )
    proto = helper.make_model(
        graph,
        producer_name="mimic",
        producer_version=__version__,
        opset_imports=[helper.make_opsetid("", OPSET)],
    )
    proto.ir_version = min(proto.ir_version, 9)  # readable by older onnxruntime releases
    meta = {
        "robot": model.robot,
        "num_joints": str(model.num_joints),
        "joint_names": json.dumps(list(model.joint_names)),
        "outputs": json.dumps(list(model.joint_names) + ["ended"]),
        "motion": model.name,
        "input": "time_s: seconds from the motion start (T, 1)",
        "input_kind": model.input_kind,
        "period_s": json.dumps(model.period_s),
        "duration_s": json.dumps(model.duration_s),
        "preset": model.preset,
        "toolkit_version": __version__,
    }
    helper.set_model_props(proto, meta)
    onnx.checker.check_model(proto)
    return proto


def export_onnx(model: MotionModel, path: str | Path, *, overwrite: bool = True) -> Path:
    """Write ``model`` as an ONNX file (under a temporary name, moved into place when
    complete, see ``mimic.files``); returns the path."""
    import onnx

    path = Path(path)
    proto = model_to_onnx(model)
    with atomic_output(path, overwrite=overwrite) as tmp:
        onnx.save(proto, str(tmp))
    return path
