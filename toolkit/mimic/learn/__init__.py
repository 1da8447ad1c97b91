"""Learning motions: datasets from recordings, the study's network, presets, a fast batched
trainer, model files, compensated targets and ONNX export.

Notebook entry points::

    from mimic.learn import training_dataset, train_model, TrainConfig, PAPER, FAST, save_model
    ds = training_dataset("recordings/kick_right.mcap")
    model = train_model(ds, TrainConfig(FAST, seed=0))
    save_model(model, "models/kick_right.mimic")
"""

from mimic.learn.dataset import Dataset, dataset_from_file, dataset_from_frame
from mimic.learn.presets import FAST, PAPER, Phase, Preset, get_preset
from mimic.learn.train import (
    TrainConfig,
    TrainProgress,
    evaluate,
    train_model,
    train_models,
    training_dataset,
)
from mimic.model.model_file import describe_model, is_model_file, load_model, save_model
from mimic.model.motion_model import MotionModel

__all__ = [
    "Dataset",
    "dataset_from_file",
    "dataset_from_frame",
    "MotionModel",
    "describe_model",
    "is_model_file",
    "load_model",
    "save_model",
    "FAST",
    "PAPER",
    "Phase",
    "Preset",
    "get_preset",
    "TrainConfig",
    "TrainProgress",
    "evaluate",
    "train_model",
    "train_models",
    "training_dataset",
]
