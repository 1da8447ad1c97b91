"""The layers of CONTRIBUTING.md hold: import-linter's contracts (``[tool.importlinter]`` in
pyproject.toml) pass on the package, and fail once one upward import is planted in a copy."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "toolkit" / "mimic"


def _lint(package_parent: Path, config: Path) -> subprocess.CompletedProcess:
    lint = shutil.which("lint-imports", path=str(Path(sys.executable).parent))
    if lint is None:
        pytest.fail("lint-imports is missing: pip install -e '.[test]'")
    env = dict(os.environ, PYTHONPATH=str(package_parent))
    return subprocess.run(
        [lint, "--config", str(config), "--no-cache"],
        cwd=package_parent,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )


def test_the_import_contracts_hold():
    done = _lint(PACKAGE.parent, ROOT / "pyproject.toml")
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    assert "0 broken" in done.stdout


@pytest.mark.parametrize(
    ("module", "planted", "contract"),
    [
        ("agents/hold.py", "import mimic.trials.report", "data flows one way"),
        ("learn/steps.py", "import mimic.agents.registry", "learn reads recordings"),
        # The league's wire sits below the worlds: the worlds use it, never the other way.
        ("league/decode.py", "import mimic.world.base", "data flows one way"),
        # Inside a function counts too: no dodging the contract by importing late.
        ("model/motion_model.py", "def _late():\n    import mimic.learn.train", "one way"),
    ],
)
def test_an_upward_import_breaks_a_contract(tmp_path, module, planted, contract):
    copy = tmp_path / "toolkit"
    shutil.copytree(PACKAGE, copy / "mimic", ignore=shutil.ignore_patterns("__pycache__"))
    with (copy / "mimic" / module).open("a") as f:
        f.write(f"\n\n{planted}  # planted\n")
    done = _lint(copy, ROOT / "pyproject.toml")
    assert done.returncode != 0, done.stdout[-3000:]
    broken = done.stdout[done.stdout.index("Broken contracts") :]
    assert contract in broken and "planted" not in done.stderr
