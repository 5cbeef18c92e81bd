"""One figure per world kind: the true signal and one search in each.

    python examples/world_figures.py [--out out/worlds] [--quick]

Writes ``world_poisson.png`` (the FEM field of the ``paper`` arena's source, the
reciprocity search's route and readings), ``world_lattice.png`` (an RBPF search on ``ristic-lattice``:
missing links, mean concentration, the path), ``world_plume.png`` (the true mean hits per
step on ``song-100`` and a free-energy search over its final posterior) and
``world_filament.png`` (the ``hmm`` search of ``farrell`` over its final source map, the
detections in red). ``--quick`` uses coarser meshes and shorter searches (for the tests).
"""

from __future__ import annotations

import argparse
from dataclasses import replace
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import numpy as np  # noqa: E402

import reciprocity as r  # noqa: E402
from reciprocity.scenarios import load_scenario  # noqa: E402
from reciprocity.viz.figures import field_figure  # noqa: E402
from reciprocity.viz.hmm import plot_search  # noqa: E402
from reciprocity.viz.lattice import lattice_figure  # noqa: E402
from reciprocity.viz.plume import search_figure  # noqa: E402

#: The files :func:`main` writes.
FIGURES = ("world_poisson.png", "world_lattice.png", "world_plume.png", "world_filament.png")


def _scenario(name: str, quick: bool, max_steps: int):
    """The built-in scenario `name`, its step cap cut to `max_steps` when `quick`."""
    sc = load_scenario(name)
    return replace(sc, max_steps=max_steps) if quick else sc


def poisson(out: Path, quick: bool) -> None:
    """The paper arena's true field with the reciprocity search's readings."""
    episode = r.run("paper", "reciprocity", seed=3, params={"h": 2.0 if quick else 1.0}, figures=True)
    truth = episode.truth                        # the environment's record: the true field and walls
    fig = field_figure(truth["field"], truth["true_arena"], title="poisson: the true field of paper, and a search")
    route = np.vstack([rec.route[:, :2] for rec in episode.records if len(rec.route)])
    points = np.array([o.position[:2] for rec in episode.records for o in rec.observations])
    fig.axes[0].plot(route[:, 0], route[:, 1], "-", color="red", lw=1)
    fig.axes[0].plot(points[:, 0], points[:, 1], "o", color="red", ms=5)
    fig.savefig(out / FIGURES[0], dpi=100)


def lattice(out: Path, quick: bool) -> None:
    """The true lattice and the RBPF searcher's path."""
    episode = r.run(_scenario("ristic-lattice", quick, 20), "rbpf", seed=1, figures=True)
    path = np.array([o.position[:2] for rec in episode.records for o in rec.observations])
    start = np.atleast_2d(episode.summary["start"])[0]
    lattice_figure(episode.truth, start=start, path=path).savefig(out / FIGURES[1], dpi=100)


def plume(out: Path, quick: bool) -> None:
    """Free-energy infotaxis on song-100 over its final posterior."""
    episode = r.run(_scenario("song-100", quick, 40), "free-energy", seed=2, figures=True)
    s = episode.summary
    search_figure(episode, title=f"plume: free energy on song-100, {s['steps']} steps").savefig(out / FIGURES[2],
                                                                                                 dpi=100)


def filament(out: Path, quick: bool) -> None:
    """The hidden-Markov map search of farrell."""
    episode = r.run(_scenario("farrell", quick, 300), "hmm", seed=2, figures=True)
    plot_search(episode, out / FIGURES[3])


def main(argv=None) -> list[Path]:
    """Write the four figures; return their paths."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="out/worlds", help="output folder (created)")
    ap.add_argument("--quick", action="store_true", help="coarser and shorter (tests)")
    a = ap.parse_args(argv)
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    for draw in (poisson, lattice, plume, filament):
        draw(out, a.quick)
    paths = [out / f for f in FIGURES]
    print("wrote", ", ".join(str(p) for p in paths))
    return paths


if __name__ == "__main__":
    main()
