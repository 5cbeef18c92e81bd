"""Start-up: importing the packages or asking the command lines for help stays cheap.

Issue 24: ``reciprocity --help`` took 1.4 s and 247 MB because every package imported its
whole stack up front (OpenCV, pymunk, scikit-fem, numba kernels, Dask, ...). The packages
now export their names lazily and the commands import what they run; these tests keep it
so. Timing is measured in ``benchmarks/bench_startup.py``, not asserted here.
"""

import importlib
import json
import subprocess
import sys

import pytest

#: Third-party stacks no import of a package and no ``--help`` may load.
HEAVY = ("matplotlib", "numba", "cv2", "pymunk", "dask", "distributed", "skfem", "pyarrow", "duckdb",
         "gymnasium")

#: Run in a fresh interpreter: imports every package and both CLIs, asks each CLI for
#: --help (its output discarded), then prints which heavy modules got loaded.
PROBE = f"""
import contextlib, io, json, sys
import reciprocity.cli, reciprocity, arenas, hjplanner, hjplanner.cli
for main in (reciprocity.cli.main, hjplanner.cli.main):
    with contextlib.redirect_stdout(io.StringIO()):
        try:
            main(["--help"])
        except SystemExit:
            pass
print(json.dumps(sorted(m for m in {HEAVY!r} if m in sys.modules)))
"""


def test_imports_and_help_load_no_heavy_stack():
    done = subprocess.run([sys.executable, "-c", PROBE], capture_output=True, text=True, check=True)
    assert json.loads(done.stdout.splitlines()[-1]) == []


#: Run in a fresh interpreter with the command's arguments after ``-c``: runs one
#: ``reciprocity`` command (its listing discarded), then prints which heavy modules it loaded.
LISTING_PROBE = f"""
import contextlib, io, json, sys
import reciprocity.cli
with contextlib.redirect_stdout(io.StringIO()):
    code = reciprocity.cli.main(sys.argv[1:])
assert code == 0, code
print(json.dumps(sorted(m for m in {HEAVY!r} if m in sys.modules)))
"""


@pytest.mark.parametrize("command", ["strategies", "scenarios"])
def test_listings_load_no_heavy_stack(command):
    # listing imports every strategy module and validates every scenario (through the
    # world kinds): their solvers, kernels and plots load where they are used
    done = subprocess.run([sys.executable, "-c", LISTING_PROBE, command], capture_output=True, text=True,
                          check=True)
    assert json.loads(done.stdout.splitlines()[-1]) == []


#: Run in a fresh interpreter with a command line after ``-c``: builds the ``reciprocity``
#: parser, parses the command line (help or not), then prints whether the campaign layer
#: got imported.
PARSER_PROBE = """
import contextlib, io, sys
import reciprocity.cli
with contextlib.redirect_stdout(io.StringIO()):
    try:
        reciprocity.cli.build_parser().parse_args(sys.argv[1:])
    except SystemExit:
        pass
print("reciprocity.campaign" in sys.modules)
"""


@pytest.mark.parametrize("argv", [["--help"], ["run", "--help"],
                                  ["run", "--arena", "paper", "--strategy", "reciprocity"]])
def test_the_parser_of_run_leaves_out_the_campaign_layer(argv):
    # the campaign layer declares its own commands' flags, on use (issue 37)
    done = subprocess.run([sys.executable, "-c", PARSER_PROBE, *argv], capture_output=True, text=True, check=True)
    assert done.stdout.split()[-1] == "False"


def test_the_campaign_commands_declare_their_flags_on_use():
    done = subprocess.run([sys.executable, "-c", PARSER_PROBE, "reproduce", "--help"], capture_output=True,
                          text=True, check=True)
    assert done.stdout.split()[-1] == "True"


@pytest.mark.parametrize("package", ["arenas", "hjplanner", "reciprocity", "reciprocity.fem",
                                     "reciprocity.campaign", "reciprocity.wiring"])
def test_lazy_exports_resolve_and_are_listed(package):
    module = importlib.import_module(package)
    assert module.__all__ and set(module.__all__) <= set(dir(module))
    for name in module.__all__:
        assert getattr(module, name) is not None, name
    with pytest.raises(AttributeError):
        module.no_such_name


def test_the_registries_resolve_every_builtin_name_through_the_lazy_exports():
    # one lazy mechanism (issue 37): a registry names an attribute its package exports lazily
    from reciprocity.scenarios import WORLD_KINDS
    from reciprocity.strategies import STRATEGIES
    assert all(STRATEGIES[name].name == name for name in STRATEGIES)
    assert all(WORLD_KINDS[name].name == name for name in WORLD_KINDS)
