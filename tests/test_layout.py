"""The package layout: the new homes of moved modules, and nothing left at the old paths."""

import ast
import importlib
import re
import subprocess
import sys
from pathlib import Path

import pytest

import reciprocity

#: A safety net against a hung subprocess, never the assertion (the work is bounded; minutes).
HANG_S = 300

#: Old path -> (new path, a public name the new path gives).
MOVED = {
    "reciprocity.mesh": ("reciprocity.fem.mesh", "mesh_free_region"),
    "reciprocity.green": ("reciprocity.fem.green", "GreenSolver"),
    "reciprocity.exact": ("reciprocity.fem.exact", "disk_green"),
    "reciprocity.car_platform": ("reciprocity.platforms.car", "CarPlatform"),
    "reciprocity.lattice_platform": ("reciprocity.platforms.lattice", "LatticePlatform"),
    "reciprocity.figures": ("reciprocity.viz.figures", "imaging_steps_figure"),
    "reciprocity.video": ("reciprocity.viz.video", "write_video"),
    "reciprocity.beliefs.occupancy": ("reciprocity.spaces.occupancy", "OccupancyGrid"),
    "reciprocity.kinds": ("reciprocity.wiring", "POISSON"),
    "reciprocity.strategies.reciprocal": ("reciprocity.strategies.reciprocity", "ReciprocityStrategy"),
    "reciprocity.strategies.plume_imaging": ("reciprocity.strategies.plume_reciprocity", "PlumeImaging"),
    "reciprocity.strategies.hmm_search": ("reciprocity.strategies.hmm", "HMMSearch"),
    "reciprocity.strategies.wind_reciprocity": ("reciprocity.strategies.reciprocity_wind", "WindReciprocity"),
    "reciprocity.strategies.wind_infotaxis": ("reciprocity.strategies.infotaxis_wind", "WindInfotaxis"),
    "reciprocity.strategies.wind_surge_cast": ("reciprocity.strategies.surge_cast_wind", "SurgeCastWind"),
}

#: Strategy modules that hold a family not named after its first member, and why.
FAMILY_MODULES = {"reward_infotaxis": "infotaxis-ii and infotaxis-iii: infotaxis with a reward other than entropy"}


@pytest.mark.parametrize("old", sorted(MOVED))
def test_old_paths_are_gone(old):
    """The deprecated aliases were removed after one release (CHANGELOG.md)."""
    with pytest.raises(ModuleNotFoundError):
        importlib.import_module(old)
    new, name = MOVED[old]
    assert getattr(importlib.import_module(new), name) is not None


def test_platforms_module_became_the_package_with_its_names():
    import reciprocity.platforms as platforms
    from reciprocity.platforms import base, car, lattice, point, walker

    assert platforms.Platform is base.Platform and platforms.PointPlatform is point.PointPlatform
    assert platforms.WalkerPlatform is walker.WalkerPlatform
    assert platforms.gradient_sample_points is point.gradient_sample_points
    assert platforms.CarPlatform is car.CarPlatform and platforms.LatticePlatform is lattice.LatticePlatform


@pytest.mark.parametrize("package, modules", [("fem", ("mesh", "green", "exact")),
                                              ("platforms", ("base", "point", "walker", "lattice", "car"))])
def test_new_packages_re_export_their_modules_names(package, modules):
    pkg = importlib.import_module(f"reciprocity.{package}")
    for m in modules:
        mod = importlib.import_module(f"reciprocity.{package}.{m}")
        missing = set(mod.__all__) - set(pkg.__all__)
        assert not missing, f"reciprocity.{package} does not re-export {sorted(missing)} of {m}"
        assert all(getattr(pkg, n) is getattr(mod, n) for n in mod.__all__)


def test_no_module_of_the_package_imports_an_old_path():
    # every module of the package, imported with deprecation warnings as errors
    code = (
        "import importlib, pkgutil, sys, reciprocity, reciprocity.cli, reciprocity.api\n"
        f"old = {sorted(MOVED)!r}\n"
        "for m in pkgutil.walk_packages(reciprocity.__path__, 'reciprocity.'):\n"
        "    if m.name not in old:\n"
        "        importlib.import_module(m.name)\n"
        "assert not set(old) & set(sys.modules), sorted(set(old) & set(sys.modules))\n"
    )
    root = Path(reciprocity.__file__).resolve().parents[1]
    out = subprocess.run([sys.executable, "-W", "error::DeprecationWarning", "-c", code], cwd=root,
                         capture_output=True, text=True, timeout=HANG_S)
    assert out.returncode == 0, out.stderr[-2000:]


#: What a measured result looks like in prose: a date, a rate with its interval, "k of n",
#: "n× faster", "median 3", "0.4 s per ...", "20 runs", "seeds 0-19".
MEASURED = re.compile(
    r"20\d\d-\d\d-\d\d"
    r"|\d(\.\d+)? ?%? \[-?\d+(\.\d+)?, -?\d+(\.\d+)?\]"
    r"|\b\d+ of \d+\b"
    r"|\d(\.\d+)? ?[×x] (faster|slower|shorter|longer)|times (faster|slower)"
    r"|\b(median|rms|percentile|mean)( error)? \d"
    r"|\d(\.\d+)? ?(ms|s) (per|at|against|to build)\b|~\d(\.\d+)? ?ms"
    r"|\bruns per\b|\b\d+ runs\b|seeds \d+ ?[-–]\d")


def _docstrings(tree):
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            doc = ast.get_docstring(node, clean=False)
            if doc:
                yield node, doc


def test_package_docstrings_hold_no_measured_results():
    """Measurements live in benchmarks/*.md and docs/, where a re-run rewrites them; a
    docstring says what the code does (issue 37)."""
    root = Path(reciprocity.__file__).resolve().parents[1]
    found = []
    for package in ("reciprocity", "arenas", "hjplanner"):
        for path in sorted((root / package).rglob("*.py")):
            for node, doc in _docstrings(ast.parse(path.read_text())):
                found += [f"{path.relative_to(root)} ({getattr(node, 'name', 'module')}): {line.strip()}"
                          for line in doc.splitlines() if MEASURED.search(line)]
    assert found == []


def test_every_strategy_module_is_named_after_the_strategy_it_holds():
    """A registered name is its module's name with ``-`` for ``_``, or a family's module is
    named after its first member (the glossary's *registered name*)."""
    from reciprocity.strategies import STRATEGIES
    firsts: dict[str, str] = {}
    for name, cls in STRATEGIES.items():
        module = cls.__module__.rsplit(".", 1)[1]
        firsts.setdefault(module, name)
    wrong = {module: first for module, first in firsts.items()
             if module.replace("_", "-") != first and module not in FAMILY_MODULES}
    assert not wrong, f"modules not named after their first strategy: {wrong}"
    assert set(FAMILY_MODULES) <= set(firsts)
