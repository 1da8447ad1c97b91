"""The motion network and its hand-written, batched, full-batch Adam trainer (numpy).

The network is the study's: input -> Dense 75 -> LeakyReLU(0.3) -> Dense 50 -> LeakyReLU(0.3)
-> Dense N + 1 (the robot's N joint angles [rad] + the ended flag). With one input (time) it
has 1*75+75 + 75*50+50 + 50*(N+1)+(N+1) parameters, 5123 for our NAO; a cyclic motion's phase
input (sin, cos) adds 75.

Why hand-written: a full-batch epoch on ~77 samples is ~3 small matrix products forward and
~4 backward; in torch each of the ~40 tiny kernels and the autograd bookkeeping costs more than
the arithmetic. Here one epoch is ~27 numpy calls writing into preallocated buffers:

* every layer keeps its bias as the last column of an augmented matrix (fan_out, fan_in + 1)
  and every layer input carries a constant row of ones, so the forward product includes the
  bias and the weight-gradient product includes the bias gradient (no separate add or sum);
  activations are feature-major (features, samples) so each layer writes a contiguous block;
* the LeakyReLU slope mask (1 or 0.3) is built with a float compare, not ``np.where`` (4x
  cheaper on these sizes), and reused by the backward pass;
* all parameters live in one flat float32 buffer per model (K models stacked as (K, P)), the
  gradients in another with the same layout, so Adam is ~10 whole-buffer ufunc calls;
* Adam's (1 - beta1) factor is folded into the loss-gradient scale and the second moment is
  stored divided by (1 - beta2)/(1 - beta1)^2, with the constants moved into the step size: the
  same update as ``torch.optim.Adam`` (checked in tests/test_learn_network.py against torch
  for a few hundred epochs from the same initial weights), fewer passes over memory;
* K models train at once with batched matmul; models with fewer samples are zero-padded and
  their padded rows get zero loss gradient (the per-row scale is 0), so each model follows
  exactly the trajectory it would follow alone.

Arrays are float32 (as in Keras and torch by default).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

__all__ = ["LEAKY_SLOPE", "HIDDEN_UNITS", "Layout", "init_params", "forward", "AdamTrainer"]

#: LeakyReLU slope for negative inputs (Keras' default, the study's setting).
LEAKY_SLOPE = 0.3
#: Hidden layer widths (the study's).
HIDDEN_UNITS = (75, 50)
_F = np.float32
#: Layer inputs at least this wide get a sample-major copy for the weight gradient (the
#: 76-wide second layer gains 2.5 us per epoch; the 51-wide third loses).
_COPY_MIN_WIDTH = 60


@dataclass(frozen=True)
class Layout:
    """Shapes of the network's layers; parameters are one flat vector in this order.

    Each layer is an augmented matrix of shape (fan_out, fan_in + 1), row-major: columns
    0..fan_in-1 are the weights (output = W @ input), the last column the bias.
    """

    # Number of outputs: N joint angles + the ended flag (see ``for_joints``). Keyword-only
    # and without a default: it comes from the robot, never from a constant.
    out_dim: int = field(kw_only=True)
    # Number of network inputs (1: time; 2: sin and cos of the phase).
    in_dim: int = 1
    # Hidden layer widths.
    hidden: tuple[int, ...] = HIDDEN_UNITS

    @classmethod
    def for_joints(cls, num_joints: int, in_dim: int = 1) -> Layout:
        """The study's network for a robot with ``num_joints`` joints: N angles + the flag."""
        return cls(out_dim=num_joints + 1, in_dim=in_dim)

    @property
    def num_joints(self) -> int:
        """N: outputs before the ended flag."""
        return self.out_dim - 1

    @property
    def widths(self) -> tuple[int, ...]:
        return (self.in_dim, *self.hidden, self.out_dim)

    @property
    def shapes(self) -> tuple[tuple[int, int], ...]:
        """(fan_out, fan_in + 1) of each augmented layer matrix."""
        w = self.widths
        return tuple((w[i + 1], w[i] + 1) for i in range(len(w) - 1))

    @property
    def offsets(self) -> tuple[int, ...]:
        """Start of each layer in the flat parameter vector (plus the total at the end)."""
        out = [0]
        for r, c in self.shapes:
            out.append(out[-1] + r * c)
        return tuple(out)

    @property
    def n_params(self) -> int:
        return self.offsets[-1]

    def views(self, flat: np.ndarray) -> list[np.ndarray]:
        """Views of a (..., P) parameter array as (..., fan_out, fan_in + 1) layer matrices."""
        lead = flat.shape[:-1]
        o = self.offsets
        return [flat[..., o[i] : o[i + 1]].reshape(*lead, *s) for i, s in enumerate(self.shapes)]

    def layers(self, flat: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
        """Per layer (W (fan_in, fan_out), b (fan_out,)) copies, the usual ``x @ W + b`` form."""
        return [(np.ascontiguousarray(m[:, :-1].T), m[:, -1].copy()) for m in self.views(flat)]


def init_params(
    layout: Layout, rng: np.random.Generator, init: str = "glorot_uniform", knot_range: float = 1.0
) -> np.ndarray:
    """A (P,) float32 parameter vector: weights drawn per layer, biases zero.

    ``glorot_uniform`` (Keras' default): U(-a, a), a = sqrt(6 / (fan_in + fan_out)).
    ``he_uniform``: U(-a, a), a = sqrt(6 / fan_in) (scaled for the LeakyReLU's gain).
    ``he_knots``: he_uniform weights; with a single input, the first layer's biases put each
    unit's kink (where w x + b = 0) at evenly spaced points of [-r, r] (r = ``knot_range``, the
    scaled input range)
    instead of all at x = 0, so the piecewise-linear fit starts with breakpoints everywhere.
    """
    flat = np.zeros(layout.n_params, dtype=_F)
    for m in layout.views(flat):
        fan_out, fan_in = m.shape[0], m.shape[1] - 1
        if init == "glorot_uniform":
            a = np.sqrt(6.0 / (fan_in + fan_out))
        elif init in ("he_uniform", "he_knots"):
            a = np.sqrt(6.0 / fan_in)
        else:
            raise ValueError(f"unknown init {init!r}; use glorot_uniform, he_uniform or he_knots")
        # Drawn in (fan_in, fan_out) order, as Keras stores a Dense kernel.
        m[:, :-1] = rng.uniform(-a, a, size=(fan_in, fan_out)).T
    first = layout.views(flat)[0]
    if init == "he_knots" and layout.in_dim == 1:
        knots = np.linspace(-knot_range, knot_range, first.shape[0])
        first[:, -1] = -first[:, 0] * rng.permutation(knots)
    return flat


def forward(params: np.ndarray, x: np.ndarray, layout: Layout) -> np.ndarray:
    """Network output (N, out_dim) for inputs x (N, in_dim); params (P,). float64 arithmetic."""
    h = np.asarray(x, dtype=np.float64)
    layers = layout.layers(np.asarray(params, dtype=np.float64))
    for i, (w, b) in enumerate(layers):
        h = h @ w + b
        if i < len(layers) - 1:
            h = np.where(h > 0, h, LEAKY_SLOPE * h)
    return h


class AdamTrainer:
    """Full-batch Adam on K networks at once, minimising each one's mean squared error.

    Args:
        layout: the network shape.
        params: (K, P) initial parameters (copied).
        x: (K, N, in_dim) inputs; y: (K, N, out_dim) targets (N = the largest sample count).
        n_samples: (K,) number of valid rows per model (rows beyond are padding).
        betas, eps: Adam's constants (torch's update rule: eps added to sqrt(v_hat)).
    """

    def __init__(
        self,
        layout: Layout,
        params: np.ndarray,
        x: np.ndarray,
        y: np.ndarray,
        n_samples: np.ndarray,
        betas: tuple[float, float] = (0.9, 0.999),
        eps: float = 1e-8,
    ) -> None:
        k, n = x.shape[0], x.shape[1]
        self.layout, self.k, self.n = layout, k, n
        self.beta1, self.beta2, self.eps = betas[0], betas[1], eps
        self.params = np.array(params, dtype=_F).reshape(k, layout.n_params)
        self.grad = np.zeros_like(self.params)
        self.m = np.zeros_like(self.params)
        self.w = np.zeros_like(self.params)  # v / c, c = (1 - b2) / (1 - b1)^2
        self.tmp = np.zeros_like(self.params)
        self.mats = layout.views(self.params)
        self.gmats = layout.views(self.grad)
        self.n_samples = np.asarray(n_samples, dtype=np.int64).reshape(k)
        valid = np.arange(n)[None, :] < self.n_samples[:, None]  # (K, N)
        self.valid = valid
        # d(MSE)/dy, times (1 - b1) for the folded Adam first moment; zero on padding rows.
        self.grad_scale = (
            valid * ((1.0 - self.beta1) * 2.0 / (self.n_samples[:, None] * layout.out_dim))
        ).astype(_F)[..., None]
        widths = layout.widths
        # Layer inputs, feature-major (K, features + 1, N), with a last row of ones (bias).
        self.acts = [np.ones((k, w + 1, n), dtype=_F) for w in widths[:-1]]
        self.acts[0][:, :-1, :] = np.transpose(x, (0, 2, 1))
        self.pre = [np.zeros((k, w, n), dtype=_F) for w in widths[1:]]
        self.slopes = [np.zeros((k, w, n), dtype=_F) for w in widths[1:-1]]
        self.delta = [np.zeros((k, w, n), dtype=_F) for w in widths[1:]]
        self.y = np.ascontiguousarray(np.transpose(np.asarray(y, dtype=_F), (0, 2, 1)))
        self.grad_scale = np.ascontiguousarray(np.transpose(self.grad_scale, (0, 2, 1)))
        self.step_count = 0
        self._c = (1.0 - self.beta2) / (1.0 - self.beta1) ** 2
        self._build_program()

    def reset_optimizer(self) -> None:
        """Zero Adam's moments and step count (the study resets them at each LR phase)."""
        self.m.fill(0.0)
        self.w.fill(0.0)
        self.step_count = 0

    def _build_program(self) -> None:
        """Precompute every view the epoch touches (view creation costs as much as a tiny op)."""
        n_layers = len(self.mats)
        self._fwd = [
            (
                self.mats[i],
                self.acts[i],
                self.pre[i],
                self.slopes[i] if i < n_layers - 1 else None,
                self.acts[i + 1][:, :-1, :] if i < n_layers - 1 else None,
            )
            for i in range(n_layers)
        ]
        # BLAS multiplies delta @ acts^T (inner dimension: the samples) ~1.6x slower through a
        # transposed view than from a sample-major copy, and for wide layers the copy costs
        # less than it saves (measured: 10.5 us vs 6.5 + 2.4 us for the 50 x 76 layer; see ``_COPY_MIN_WIDTH``).
        copies = [
            np.empty((self.k, self.n, a.shape[1]), dtype=_F)
            if a.shape[1] >= _COPY_MIN_WIDTH
            else None
            for a in self.acts
        ]
        self._bwd = [
            (
                self.delta[i],
                copies[i] if copies[i] is not None else self.acts[i].transpose(0, 2, 1),
                self.gmats[i],
                self.mats[i][:, :, :-1].transpose(0, 2, 1) if i > 0 else None,
                self.delta[i - 1] if i > 0 else None,
                self.slopes[i - 1] if i > 0 else None,
                self.acts[i].transpose(0, 2, 1) if copies[i] is not None else None,
            )
            for i in range(n_layers - 1, -1, -1)
        ]

    def _forward(self) -> np.ndarray:
        # Python floats, not np.float32 scalars: numpy keeps float32 either way (NEP 50) and
        # a Python scalar operand is ~2x cheaper per call on these sizes.
        keep, slope = 1.0 - LEAKY_SLOPE, LEAKY_SLOPE
        for m, a, h, s, a_next in self._fwd:
            np.matmul(m, a, out=h)
            if s is not None:
                # s = 1 where h > 0 else slope (torch's and TF's LeakyReLU gradient at 0).
                np.greater(h, 0.0, out=s, casting="unsafe")
                s *= keep
                s += slope
                np.multiply(h, s, out=a_next)
        return self.pre[-1]

    def _backward(self) -> None:
        d = self.delta[-1]
        np.subtract(self.pre[-1], self.y, out=d)
        d *= self.grad_scale
        for delta, a_t, g, m_t, prev, s, a_view in self._bwd:
            if a_view is not None:
                np.copyto(a_t, a_view)
            np.matmul(delta, a_t, out=g)
            if m_t is not None:
                np.matmul(m_t, delta, out=prev)
                prev *= s

    def _adam_step(self, lr: float) -> None:
        b1, b2 = self.beta1, self.beta2
        self.step_count += 1
        t = self.step_count
        bc1, bc2 = 1.0 - b1**t, 1.0 - b2**t
        root = math.sqrt(bc2 / self._c)
        g, m, w, tmp = self.grad, self.m, self.w, self.tmp
        m *= b1
        m += g  # g already carries the (1 - b1) factor
        np.multiply(g, g, out=g)
        w *= b2
        w += g
        # torch: p -= lr/bc1 * m / (sqrt(v)/sqrt(bc2) + eps), with v = c * w
        np.sqrt(w, out=tmp)
        tmp += self.eps * root
        np.divide(m, tmp, out=tmp)
        tmp *= lr / bc1 * root
        self.params -= tmp

    def run(self, epochs: int, lr: float, *, callback=None, every: int = 0) -> None:
        """Train ``epochs`` full-batch steps at learning rate ``lr``.

        ``callback(epoch_done)`` is called every ``every`` epochs (0: never) — use it for
        progress and loss curves; computing the loss is not part of the epoch.
        """
        for e in range(1, epochs + 1):
            self._forward()
            self._backward()
            self._adam_step(lr)
            if every and callback is not None and (e % every == 0 or e == epochs):
                callback(e)

    def predict(self) -> np.ndarray:
        """(K, N, out_dim) outputs of the current parameters on the training inputs."""
        return np.transpose(self._forward(), (0, 2, 1)).copy()

    def mse(self) -> np.ndarray:
        """(K,) mean squared error of each model over its valid rows and all outputs."""
        err = (self._forward() - self.y).astype(np.float64) ** 2  # (K, out, N)
        return (err.sum(axis=1) * self.valid).sum(axis=1) / (self.n_samples * self.layout.out_dim)
