"""notebooks/reproduce_paper.ipynb runs top to bottom (with a small trial budget)."""

from pathlib import Path

import pytest

nbformat = pytest.importorskip("nbformat")
nbclient = pytest.importorskip("nbclient")
pytest.importorskip("ipykernel")

NOTEBOOK = Path(__file__).resolve().parents[1] / "notebooks" / "reproduce_paper.ipynb"


@pytest.mark.slow  # the whole paper pipeline: one kick episode alone may run 240 simulated s
def test_reproduce_paper_notebook_runs(tmp_path, monkeypatch):
    monkeypatch.setenv("MIMIC_PAPER_MINUTES", "0.3")
    monkeypatch.setenv("MIMIC_PAPER_OUT", str(tmp_path / "paper"))
    notebook = nbformat.read(NOTEBOOK, as_version=4)
    client = nbclient.NotebookClient(
        notebook,
        timeout=600,
        kernel_name="python3",
        resources={"metadata": {"path": str(tmp_path)}},
    )
    client.execute()
    outputs = [o for cell in notebook.cells if cell.cell_type == "code" for o in cell.outputs]
    text = "".join(
        str(o.get("data", {}).get("text/plain", "")) + o.get("text", "") for o in outputs
    )
    assert "study: ITAndroids kick" in text  # table 1 beside ours
    assert "study: learned" in text  # tables 2 and 3
    assert any("image/png" in o.get("data", {}) for o in outputs), "joint-curve figures"
    assert (tmp_path / "paper" / "kick_trial.parquet").exists()
    assert (tmp_path / "paper" / "walk_trial.parquet").exists()
