"""The package declaration ships what the code needs, without building a wheel.

``.ci/wheel-check`` builds and installs the wheel and runs the commands (minutes); these
checks read ``pyproject.toml`` and the tree (milliseconds), so a data file added without its
``[tool.setuptools.package-data]`` glob fails here first: an editable install reads it from
the source tree and would never notice.
"""

from __future__ import annotations

import fnmatch
import tomllib
from pathlib import Path, PurePosixPath

import pytest

ROOT = Path(__file__).resolve().parents[1]
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())
SETUPTOOLS = PYPROJECT["tool"]["setuptools"]
PACKAGE_DATA: dict[str, list[str]] = SETUPTOOLS["package-data"]
TOP_LEVEL = ("arenas", "hjplanner", "reciprocity")


def _matches(relative: PurePosixPath, pattern: str) -> bool:
    """setuptools' glob: ``*`` stays within one folder, so compare part by part."""
    parts = PurePosixPath(pattern).parts
    return len(parts) == len(relative.parts) and all(map(fnmatch.fnmatchcase, relative.parts, parts))


def _data_files(package: str) -> list[PurePosixPath]:
    """Every file of a top-level package that is not Python source or a cache, relative to it."""
    top = ROOT / package
    return sorted(PurePosixPath(p.relative_to(top).as_posix()) for p in top.rglob("*")
                  if p.is_file() and p.suffix not in (".py", ".pyc")
                  and not any(part == "__pycache__" or part.startswith(".") for part in p.relative_to(top).parts))


@pytest.mark.parametrize("package", TOP_LEVEL)
def test_every_data_file_is_declared(package):
    globs = PACKAGE_DATA.get(package, [])
    missing = [str(f) for f in _data_files(package) if not any(_matches(f, g) for g in globs)]
    assert not missing, (f"{package}: files not in [tool.setuptools.package-data] {package} = {globs}, "
                         f"so the wheel would lack them: {missing}")


@pytest.mark.parametrize("package", TOP_LEVEL)
def test_every_package_data_glob_finds_a_file(package):
    files = _data_files(package)
    stale = [g for g in PACKAGE_DATA.get(package, []) if not any(_matches(f, g) for f in files)]
    assert not stale, f"{package}: package-data globs that match nothing: {stale}"


@pytest.mark.parametrize("package", TOP_LEVEL)
def test_each_package_is_typed(package):
    """PEP 561: the marker file exists and is shipped."""
    assert (ROOT / package / "py.typed").is_file()
    assert "py.typed" in PACKAGE_DATA.get(package, [])


def test_every_python_folder_is_a_found_package():
    """Each folder with Python modules has an ``__init__.py`` and matches packages.find's include."""
    include = SETUPTOOLS["packages"]["find"]["include"]
    folders = {p.parent for top in TOP_LEVEL for p in (ROOT / top).rglob("*.py") if "__pycache__" not in p.parts}
    bad = []
    for folder in sorted(folders):
        dotted = ".".join(folder.relative_to(ROOT).parts)
        if not (folder / "__init__.py").is_file() or not any(fnmatch.fnmatchcase(dotted, g) for g in include):
            bad.append(dotted)
    assert not bad, f"folders with modules that the wheel would miss or ship as namespace packages: {bad}"


def test_the_licence_is_declared_and_shipped():
    project = PYPROJECT["project"]
    assert project["license"] == "BSD-3-Clause"
    assert all((ROOT / f).is_file() for f in project["license-files"])
    # PEP 639: a licence expression and a "License ::" classifier may not be given together.
    assert not [c for c in project["classifiers"] if c.startswith("License ::")]
