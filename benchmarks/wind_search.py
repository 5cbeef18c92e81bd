"""Reciprocity in wind against the wall-blind baseline on a ``flow`` scenario (issue 38).

    PYTHONPATH=. python benchmarks/wind_search.py [--scenario paper-wind] [--seeds 20] [--h 2]
        [--strategies reciprocity-wind,free-space-wind] [--set KEY=VALUE ...] [--json FILE]

Each seed draws the true source and the start as campaigns do (``random_source``:
:func:`reciprocity.campaign.worker.world_draw`), and every strategy runs on the same
draws. Prints one row per strategy: success, converged, mean readings (= steps: one
reading per round on the point observer), mean path, mean and median error of the
converged runs (cm), and the mean wall time per episode.
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

from reciprocity.api import run
from reciprocity.campaign.worker import world_draw
from reciprocity.scenarios import load_scenario


def _value(text: str):
    try:
        return json.loads(text)
    except json.JSONDecodeError:
        return text


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenario", default="paper-wind")
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--h", type=float, default=2.0, help="mesh size of the strategies' model, cm")
    ap.add_argument("--strategies", default="reciprocity-wind,free-space-wind")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="a strategy parameter")
    ap.add_argument("--json", help="write every summary here")
    args = ap.parse_args()
    sc = load_scenario(args.scenario)
    extra = {k: _value(v) for k, v in (s.split("=", 1) for s in args.set)}
    rows, summaries = [], []
    for name in args.strategies.split(","):
        runs = []
        for seed in range(args.seeds):
            t0 = time.perf_counter()
            s = run(sc, name, seed=seed, params=dict(h=args.h, **extra), world=world_draw(sc, seed)).summary
            s["bench_wall_s"] = time.perf_counter() - t0
            runs.append(s)
        summaries += runs
        ok = [s for s in runs if s["converged"]]
        err = np.array([s["error"] for s in ok]) if ok else np.array([np.nan])
        rows.append((name, np.mean([s["success"] for s in runs]), len(ok) / len(runs),
                     np.mean([s["n_measurements"] for s in runs]), np.mean([s["path_length"] for s in runs]),
                     float(np.mean(err)), float(np.median(err)), np.mean([s["bench_wall_s"] for s in runs])))
    print(f"scenario {sc.name!r}, {args.seeds} seeds (random source and start), strategy h = {args.h:g} cm"
          + (f", {extra}" if extra else ""))
    print("| strategy | success | converged | readings (= steps) | path cm | error cm (mean, converged) "
          "| error cm (median, converged) | wall s / episode |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r[0]} | {r[1]:.0%} | {r[2]:.0%} | {r[3]:.1f} | {r[4]:.0f} | {r[5]:.2f} | {r[6]:.2f} | {r[7]:.1f} |")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(summaries, fh, indent=1, default=float)


if __name__ == "__main__":
    main()
