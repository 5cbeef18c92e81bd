"""Figs. 6-7 of Song, He & Lei (2019): free energy at the temperatures T = 0 and T = 10⁴.

    nice -n 10 python benchmarks/song_fig67.py --seeds 5 --out runs/song_fig67

Section 4.3 of papers/002 runs the free-energy search with its temperature fixed, T = 0
(Fig. 6: the searcher chases its estimate and self-traps beside it, away from the source)
and T = 10⁴ (Fig. 7: the entropy dominates and the search succeeds), the source at
(−250, 100) in the area [−300, 300] × [−150, 150]. The start is not given: (200, −100),
heading +y, as in Fig. 5; turns of at most ±3°, the plume and filter of Table 1. The
score of a move is ``E_z{W} + T E_z{S}`` (eqs. (8)-(10) with a constant T,
:class:`FixedTemperature`). Per run one CSV row (``fig67.csv``): found, steps, the final
estimate's distance from the source, the share of the moves on which T changed the
choice from T = 0's, and the share of the last `--last` steps spent within `--radius` of
the final estimate (self-trapped). The figure (``fig67.png``) draws seed 0 at each T:
trajectory, hits, final particles, estimate and source over the mean hit rate.
Results: ``docs/papers/song2019.md``.
"""

from __future__ import annotations

import argparse
import csv
from pathlib import Path

import numpy as np

from reciprocity.beliefs.base import posterior_entropies
from reciprocity.env import SearchEnv, rollout
from reciprocity.scenarios import load_scenario
from reciprocity.strategies.agent import StrategyAgent
from reciprocity.strategies.infotaxis import TIE, FreeEnergyInfotaxis

#: The world of Figs. 6-7 (papers/002, captions; the start as in Fig. 5).
FIG67_WORLD = {"bounds": [-300, 300, -150, 150], "source": [-250, 100], "start": [200, -100, np.pi / 2],
               "max_turn": 3}
#: The two temperatures of Figs. 6 and 7 (``--temperatures`` runs others beside them).
TEMPERATURES = (0.0, 1e4)
#: CSV columns, one row per run.
COLUMNS = ("temperature", "seed", "success", "steps", "error", "decided_by_T", "near_estimate")


class FixedTemperature(FreeEnergyInfotaxis):
    """Free energy with a constant temperature: the score ``E_z{W} + T E_z{S}``.

    Parameters
    ----------
    temperature : float
        T, length^γ per nat (0: the potential alone, Fig. 6).
    """

    def __init__(self, *, temperature: float = 0.0, **params):
        self.temperature = float(temperature)
        super().__init__(**params)

    def start(self, ctx):
        super().start(ctx)
        self.decided: list[bool] = []

    def scores(self, cands):
        potential = self.terms(cands)[0]
        joint, _, _ = self.belief.outcomes(cands, eta=self.eta)
        rho, H, _ = posterior_entropies(joint)
        score = potential + self.temperature * np.sum(rho * H, axis=0)
        first = lambda s: int(np.flatnonzero(s <= np.min(s) + TIE)[0])   # noqa: E731 (as decide())
        self.decided.append(first(score) != first(potential))
        return score

    def figure_record(self) -> dict:
        return {"particles": self.belief.support().copy(), "weights": self.belief.weights().copy(),
                "decided": list(self.decided)}


def run(temperature: float, seed: int, max_steps: int, last: int, radius: float,
        world: dict = FIG67_WORLD):
    """One run at `temperature`; its CSV row and its episode (with the final cloud)."""
    sc = load_scenario("song-100").with_world(world).with_limits(max_steps=max_steps)
    agent = StrategyAgent(FixedTemperature, {"temperature": temperature}, figures=True)
    episode = rollout(SearchEnv(sc), agent, seed, figures=True)
    s = episode.summary
    xy = np.array([r["pose"][:2] for r in episode.trace], dtype=float)
    est = np.asarray(episode.trace[-1]["estimate"], dtype=float)
    decided = episode.belief["decided"]
    row = dict(temperature=temperature, seed=seed, success=bool(s["success"]), steps=int(s["steps"]),
               error=float(s["error"]), decided_by_T=float(np.mean(decided)) if decided else 0.0,
               near_estimate=float(np.mean(np.hypot(*(xy[-last:] - est).T) <= radius)))
    return row, episode


