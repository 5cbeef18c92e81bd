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
trajectory, hits, final particles, estimate and source over the mean hit rate (each
kept in ``fig67_seed0_T<T>.json`` when it ends). Rows are appended as runs end, and a
rerun with the same ``--out`` resumes: it runs only what the CSV lacks, then draws and
prints from all the rows asked for; ``--minutes M`` starts no new run after M minutes.
Results: ``docs/papers/song2019.md``.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from arguments import Parser, listed, number, whole
from resumable import resume, truth

from arenas.files import atomic_output
from reciprocity.beliefs.base import posterior_entropies
from reciprocity.env import SearchEnv, rollout
from reciprocity.scenarios import MAX_STEPS, load_scenario
from reciprocity.strategies.agent import StrategyAgent
from reciprocity.strategies.infotaxis import TIE, FreeEnergyInfotaxis

#: The world of Figs. 6-7 (papers/002, captions; the start as in Fig. 5).
FIG67_WORLD = {"bounds": [-300, 300, -150, 150], "source": [-250, 100], "start": [200, -100, np.pi / 2],
               "max_turn": 3}
#: The two temperatures of Figs. 6 and 7 (``--temperatures`` runs others beside them).
TEMPERATURES = (0.0, 1e4)
#: CSV columns, one row per run, and how each is read back.
TYPES = dict(temperature=float, seed=int, success=truth, steps=int, error=float, decided_by_T=float,
             near_estimate=float)
COLUMNS = tuple(TYPES)


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


def record(temperature: float, episode) -> dict:
    """What the figure draws of one run: its path from the start, hits, final particles,
    final estimate and outcome (JSON-ready; lengths in the scenario's unit)."""
    s = episode.summary
    xy = np.array([s["start"][:2]] + [r["pose"][:2] for r in episode.trace], dtype=float)
    hits = np.array([r["points"][0] for r in episode.trace if r["readings"][0] > 0], dtype=float).reshape(-1, 2)
    return dict(temperature=temperature, path=xy.tolist(), hits=hits.tolist(),
                particles=np.asarray(episode.belief["particles"], dtype=float).tolist(),
                estimate=np.asarray(episode.trace[-1]["estimate"], dtype=float).tolist(),
                source=np.asarray(s["source"], dtype=float).tolist(), success=bool(s["success"]),
                steps=int(s["steps"]), error=float(s["error"]))


def figure(records: list[dict], world: dict, path: Path) -> None:
    """One panel per :func:`record` (seed 0 at each temperature): trajectory, hits, final
    particles, estimate, source over the mean hit rate."""
    from matplotlib.figure import Figure
    sc = load_scenario("song-100").with_world(world)
    truth = sc.build_world(0)
    (x0, x1), (y0, y1) = truth.bounds
    X, Y = np.meshgrid(np.linspace(x0, x1, 300), np.linspace(y0, y1, 150))
    rate = truth.rate(np.column_stack([X.ravel(), Y.ravel()])).reshape(X.shape)
    fig = Figure(figsize=(8.5, 4.3 * max(len(records), 1)), layout="constrained")
    for ax, rec in zip(np.atleast_1d(fig.subplots(max(len(records), 1), 1)), records):
        ax.contour(X, Y, np.log10(np.maximum(rate, 1e-8)), levels=np.arange(-4, 1), cmap="Greys",
                   linewidths=0.7)
        cloud = np.asarray(rec["particles"]).reshape(-1, 2)
        ax.scatter(cloud[:, 0], cloud[:, 1], s=2, c="k", label="particles (end)")
        ax.plot(*np.asarray(rec["path"]).T, "r-", lw=0.8, label="trajectory")
        hits = np.asarray(rec["hits"]).reshape(-1, 2)
        ax.plot(hits[:, 0], hits[:, 1], "o", c="r", ms=3, label="hits")
        ax.plot(*rec["estimate"], "*", c="r", mec="k", ms=14, label="estimate (end)")
        ax.plot(*rec["source"], "P", c="tab:blue", ms=11, label="source")
        ax.set_title(f"T = {rec['temperature']:g}, seed 0: "
                     f"{'found' if rec['success'] else 'not found (step cap)'} after {rec['steps']} steps, "
                     f"estimate {rec['error']:.1f} from the source")
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
        ax.set_aspect("equal")
        ax.legend(loc="lower left", fontsize=7, ncol=5)
    fig.savefig(path, dpi=110, format="png")


def record_path(out: Path, temperature: float) -> Path:
    """Where the run of seed 0 at `temperature` keeps its :func:`record`."""
    return out / f"fig67_seed0_T{temperature:g}.json"


def parse(argv=None) -> argparse.Namespace:
    """The checked command line (exit 2 with one ``error:`` line on a bad one)."""
    ap = Parser.of(__file__, __doc__)
    ap.add_argument("--seeds", type=whole(1), default=5, help="runs per temperature")
    ap.add_argument("--temperatures", type=listed(number(0)), default=list(TEMPERATURES),
                    help="temperatures T ≥ 0, comma-separated (the paper's: 0 and 1e4)")
    ap.add_argument("--max-steps", type=whole(1, MAX_STEPS), default=6000, help="step cap of a run")
    ap.add_argument("--last", type=whole(1), default=500, help="final steps measured for self-trapping")
    ap.add_argument("--radius", type=number(0, low_open=True), default=25.0,
                    help="'near the estimate' radius (length unit)")
    args = ap.parse_resumable(argv, "runs/song_fig67", "fig67.csv", COLUMNS,
                              ", fig67.png and seed 0's runs drawn in it (fig67_seed0_T<T>.json)")
    args.png = ap.output_file(args.out / "fig67.png")
    for t in args.temperatures:
        ap.output_file(record_path(args.out, t))
    return args


def main(argv=None) -> list[dict]:
    """Run the seeds not yet in ``fig67.csv`` (keeping seed 0's runs for the figure), then
    draw and print from all its rows of the seeds and temperatures asked for; those rows."""
    args = parse(argv)
    temperatures = args.temperatures

    def rows_of(key):
        temperature, seed = key
        row, episode = run(temperature, seed, args.max_steps, args.last, args.radius)
        if seed == 0:                # kept before its row, so that a written row has its record
            with atomic_output(record_path(args.out, temperature)) as tmp:
                tmp.write_text(json.dumps(record(temperature, episode)))
        return [row]

    keys = [(t, seed) for seed in range(args.seeds) for t in temperatures]
    rows = resume(args.csv, TYPES, keys, lambda r: (r["temperature"], r["seed"]), rows_of, args.minutes)
    records = [json.loads(p.read_text()) for t in temperatures if (p := record_path(args.out, t)).exists()]
    with atomic_output(args.png) as tmp:
        figure(records, FIG67_WORLD, tmp)
    for temperature in temperatures:
        mine = [r for r in rows if r["temperature"] == temperature]
        if not mine:
            continue
        found = [r["steps"] for r in mine if r["success"]]
        print(f"T = {temperature:g}: found {len(found)}/{len(mine)}, mean steps of the found "
              f"{np.mean(found) if found else float('nan'):.0f}, median final error "
              f"{np.median([r['error'] for r in mine]):.1f}, T decided {np.mean([r['decided_by_T'] for r in mine]):.0%} "
              f"of the moves, last steps near the estimate {np.median([r['near_estimate'] for r in mine]):.0%}")
    return rows


if __name__ == "__main__":
    main()
