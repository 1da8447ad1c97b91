"""Training curves in Rerun: loss (MSE) and mean absolute joint error per motion, on an
``epoch`` sequence timeline, with the learning-rate phase as its own scalar.

Entities: ``training/<motion>/loss_mse``, ``training/<motion>/mae_rad``,
``training/<motion>/phase``. Points are buffered and sent with ``rr.send_columns`` in chunks
(one call per motion and series), so logging costs nothing noticeable next to training.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from mimic.files import PendingOutput

__all__ = ["TrainingCurves"]


class TrainingCurves:
    """A ``progress`` callback for ``mimic.learn.train.train_models`` that streams to Rerun.

    Args:
        spawn: open (or connect to) a Rerun viewer.
        save_rrd: also/instead write the stream to this ``.rrd`` file (under a temporary name
            until ``close``; ``discard`` removes it: ``mimic.files``).
        flush_every: send buffered points after this many reports.
        overwrite: replace an existing ``save_rrd`` on ``close`` (False: refuse then).
    """

    def __init__(
        self,
        *,
        spawn: bool = False,
        save_rrd: str | Path | None = None,
        flush_every: int = 20,
        application_id: str = "mimic_train",
        overwrite: bool = True,
    ) -> None:
        import rerun as rr

        self._rr = rr
        self.rec = rr.RecordingStream(application_id)
        self._pending = None
        if spawn:
            self.rec.spawn()
        if save_rrd is not None:
            self._pending = PendingOutput(save_rrd, overwrite=overwrite)
            self.rec.save(str(self._pending.tmp))
        self.flush_every = flush_every
        self._buf: dict[str, dict[str, list]] = {}
        self._reports = 0

    def __call__(self, p) -> None:
        """Record one ``TrainProgress`` report."""
        for i, name in enumerate(p.names):
            b = self._buf.setdefault(name, {"epoch": [], "loss": [], "mae": [], "phase": []})
            b["epoch"].append(p.epoch)
            b["loss"].append(float(p.loss[i]))
            b["mae"].append(float(p.mae_rad[i]))
            b["phase"].append(float(p.phase))
        self._reports += 1
        if self._reports % self.flush_every == 0:
            self.flush()

    def flush(self) -> None:
        """Send what is buffered."""
        rr = self._rr
        for name, b in self._buf.items():
            if not b["epoch"]:
                continue
            index = [rr.TimeColumn("epoch", sequence=np.asarray(b["epoch"], dtype=np.int64))]
            for series, key in (("loss_mse", "loss"), ("mae_rad", "mae"), ("phase", "phase")):
                rr.send_columns(
                    f"training/{name}/{series}",
                    indexes=index,
                    columns=rr.Scalars.columns(scalars=np.asarray(b[key])),
                    recording=self.rec,
                )
            for v in b.values():
                v.clear()

    def close(self) -> None:
        """Flush and finish the stream (the .rrd file is complete and in place afterwards)."""
        self.flush()
        self.rec.flush()
        self.rec.disconnect()
        if self._pending is not None:
            self._pending.commit()

    def discard(self) -> None:
        """Stop the stream and remove the unfinished .rrd file (training failed)."""
        self.rec.disconnect()
        if self._pending is not None:
            self._pending.discard()
