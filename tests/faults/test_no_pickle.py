"""Rule: nothing is ever unpickled from a file (issue 34, item 2: the bank's workers
unpickled their workspace from a file in a shared cache, so whoever could write there ran
code as the user).

Every call in the three packages that can unpickle is found by walking their syntax trees;
``numpy.load`` must say ``allow_pickle=False``."""

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SOURCES = sorted(p for pkg in ("arenas", "hjplanner", "reciprocity") for p in (ROOT / pkg).rglob("*.py"))
#: Calls that unpickle, by their dotted name's last two parts.
UNPICKLERS = {("pickle", "load"), ("pickle", "loads"), ("pickle", "Unpickler"), ("cloudpickle", "load"),
              ("cloudpickle", "loads"), ("dill", "load"), ("dill", "loads"), ("joblib", "load"),
              ("shelve", "open"), ("pd", "read_pickle"), ("pandas", "read_pickle"), ("torch", "load")}


def _name(node: ast.AST) -> tuple[str, ...]:
    parts = []
    while isinstance(node, ast.Attribute):
        parts.append(node.attr)
        node = node.value
    if isinstance(node, ast.Name):
        parts.append(node.id)
    return tuple(reversed(parts))


def _calls(path: Path):
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Call):
            yield node, _name(node.func)


def test_nothing_unpickles():
    bad, loads = [], 0
    for path in SOURCES:
        where = path.relative_to(ROOT)
        for call, name in _calls(path):
            if name[-2:] in UNPICKLERS:
                bad.append(f"{where}:{call.lineno}: {'.'.join(name)}")
            if name[-2:] in (("np", "load"), ("numpy", "load")):
                loads += 1
                safe = any(k.arg == "allow_pickle" and isinstance(k.value, ast.Constant) and k.value.value is False
                           for k in call.keywords)
                if not safe:
                    bad.append(f"{where}:{call.lineno}: {'.'.join(name)} without allow_pickle=False")
    assert len(SOURCES) > 100 and loads >= 3          # the walk saw the packages and their loads
    assert not bad, bad


def test_the_walk_finds_what_it_looks_for(tmp_path):
    probe = tmp_path / "probe.py"
    probe.write_text("import pickle, numpy as np\npickle.load(f)\nnp.load('x.npz')\nnp.load('y', allow_pickle=False)\n")
    names = [name for _, name in _calls(probe)]
    assert ("pickle", "load") in names and names.count(("np", "load")) == 2
