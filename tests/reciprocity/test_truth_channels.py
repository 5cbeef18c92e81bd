"""Truth stays on the truth's side: each test fails if a channel to the strategy reopens."""

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from reciprocity.api import execute
from reciprocity.worlds.poisson import truth_solver

ROOT = Path(__file__).resolve().parents[2]


def test_the_truth_never_shares_a_solver_with_a_strategy():
    """Even at the truth's own mesh size the strategy's solver, mesh and factorization are
    its own: the data never come from the very model that inverts them."""
    h = 3.0
    episode, strategy, _ = execute("paper", "reciprocity", seed=1, params={"h": h, "max_steps": 2},
                                   world={"truth_h": h})
    truth = truth_solver(strategy.solver.arena.without_scenario(), h)
    assert truth.arena.boundary.tolist() == strategy.solver.arena.boundary.tolist()   # the same walls, and yet
    assert strategy.solver is not truth
    assert strategy.solver.mesh is not truth.mesh
    assert strategy.solver._lu is not truth._lu


def test_the_layer_contracts_hold_without_exceptions():
    """import-linter's contracts (pyproject.toml): belief never imports truth, truth never
    imports belief, numerics at the bottom; none may list an ignored import."""
    text = (ROOT / "pyproject.toml").read_text()
    assert "ignore_imports" not in text, "a contract has an exception again"
    exe = shutil.which("lint-imports", path=str(Path(sys.executable).parent)) or shutil.which("lint-imports")
    if exe is None:
        pytest.skip("import-linter is not installed")
    done = subprocess.run([exe], cwd=ROOT, capture_output=True, text=True)
    assert done.returncode == 0, done.stdout[-3000:]
    assert "0 broken" in done.stdout
