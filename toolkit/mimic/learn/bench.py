"""Training speed benchmark: our numpy trainer vs the straightforward torch loop, and batched vs
one-after-another training (``mimic bench train``, ``benchmarks/train_speed.py``).

All timings are measured in the same process, single-threaded (numpy/BLAS and torch limited to
one thread), and printed as ratios. The torch baseline runs fewer epochs than the full schedule
and is extrapolated linearly (its cost per epoch is constant); the report says so.
"""

from __future__ import annotations

import os
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from mimic.learn.dataset import dataset_from_frame
from mimic.learn.presets import FAST, PAPER
from mimic.learn.train import TrainConfig, train_model, train_models
from mimic.model.network import LEAKY_SLOPE, Layout, init_params
from mimic.recording.layout import ENDED_COLUMN, TIME_COLUMN
from mimic.recording.paper_import import STUDY_ROBOT
from mimic.robot.model import RobotDescription
from mimic.robot.registry import DEFAULT_ROBOT, get_robot
from mimic.world.base import CYCLE_S

__all__ = ["BenchResult", "bench_train", "kick_dataset", "synthetic_dataset", "torch_baseline"]

_PAPER_DATA = Path(
    os.environ.get("MIMIC_PAPER_DATA")
    or Path(__file__).resolve().parents[4] / "shared" / "paper-data"
)


def _single_thread() -> None:
    # Tiny matrices: threads only add synchronisation (and the machine is shared).
    for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(var, "1")
    import torch

    torch.set_num_threads(1)


def synthetic_dataset(
    n: int = 77,
    seed: int = 0,
    name: str = "synthetic",
    robot: str | RobotDescription = DEFAULT_ROBOT,
):
    """A smooth motion of ``robot``'s N joints, ``n`` 20 ms samples (sums of sines), with the
    ended flag."""
    import polars as pl

    robot = get_robot(robot)
    shape = (3, robot.num_joints)  # three sines per joint
    rng = np.random.default_rng(seed)
    t = np.arange(n) * CYCLE_S
    amp, freq, ph = (
        rng.uniform(0.1, 0.8, shape),
        rng.uniform(0.3, 2.0, shape),
        rng.uniform(0, 6.3, shape),
    )
    q = (amp[:, None] * np.sin(2 * np.pi * freq[:, None] * t[None, :, None] + ph[:, None])).sum(0)
    frame = pl.DataFrame({TIME_COLUMN: t, **{j: q[:, i] for i, j in enumerate(robot.joint_names)}})
    return dataset_from_frame(frame, robot=robot, metadata={"motion": name})


def kick_dataset(path: Path | None = None):
    """The study's kick (``kick_itandroids.txt``) as a dataset, or None when absent.

    Parsed directly (columns: timestep, the NAO's joints, hasEnded); signs as in the file, which
    does not matter for fitting.
    """
    import polars as pl

    path = path or (_PAPER_DATA / "kick_itandroids.txt")
    if not path.is_file():
        return None
    robot = get_robot(STUDY_ROBOT)
    rows = [line.strip().split("::") for line in path.read_text().splitlines()[1:] if line.strip()]
    a = np.array(rows, dtype=float)
    n = robot.num_joints
    frame = pl.DataFrame(
        {
            TIME_COLUMN: a[:, 0],
            **{j: a[:, 1 + i] for i, j in enumerate(robot.joint_names)},
            ENDED_COLUMN: a[:, 1 + n],
        }
    )
    return dataset_from_frame(
        frame, robot=robot, metadata={"motion": "kick_itandroids", "source": str(path)}
    )


def torch_baseline(dataset, params0: np.ndarray, epochs: int, lr: float = 1e-3):
    """The straightforward loop: nn.Sequential + torch.optim.Adam, full batch, MSE.

    Starts from the same flat parameters as ours; returns (losses before each step, seconds).
    """
    import torch

    layout = Layout.for_joints(dataset.num_joints)
    w = layout.widths
    layers = []
    for i in range(len(w) - 1):
        layers.append(torch.nn.Linear(w[i], w[i + 1]))
        if i < len(w) - 2:
            layers.append(torch.nn.LeakyReLU(LEAKY_SLOPE))
    net = torch.nn.Sequential(*layers)
    with torch.no_grad():
        for lin, (w, b) in zip(net[::2], layout.layers(params0)):
            lin.weight.copy_(torch.from_numpy(w.T.copy()))
            lin.bias.copy_(torch.from_numpy(b))
    x = torch.tensor(dataset.time_s[:, None], dtype=torch.float32)
    y = torch.tensor(dataset.targets, dtype=torch.float32)
    opt = torch.optim.Adam(net.parameters(), lr=lr, betas=(0.9, 0.999), eps=1e-8)
    losses = np.empty(epochs)
    start = time.perf_counter()
    for e in range(epochs):
        opt.zero_grad()
        loss = torch.nn.functional.mse_loss(net(x), y)
        loss.backward()
        opt.step()
        losses[e] = loss.item()
    return losses, time.perf_counter() - start