def figure(episodes: dict, world: dict, path: Path) -> None:
    """Seed 0 at each temperature: trajectory, hits, final particles, estimate, source."""
    from matplotlib.figure import Figure
    sc = load_scenario("song-100").with_world(world)
    truth = sc.build_world(0)
    (x0, x1), (y0, y1) = truth.bounds
    X, Y = np.meshgrid(np.linspace(x0, x1, 300), np.linspace(y0, y1, 150))
    rate = truth.rate(np.column_stack([X.ravel(), Y.ravel()])).reshape(X.shape)
    fig = Figure(figsize=(8.5, 4.3 * len(episodes)), layout="constrained")
    for ax, (temperature, episode) in zip(np.atleast_1d(fig.subplots(len(episodes), 1)), episodes.items()):
        ax.contour(X, Y, np.log10(np.maximum(rate, 1e-8)), levels=np.arange(-4, 1), cmap="Greys",
                   linewidths=0.7)
        cloud = episode.belief["particles"]
        ax.scatter(cloud[:, 0], cloud[:, 1], s=2, c="k", label="particles (end)")
        xy = np.array([r["pose"][:2] for r in episode.trace])
        start = np.asarray(episode.summary["start"][:2])
        ax.plot(*np.vstack([start, xy]).T, "r-", lw=0.8, label="trajectory")
        hits = np.array([r["points"][0] for r in episode.trace if r["readings"][0] > 0]).reshape(-1, 2)
        ax.plot(hits[:, 0], hits[:, 1], "o", c="r", ms=3, label="hits")
        ax.plot(*episode.trace[-1]["estimate"], "*", c="r", mec="k", ms=14, label="estimate (end)")
        ax.plot(*episode.summary["source"], "P", c="tab:blue", ms=11, label="source")
        s = episode.summary
        ax.set_title(f"T = {temperature:g}, seed 0: {'found' if s['success'] else 'not found (step cap)'} "
                     f"after {s['steps']} steps, estimate {s['error']:.1f} from the source")
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
        ax.set_aspect("equal")
        ax.legend(loc="lower left", fontsize=7, ncol=5)
    fig.savefig(path, dpi=110)


def main(argv=None) -> list[dict]:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=5, help="runs per temperature")
    ap.add_argument("--temperatures", default=",".join(f"{t:g}" for t in TEMPERATURES),
                    help="temperatures T, comma-separated (the paper's: 0 and 1e4)")
    ap.add_argument("--max-steps", type=int, default=6000, help="step cap of a run")
    ap.add_argument("--last", type=int, default=500, help="final steps measured for self-trapping")
    ap.add_argument("--radius", type=float, default=25.0, help="'near the estimate' radius")
    ap.add_argument("--out", default="runs/song_fig67", help="folder for fig67.csv and fig67.png")
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    temperatures = [float(t) for t in args.temperatures.split(",")]
    rows, first = [], {}
    with open(out / "fig67.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, COLUMNS)
        writer.writeheader()
        for temperature in temperatures:
            for seed in range(args.seeds):
                row, episode = run(temperature, seed, args.max_steps, args.last, args.radius)
                writer.writerow(row)
                fh.flush()
                rows.append(row)
                if seed == 0:
                    first[temperature] = episode
    figure(first, FIG67_WORLD, out / "fig67.png")
    for temperature in temperatures:
        mine = [r for r in rows if r["temperature"] == temperature]
        found = [r["steps"] for r in mine if r["success"]]
        print(f"T = {temperature:g}: found {len(found)}/{len(mine)}, mean steps of the found "
              f"{np.mean(found) if found else float('nan'):.0f}, median final error "
              f"{np.median([r['error'] for r in mine]):.1f}, T decided {np.mean([r['decided_by_T'] for r in mine]):.0%} "
              f"of the moves, last steps near the estimate {np.median([r['near_estimate'] for r in mine]):.0%}")
    return rows


if __name__ == "__main__":
    main()
