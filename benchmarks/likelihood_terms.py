"""What each error term and rule of the reciprocity search costs in readings and gains in
error, on generated arenas (issue 33): the runs behind ``benchmarks/likelihood_terms.md``.

Draw ``i`` of a family is ``arenas.generate(FAMILY, i)`` with its own source and start, the
point observer, episode seed ``i``; one row per episode in ``likelihood_terms/NAME.csv``.

    python benchmarks/likelihood_terms.py run NAME --params '{"strength_error": 0.2}' --draws 10
    python benchmarks/likelihood_terms.py run s12_e0 --world '{"mismatch": {"strength_factor": 1.2}}'
    python benchmarks/likelihood_terms.py run unk_survey --mode unknown --draws 5
    python benchmarks/likelihood_terms.py table base+base_b s10_e0 unk_base unk_survey

``--patch '{"INFO_SUPPORT": 64}'`` sets module constants of the reciprocity search's parts
(``reciprocity.strategies.imaging_search``) first (the rule experiments). ``table`` joins CSVs
with ``+`` and limits draws with ``@N`` (``s10_e0@10``): success with its Wilson 95 %
interval, error median / p95 / max (cm), readings median / p90 and mean with its Student-t
95 % interval, path median (cm).
"""

from __future__ import annotations

import argparse
import csv
import json
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).parent / "likelihood_terms"
FIELDS = ["family", "draw", "success", "stop", "error", "n", "path", "t"]


def run(name: str, params: dict, draws: int, start: int, mode: str, world: dict, patch: dict) -> None:
    import arenas
    import importlib
    from reciprocity.env import SearchEnv, rollout
    from reciprocity.scenarios import load_scenario
    from reciprocity.strategies import STRATEGIES
    from reciprocity.strategies.agent import StrategyAgent
    parts = [importlib.import_module(f"reciprocity.strategies.imaging_search.{m}")
             for m in ("likelihood", "next_point", "stop_rule", "reachability", "meshing", "several")]
    for key, value in patch.items():
        owner = [m for m in parts if hasattr(m, key) and key.isupper()]
        if not owner:
            raise SystemExit(f"error: --patch key {key!r} is not a constant of the parts of the reciprocity "
                             f"search (reciprocity.strategies.imaging_search)")
        for module in owner:          # every part that reads it (some import it from another)
            setattr(module, key, value)
    world = dict(world, **({"map": "unknown"} if mode == "unknown" else {}))
    HERE.mkdir(exist_ok=True)
    with (HERE / f"{name}.csv").open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(FIELDS)
        for i in range(start, start + draws):
            for fam in arenas.FAMILIES:
                env = SearchEnv(load_scenario(arenas.generate(fam, i)), world=dict(world))
                t0 = time.perf_counter()
                s = rollout(env, StrategyAgent(STRATEGIES["reciprocity"], dict(params)), i).summary
                w.writerow([fam, i, s["success"], s["stop"], round(s["error"], 3), s["n_measurements"],
                            round(s["path_length"]), round(time.perf_counter() - t0, 2)])
                f.flush()


def _wilson(k: int, n: int) -> str:
    """Wilson 95 % interval of k successes in n, in percent (scipy's)."""
    from scipy.stats import binomtest
    ci = binomtest(k, n).proportion_ci(method="wilson")
    return f"[{100 * ci.low:.0f}, {100 * ci.high:.0f}]"


def _mean_ci(x) -> str:
    """Mean with its Student-t 95 % interval (scipy's)."""
    from scipy import stats
    x = np.asarray(x, float)
    lo, hi = stats.t.interval(0.95, len(x) - 1, loc=x.mean(), scale=stats.sem(x))
    return f"{x.mean():.2f} [{lo:.2f}, {hi:.2f}]"


def table(specs: list[str]) -> str:
    lines = ["| runs | episodes | success [95 %] | error median / p95 / max (cm) | readings median / p90 "
             "| readings mean [95 %] | path median (cm) |", "|---|---|---|---|---|---|---|"]
    for spec in specs:
        names, _, limit = spec.partition("@")
        rows = []
        for name in names.split("+"):
            with (HERE / f"{name}.csv").open() as f:
                rows += list(csv.DictReader(f))
        if limit:
            rows = [r for r in rows if int(r["draw"]) < int(limit)]
        e = np.array([float(r["error"]) for r in rows])
        n = np.array([int(r["n"]) for r in rows])
        path = np.array([float(r["path"]) for r in rows])
        k = sum(r["success"] == "True" for r in rows)
        lines.append(f"| {spec} | {len(rows)} | {100 * k / len(rows):.1f} % {_wilson(k, len(rows))} | {np.median(e):.2f} / "
                     f"{np.percentile(e, 95):.2f} / {e.max():.1f} | {np.median(n):.1f} / {np.percentile(n, 90):.1f} "
                     f"| {_mean_ci(n)} | {np.median(path):.0f} |")
    return "\n".join(lines)


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = p.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run")
    r.add_argument("name")
    r.add_argument("--params", default="{}", help="strategy parameters, JSON")
    r.add_argument("--draws", type=int, default=5, help="draws per family")
    r.add_argument("--start", type=int, default=0)
    r.add_argument("--mode", choices=("known", "unknown"), default="known")
    r.add_argument("--world", default="{}", help="world keys, JSON (e.g. a mismatch)")
    r.add_argument("--patch", default="{}", help="constants of reciprocity.strategies.imaging_search, JSON")
    t = sub.add_parser("table")
    t.add_argument("specs", nargs="+")
    args = p.parse_args(argv)
    if args.cmd == "table":
        print(table(args.specs))
        return 0
    try:
        params, world, patch = (json.loads(v) for v in (args.params, args.world, args.patch))
    except json.JSONDecodeError as exc:
        p.error(f"--params, --world and --patch take JSON: {exc}")
    run(args.name, params, args.draws, args.start, args.mode, world, patch)
    print(table([args.name]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
