"""Record every own-team motion into recordings/<name>.mcap (small files, seeded).

python scripts/make_recordings.py            # all shipped motions
python scripts/make_recordings.py stand kick_right
"""

from __future__ import annotations

import sys
from pathlib import Path

from mimic.motion.files import list_motions
from mimic.recording.recorder import RecordConfig, record

OUT_DIR = Path(__file__).resolve().parents[1] / "recordings"
#: Files above this size are recorded again with /tf at half rate [bytes].
MAX_BYTES = 900_000
#: Motions recorded for a fixed time instead of until they end [s].
DURATIONS_S = {"stand": 3.0}


def make_recording(name: str, out_dir: Path = OUT_DIR) -> Path:
    """Record one motion; returns the file path."""
    path = out_dir / f"{name}.mcap"
    for tf_every in (1, 2, 4):
        record(
            name,
            path,
            duration_s=DURATIONS_S.get(name),
            seed=0,
            config=RecordConfig(tf_every=tf_every),
        )
        if path.stat().st_size <= MAX_BYTES:
            break
    return path


def main(names: list[str]) -> None:
    for name in names or list_motions():
        path = make_recording(name)
        print(f"{path}: {path.stat().st_size / 1000:.0f} kB")


if __name__ == "__main__":
    main(sys.argv[1:])
