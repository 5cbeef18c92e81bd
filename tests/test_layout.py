"""The package layout: old module paths still import (with a warning) and nothing of ours uses them."""

import importlib
import subprocess
import sys
from pathlib import Path

import pytest

import reciprocity

#: Old path -> (new path, a public name both must give as the same object).
MOVED = {
    "reciprocity.mesh": ("reciprocity.fem.mesh", "mesh_free_region"),
    "reciprocity.green": ("reciprocity.fem.green", "GreenSolver"),
    "reciprocity.exact": ("reciprocity.fem.exact", "disk_green"),
    "reciprocity.car_platform": ("reciprocity.platforms.car", "CarPlatform"),
    "reciprocity.lattice_platform": ("reciprocity.platforms.lattice", "LatticePlatform"),
    "reciprocity.figures": ("reciprocity.viz.figures", "imaging_steps_figure"),
    "reciprocity.video": ("reciprocity.viz.video", "write_video"),
}


def _forget(name: str) -> None:
    """Drop module `name` from the import system, so that importing it runs it again."""
    sys.modules.pop(name, None)
    parent, _, child = name.rpartition(".")
    if hasattr(sys.modules[parent], child):
        delattr(sys.modules[parent], child)


@pytest.mark.parametrize("old", sorted(MOVED))
def test_old_path_warns_and_gives_the_new_objects(old):
    new, name = MOVED[old]
    _forget(old)
    with pytest.warns(DeprecationWarning, match=rf"{old} is deprecated.*import {new} instead"):
        mod = importlib.import_module(old)
    assert getattr(mod, name) is getattr(importlib.import_module(new), name)


def test_readme_names_resolve_through_the_old_paths():
    _forget("reciprocity.car_platform")
    with pytest.warns(DeprecationWarning):
        from reciprocity.car_platform import CAR_KEYS, CarPlatform
    from reciprocity.platforms.car import CAR_KEYS as keys, CarPlatform as car
    assert CAR_KEYS is keys and CarPlatform is car


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
                         capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