@dataclass
class BenchResult:
    """Measured numbers (seconds are wall time in this process)."""

    baseline_epochs: int
    baseline_s_per_epoch: float
    paper_epochs: int
    paper_s: float
    paper_mae_rad: float
    fast_s: float
    fast_mae_rad: float
    batch_k: int
    batch_epochs: int
    sequential_s: float
    batched_s: float
    data: str
    # CPU seconds of this process for the same runs (the machine may be shared).
    paper_cpu_s: float = float("nan")
    fast_cpu_s: float = float("nan")

    @property
    def baseline_ratio(self) -> float:
        """Extrapolated baseline time for the full paper schedule / ours."""
        return self.baseline_s_per_epoch * self.paper_epochs / self.paper_s

    @property
    def batched_ratio(self) -> float:
        return self.sequential_s / self.batched_s

    def lines(self) -> list[str]:
        base_full = self.baseline_s_per_epoch * self.paper_epochs
        return [
            f"data: {self.data}",
            f"torch baseline: {self.baseline_epochs} epochs measured, "
            f"{self.baseline_s_per_epoch * 1e6:.0f} us/epoch -> {base_full:.1f} s for "
            f"{self.paper_epochs} epochs (extrapolated)",
            f"ours, paper preset ({self.paper_epochs} epochs): {self.paper_s:.2f} s wall "
            f"({self.paper_cpu_s:.2f} s CPU), MAE {self.paper_mae_rad:.4f} rad  -> "
            f"{self.baseline_ratio:.1f}x faster than baseline",
            f"ours, fast preset: {self.fast_s:.2f} s wall ({self.fast_cpu_s:.2f} s CPU), "
            f"MAE {self.fast_mae_rad:.4f} rad",
            f"{self.batch_k} motions x {self.batch_epochs} epochs: one after another "
            f"{self.sequential_s:.2f} s, batched {self.batched_s:.2f} s -> "
            f"{self.batched_ratio:.2f}x",
        ]


def bench_train(
    baseline_epochs: int = 2000, batch_k: int = 8, batch_epochs: int = 2000, seed: int = 0
) -> BenchResult:
    """Run the benchmark (about 10 s on an idle 2-core machine)."""
    _single_thread()

    ds = kick_dataset()
    data = "study kick (77 samples)"
    if ds is None:
        ds, data = synthetic_dataset(), "synthetic 77-sample motion (study data absent)"
    params0 = init_params(Layout.for_joints(ds.num_joints), np.random.default_rng(seed))
    _, base_s = torch_baseline(ds, params0, baseline_epochs)
    start, cpu = time.perf_counter(), time.process_time()
    paper = train_model(ds, TrainConfig(PAPER, seed=seed))
    paper_s, paper_cpu_s = time.perf_counter() - start, time.process_time() - cpu
    start, cpu = time.perf_counter(), time.process_time()
    fast = train_model(ds, TrainConfig(FAST, seed=seed))
    fast_s, fast_cpu_s = time.perf_counter() - start, time.process_time() - cpu
    many = [synthetic_dataset(60 + 5 * i, seed=i, name=f"m{i}") for i in range(batch_k)]
    cfg = TrainConfig(PAPER, seed=seed, epochs=batch_epochs)
    start = time.perf_counter()
    for d in many:
        train_model(d, cfg)
    seq_s = time.perf_counter() - start
    start = time.perf_counter()
    train_models(many, cfg)
    bat_s = time.perf_counter() - start
    return BenchResult(
        baseline_epochs,
        base_s / baseline_epochs,
        PAPER.epochs,
        paper_s,
        paper.metrics["mae_rad"],
        fast_s,
        fast.metrics["mae_rad"],
        batch_k,
        batch_epochs,
        seq_s,
        bat_s,
        data,
        paper_cpu_s,
        fast_cpu_s,
    )
