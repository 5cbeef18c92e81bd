"""The module walk of a point run's setup: how often the call stack's top frame changes
module, and how often the strategy is built and the scenario checked, before the first
reading (issue 37).

    PYTHONPATH=. python benchmarks/module_walk.py [--arena paper] [--strategy reciprocity]

Every module of ``arenas``, ``hjplanner`` and ``reciprocity`` is imported first, so that
no module body is counted. Then two setups are profiled (:func:`sys.setprofile`), each
until the first :meth:`SearchEnv.step` (the first reading):

* ``cli``: ``reciprocity run --arena A --strategy S --seed 0 --quiet`` from ``main``;
* ``api``: ``reciprocity.api.run(A, S, seed=0)``.

A *module switch* is a call of a function in one of those three packages whose module
differs from the module of the nearest calling frame in them (calls into numpy, scipy and
the standard library are not counted, nor are the calls they make back into ours counted
twice). The counts of one machine are in ``benchmarks/module_walk.md``.
"""

from __future__ import annotations

import argparse
import importlib
import pkgutil
import sys
from collections import Counter
from pathlib import Path

PACKAGES = ("arenas", "hjplanner", "reciprocity")


class FirstReading(Exception):
    """Raised at the first step: the setup is over."""


def _import_all() -> None:
    """Import every module of ours (so that no module body runs while profiling)."""
    for name in PACKAGES:
        pkg = importlib.import_module(name)
        for info in pkgutil.walk_packages(pkg.__path__, name + "."):
            if ".gym" in info.name or ".pettingzoo" in info.name or info.name.endswith("__main__"):
                continue
            try:
                importlib.import_module(info.name)
            except Exception:                            # noqa: BLE001 - optional extras
                pass


def _root() -> Path:
    """The folder holding the packages (the repository root)."""
    return Path(importlib.import_module("reciprocity").__file__).resolve().parents[1]


def _module(filename: str) -> str | None:
    """``reciprocity.env.search_env`` for a file of ours, else None."""
    try:
        rel = Path(filename).resolve().relative_to(_root())
    except ValueError:
        return None
    if rel.parts[0] not in PACKAGES or rel.suffix != ".py":
        return None
    return ".".join(rel.with_suffix("").parts)


class Walk:
    """The profile function: counts module switches and the calls of `watched` code."""

    def __init__(self, watched: dict):
        self.switches = 0
        self.calls = Counter()
        self.watched = watched                          # code object -> label
        self.cache: dict = {}
        self.pairs = Counter()
        self.marks: dict = {}                            # label -> switches before its first call

    def mod(self, code) -> str | None:
        if code not in self.cache:
            self.cache[code] = _module(code.co_filename)
        return self.cache[code]

    def __call__(self, frame, event, arg) -> None:
        if event != "call":
            return
        code = frame.f_code
        label = self.watched.get(code)
        if label is not None:
            self.calls[label] += 1
            self.marks.setdefault(label, self.switches)
        here = self.mod(code)
        if here is None:
            return
        caller = frame.f_back
        while caller is not None and self.mod(caller.f_code) is None:
            caller = caller.f_back
        if caller is not None and self.mod(caller.f_code) != here:
            self.switches += 1
            self.pairs[f"{self.mod(caller.f_code)} -> {here}.{code.co_name}"] += 1


def _watched(strategy: str) -> dict:
    """The functions whose calls are counted: the strategy's constructor and the checks."""
    from reciprocity import api, scenarios
    from reciprocity.env import search_env
    from reciprocity.strategies import STRATEGIES
    from reciprocity.strategies.agent import StrategyAgent
    out = {STRATEGIES[strategy].__init__.__code__: "strategy built",
           scenarios.from_dict.__code__: "scenarios.from_dict",
           scenarios.Scenario.with_world.__code__: "Scenario.with_world",
           scenarios.Scenario.check_observers.__code__: "Scenario.check_observers (agents)",
           scenarios._check_starts.__code__: "scenarios._check_starts (start poses)",
           scenarios.WORLD_KINDS["poisson"].check.__code__: "poisson kind check (world parameters)",
           api.check.__code__: "api.check",
           search_env.SearchEnv.__init__.__code__: "SearchEnv.__init__",
           search_env.SearchEnv.reset.__code__: "SearchEnv.reset",
           StrategyAgent.reset.__code__: "StrategyAgent.reset"}
    for name in ("make_strategy", "check_spec", "environment_spec", "checked_seed"):
        for mod in (api, search_env, sys.modules.get("reciprocity.env.spec")):
            f = getattr(mod, name, None) if mod is not None else None
            if f is not None and hasattr(f, "__code__"):
                out[f.__code__] = f"{mod.__name__.split('.')[-1]}.{name}"
    return out


def walk(setup, strategy: str) -> Walk:
    """Profile `setup()` until the first step."""
    from reciprocity.env import search_env
    name = "carry_out" if hasattr(search_env.SearchEnv, "carry_out") else "step"
    step = getattr(search_env.SearchEnv, name)

    def first(self, *args):
        raise FirstReading
    w = Walk(_watched(strategy))
    setattr(search_env.SearchEnv, name, first)
    sys.setprofile(w)
    try:
        setup()
    except FirstReading:
        pass
    finally:
        sys.setprofile(None)
        setattr(search_env.SearchEnv, name, step)
    return w


def _setup(mode: str, arena: str, strategy: str):
    """The setup to profile: the command line's or the Python API's."""
    if mode == "cli":
        from reciprocity.cli import main as cli
        return lambda: cli(["run", "--arena", arena, "--strategy", strategy, "--seed", "0", "--quiet"])
    from reciprocity import api
    return lambda: api.run(arena, strategy, seed=0)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--arena", default="paper")
    ap.add_argument("--strategy", default="reciprocity")
    ap.add_argument("--mode", choices=("cli", "api"), help="profile this one here (default: each in a "
                    "fresh interpreter, so that neither profits from the other's in-memory caches)")
    ap.add_argument("--detail", action="store_true", help="list every switch (caller -> callee)")
    a = ap.parse_args(argv)
    if a.mode is None:
        import subprocess
        for mode in ("cli", "api"):
            rest = ["--arena", a.arena, "--strategy", a.strategy, "--mode", mode] + (["--detail"] * a.detail)
            subprocess.run([sys.executable, __file__, *rest], check=True)
        return
    _import_all()
    w = walk(_setup(a.mode, a.arena, a.strategy), a.strategy)
    print(f"{a.mode}: {w.switches} module switches before the first reading")
    env, agent = w.marks.get("SearchEnv.reset", 0), w.marks.get("StrategyAgent.reset", 0)
    print(f"  checks and building (before SearchEnv.reset)   {env}")
    print(f"  SearchEnv.reset (world, platform, task)        {agent - env}")
    print(f"  the agent's reset (the strategy's start)       {w.switches - agent}")
    for label, n in sorted(w.calls.items()):
        print(f"  {label:<45} {n}")
    if a.detail:
        for pair, n in w.pairs.most_common():
            print(f"    {n:>4}  {pair}")


if __name__ == "__main__":
    main()
