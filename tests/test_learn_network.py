"""The hand-written trainer is torch's algorithm, reproducible, batched-consistent, and learns."""

import numpy as np
import pytest
from _learn_helpers import NAO, joint_frame, smooth_motion

from mimic.learn.bench import torch_baseline
from mimic.learn.dataset import dataset_from_frame
from mimic.learn.presets import FAST, PAPER
from mimic.learn.train import TrainConfig, train_model, train_models
from mimic.model.network import AdamTrainer, Layout, init_params


@pytest.fixture(scope="module")
def motion():
    t, q = smooth_motion(50)
    return dataset_from_frame(joint_frame(t, q), metadata={"motion": "wave"})


def test_paper_network_has_5123_parameters():
    assert Layout.for_joints(NAO.num_joints, in_dim=1).n_params == 5123
    assert Layout.for_joints(NAO.num_joints, in_dim=2).n_params == 5123 + 75
    assert Layout.for_joints(NAO.num_joints).out_dim == 23


def test_numpy_trainer_matches_torch_adam(motion):
    torch = pytest.importorskip("torch")
    torch.manual_seed(0)
    layout = Layout.for_joints(motion.num_joints)
    p0 = init_params(layout, np.random.default_rng(3))
    epochs = 300
    torch_losses, _ = torch_baseline(motion, p0, epochs, lr=1e-3)
    tr = AdamTrainer(
        layout,
        p0[None],
        motion.time_s[None, :, None],
        motion.targets[None],
        np.array([motion.n_samples]),
    )
    ours = []
    for _ in range(epochs):
        ours.append(tr.mse()[0])  # loss before the step, as torch reports it
        tr.run(1, 1e-3)
    ours = np.array(ours)
    assert ours[-1] < 0.5 * ours[0]
    np.testing.assert_allclose(ours, torch_losses, rtol=2e-3, atol=1e-6)


def test_same_seed_same_weights_and_different_seed_differs(motion):
    cfg = TrainConfig(FAST, seed=7, epochs=200)
    a, b = train_model(motion, cfg), train_model(motion, cfg)
    c = train_model(motion, TrainConfig(FAST, seed=8, epochs=200))
    assert np.array_equal(a.params, b.params)
    assert not np.array_equal(a.params, c.params)


def test_training_reduces_error_tenfold(motion):
    short = train_model(motion, TrainConfig(FAST, seed=0, epochs=1))
    longer = train_model(motion, TrainConfig(FAST, seed=0, epochs=600))
    assert longer.metrics["mae_rad"] < 0.1 * short.metrics["mae_rad"]
    assert longer.metrics["ended_accuracy"] >= 0.9


def test_batched_training_matches_one_at_a_time():
    sets = []
    for seed, n in ((0, 30), (1, 45), (2, 38)):  # ragged sample counts
        t, q = smooth_motion(n, seed)
        sets.append(dataset_from_frame(joint_frame(t, q), metadata={"motion": f"m{seed}"}))
    cfg = TrainConfig(PAPER, seed=1, epochs=150)
    together = train_models(sets, cfg)
    for d, m in zip(sets, together):
        alone = train_model(d, cfg)
        np.testing.assert_allclose(m.params, alone.params, rtol=1e-4, atol=1e-5)
        assert m.name == d.name
