"""Training speed: numpy trainer vs the straightforward torch loop; batched vs sequential.

Run: python benchmarks/train_speed.py   (same as `mimic bench train`)
"""

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # before numpy loads: tiny matrices

from mimic.learn.bench import bench_train  # noqa: E402

if __name__ == "__main__":
    for line in bench_train().lines():
        print(line)
