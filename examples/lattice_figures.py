"""Figures of one RBPF search on the Ristic et al. (2014) lattice (their Figs. 2, 3, 6).

    python examples/lattice_figures.py [--seed 1] [--lattice-seed 120] [--out out/lattice]

Writes ``lattice.png`` (missing links, mean concentration, true path) and ``search.png``
(source and searcher particle clouds and the links believed to exist at a few steps).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

import reciprocity.api as api
from reciprocity.env import SearchEnv, rollout
from reciprocity.strategies.agent import StrategyAgent
from reciprocity.viz.lattice import lattice_figure, search_figure, snapshot


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--lattice-seed", type=int, default=None)
    ap.add_argument("--strategy", default="rbpf")
    ap.add_argument("--steps", default="5,15,30")
    ap.add_argument("--out", default="out/lattice")
    a = ap.parse_args(argv)
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    at = {int(s) for s in a.steps.split(",")}
    world = {} if a.lattice_seed is None else {"lattice_seed": a.lattice_seed}
    spec = api.check("ristic-lattice", a.strategy, world=world, seeds=a.seed)
    env, agent = SearchEnv(spec), StrategyAgent(spec, figures=True)
    path, snaps = [], []

    def progress(rec):
        if not path:                             # the first move's route begins at the start
            path.append(rec.route[0].tolist())
        path.append(rec.route[-1].tolist())      # the routes hold the true positions
        if rec.step in at:                       # the searcher's record of its belief now
            snaps.append(snapshot(rec.step, agent.strategy.figure_record(), path[-1], path))

    ep = rollout(env, agent, a.seed, progress=progress, figures=True)
    start = np.atleast_2d(ep.summary["start"])
    path = path or [start[0, :2].tolist()]
    snaps.append(snapshot(ep.summary["steps"], ep.belief, path[-1], path))
    lattice_figure(ep.truth, start=start[0], path=np.array(path)).savefig(out / "lattice.png", dpi=90)
    search_figure(ep.truth, snaps).savefig(out / "search.png", dpi=80)
    s = ep.summary
    print(f"{s['stop_reason']} after {s['steps']} steps; estimate {np.round(s['estimate'], 2).tolist()}, "
          f"slips {s['slips']}; figures in {out}")


if __name__ == "__main__":
    main()
