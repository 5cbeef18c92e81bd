"""How much does free energy's temperature decide, per area? Song, He & Lei (2019), eq. (8)-(10).

    nice -n 10 python benchmarks/song_temperature.py --seeds 10 [--sides 100,200,300]

The criterion of papers/002 is, for each candidate move ``v``,

    E{F(v)} = E{W(v)} + α · E{tr(Σ)^β · S(v)}                      eqs. (8), (10)

with ``W`` the γ-weighted mean distance to the particles (length^γ), ``S`` the entropy of
the particle weights (nats) and ``T = α tr(Σ)^β`` (length^2β). Only differences between
moves decide. Each step of a ``free-energy`` run (the printed α = 0.01, β = 1.4, γ = 3,
the ``song-<side>`` scenarios) is scored twice, with α and with α = 0, and this script
records

* whether the printed α chose another move than α = 0 (the temperature *decided* the step);
* the critical α of the step: the least α at which the choice differs from α = 0's
  (+inf when no α changes it).

The median critical α over the steps of the runs is the α at which the temperature term
decides about half the steps: the balance the paper describes (exploration first, then
exploitation as tr(Σ) shrinks) needs α of that order, at every area. ``--alpha`` and
``--area-exponent`` measure another temperature the same way (the critical α is then
still the least α, at this run's moves, that changes the α = 0 choice). Results:
``docs/papers/song2019.md``.
"""

from __future__ import annotations

import argparse
from multiprocessing import Pool

import numpy as np

from reciprocity.strategies.infotaxis import TIE, FreeEnergyInfotaxis


class SplitFreeEnergy(FreeEnergyInfotaxis):
    """The paper's free energy, recording each step's two terms separately."""

    def start(self, ctx):
        super().start(ctx)
        self.steps_log: list[tuple[bool, float]] = []

    def scores(self, cands):
        EW, ES = self.terms(cands)
        first = lambda s: int(np.flatnonzero(s <= np.min(s) + TIE)[0])   # noqa: E731 (as decide())
        cold = first(EW)
        decided = first(EW + self.alpha_used * ES) != cold
        # the least alpha at which another move beats the alpha = 0 choice
        gap_w, gap_s = EW - EW[cold], ES[cold] - ES
        ok = gap_s > 0
        crit = float(np.min(gap_w[ok] / gap_s[ok])) if ok.any() else np.inf
        self.steps_log.append((bool(decided), crit))
        return EW + self.alpha_used * ES


def one(job):
    side, seed, params = job
    from reciprocity.env import SearchEnv, rollout
    from reciprocity.strategies.agent import StrategyAgent
    agent = StrategyAgent(SplitFreeEnergy, params)
    episode = rollout(SearchEnv(f"song-{side}"), agent, seed)
    log = agent.strategy.steps_log
    return side, seed, bool(episode.summary["success"]), int(episode.summary["steps"]), log


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--sides", default="100,150,200,250,300,350")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--alpha", type=float, default=0.01, help="free energy's alpha (the paper's 0.01)")
    ap.add_argument("--area-exponent", type=float, default=0.0,
                    help="alpha grows as (L/100)^k (0: the paper; 2.35: song2019-table1 --protocol balanced)")
    args = ap.parse_args(argv)
    sides = [int(s) for s in args.sides.split(",")]
    params = {"alpha": args.alpha, "area_exponent": args.area_exponent}
    jobs = [(side, seed, params) for side in sides for seed in range(args.seeds)]
    with Pool(args.workers) as pool:
        out = pool.map(one, jobs)
    print(f"free-energy, alpha = {args.alpha:g} (L/100)^{args.area_exponent:g}, beta = 1.4, gamma = 3; "
          f"seeds 0..{args.seeds - 1} per side\n")
    print("| side | found | mean steps | steps decided by T | no α decides | critical α: p25 / median / p75 |")
    print("|---:|---:|---:|---:|---:|---|")
    for side in sides:
        rows = [o for o in out if o[0] == side]
        decided = np.array([d for o in rows for d, _ in o[4]])
        crit = np.array([c for o in rows for _, c in o[4]])
        q = np.percentile(crit, [25, 50, 75], method="lower")      # inf (no alpha decides) sorts last
        print(f"| {side}² | {sum(o[2] for o in rows)}/{len(rows)} | {np.mean([o[3] for o in rows]):.0f} | "
              f"{100 * decided.mean():.1f} % | {100 * np.isinf(crit).mean():.1f} % | "
              f"{q[0]:.3g} / {q[1]:.3g} / {q[2]:.3g} |", flush=True)
    print("\nA power law through the medians (sides up to 250², where no run self-traps): "
          + _fit(sides, out))


def _fit(sides, out) -> str:
    """``alpha_50 = a (L/100)^k`` fitted to the medians of the sides up to 250."""
    pts = [(side, np.percentile([c for o in out if o[0] == side for _, c in o[4]], 50, method="lower"))
           for side in sides if side <= 250]
    pts = [(s, m) for s, m in pts if np.isfinite(m)]
    if len(pts) < 2:
        return "too few sides"
    k, loga = np.polyfit(np.log([s / 100 for s, _ in pts]), np.log([m for _, m in pts]), 1)
    return f"alpha_50 = {np.exp(loga):.3g} (L/100)^{k:.2f}"


if __name__ == "__main__":
    main()
