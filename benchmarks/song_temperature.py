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
still the least α, at this run's moves, that changes the α = 0 choice).

Each step is a row of ``temperature.csv`` under ``--out``, appended as its run ends; a
rerun with the same ``--out`` resumes (runs are keyed by α, area exponent, side and
seed, so one folder holds several temperatures), and ``--minutes M`` takes no new run
after M minutes. Results: ``docs/papers/song2019.md``.
"""

from __future__ import annotations

import argparse
from multiprocessing import Pool

import numpy as np

from arguments import Parser, among, listed, number, whole
from resumable import resume, truth

from reciprocity.campaign.tables.song2019 import SONG_SCALES
from reciprocity.strategies.infotaxis import TIE, FreeEnergyInfotaxis

#: CSV columns, one row per step of a run, and how each is read back.
TYPES = dict(alpha=float, area_exponent=float, side=int, seed=int, success=truth, steps=int, step=int,
             decided=truth, critical_alpha=float)
COLUMNS = tuple(TYPES)


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


def one(key: tuple) -> list[dict]:
    """The run ``(alpha, area_exponent, side, seed)``: one row per step."""
    alpha, area_exponent, side, seed = key
    from reciprocity.env import SearchEnv, rollout
    from reciprocity.strategies.agent import StrategyAgent
    agent = StrategyAgent(SplitFreeEnergy, {"alpha": alpha, "area_exponent": area_exponent})
    s = rollout(SearchEnv(f"song-{side}"), agent, seed).summary
    return [dict(alpha=alpha, area_exponent=area_exponent, side=side, seed=seed, success=bool(s["success"]),
                 steps=int(s["steps"]), step=i + 1, decided=decided, critical_alpha=crit)
            for i, (decided, crit) in enumerate(agent.strategy.steps_log)]


def parse(argv=None) -> argparse.Namespace:
    """The checked command line (exit 2 with one ``error:`` line on a bad one)."""
    ap = Parser.of(__file__, __doc__)
    ap.add_argument("--seeds", type=whole(1), default=10, help="runs per side")
    ap.add_argument("--sides", type=listed(among(SONG_SCALES, int)), default=list(SONG_SCALES),
                    help=f"area sides, comma-separated, among {', '.join(map(str, SONG_SCALES))}")
    ap.add_argument("--workers", type=whole(1), default=2, help="processes running the seeds")
    ap.add_argument("--alpha", type=number(0), default=0.01, help="free energy's alpha (the paper's 0.01)")
    ap.add_argument("--area-exponent", type=number(), default=0.0,
                    help="alpha grows as (L/100)^k (0: the paper; 2.35: song2019-table1 --protocol balanced)")
    return ap.parse_resumable(argv, "runs/song_temperature", "temperature.csv", COLUMNS,
                              "; one row per step, keyed by alpha and area exponent too")


def main(argv=None) -> list[dict]:
    """Run what ``temperature.csv`` lacks, then print the table from all its rows asked
    for; those rows."""
    args = parse(argv)
    keys = [(args.alpha, args.area_exponent, side, seed) for side in args.sides for seed in range(args.seeds)]
    with Pool(args.workers) as pool:
        rows = resume(args.csv, TYPES, keys, lambda r: (r["alpha"], r["area_exponent"], r["side"], r["seed"]),
                      one, args.minutes, mapper=pool.imap)
    print(f"free-energy, alpha = {args.alpha:g} (L/100)^{args.area_exponent:g}, beta = 1.4, gamma = 3; "
          f"seeds 0..{args.seeds - 1} per side\n")
    print("| side | found | mean steps | steps decided by T | no α decides | critical α: p25 / median / p75 |")
    print("|---:|---:|---:|---:|---:|---|")
    for side in args.sides:
        mine = [r for r in rows if r["side"] == side]
        if not mine:
            continue
        runs = {r["seed"]: r for r in mine}                       # the run's own columns, once
        decided = np.array([r["decided"] for r in mine])
        crit = np.array([r["critical_alpha"] for r in mine])
        q = np.percentile(crit, [25, 50, 75], method="lower")      # inf (no alpha decides) sorts last
        print(f"| {side}² | {sum(r['success'] for r in runs.values())}/{len(runs)} | "
              f"{np.mean([r['steps'] for r in runs.values()]):.0f} | {100 * decided.mean():.1f} % | "
              f"{100 * np.isinf(crit).mean():.1f} % | {q[0]:.3g} / {q[1]:.3g} / {q[2]:.3g} |", flush=True)
    print("\nA power law through the medians (sides up to 250², where no run self-traps): "
          + _fit(args.sides, rows))
    return rows


def _fit(sides, rows) -> str:
    """``alpha_50 = a (L/100)^k`` fitted to the medians of the sides up to 250."""
    pts = [(side, np.percentile([r["critical_alpha"] for r in rows if r["side"] == side], 50, method="lower"))
           for side in sides if side <= 250 and any(r["side"] == side for r in rows)]
    pts = [(s, m) for s, m in pts if np.isfinite(m)]
    if len(pts) < 2:
        return "too few sides"
    k, loga = np.polyfit(np.log([s / 100 for s, _ in pts]), np.log([m for _, m in pts]), 1)
    return f"alpha_50 = {np.exp(loga):.3g} (L/100)^{k:.2f}"


if __name__ == "__main__":
    main()
