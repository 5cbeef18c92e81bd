"""The plume figures: true hit rates, searches with their particle clouds, and teams.

    python examples/plume_figures.py [--out out/plume] [--seed 2] [--quick]

Writes ``rate_song-100.png``, ``rate_otto-2d.png`` and ``rate_hajieghrary.png`` (the true
mean hits per step of each scenario); ``search_free-energy_turn30.png``,
``search_infotaxis_turn30.png`` (song-100 with ±30° turns, seed ``--seed``) and
``search_infotaxis_turn3.png`` (the paper's printed ±3°, seed 1: it circles the
estimate); ``voi.png`` (the three hajieghrary teams and their messages). Every episode
runs with ``figures=True``, and the figures draw its record alone. ``--quick`` caps each
search at 25 steps (for the tests).
"""

from __future__ import annotations

import argparse
from dataclasses import replace
from pathlib import Path

import reciprocity as r
from reciprocity.scenarios import load_scenario
from reciprocity.viz.plume import rate_field_figure, search_figure, voi_figure

#: The files :func:`main` writes.
FIGURES = ("rate_song-100.png", "rate_otto-2d.png", "rate_hajieghrary.png", "search_free-energy_turn30.png",
           "search_infotaxis_turn30.png", "search_infotaxis_turn3.png", "voi.png")


def _scenario(name: str, quick: bool):
    """The built-in scenario `name`, cut to 25 steps when `quick`."""
    sc = load_scenario(name)
    return replace(sc, max_steps=25) if quick else sc


def main(argv=None) -> list[Path]:
    """Write the seven figures; return their paths."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="out/plume", help="output folder (created)")
    ap.add_argument("--seed", type=int, default=2, help="seed of the ±30° searches")
    ap.add_argument("--quick", action="store_true", help="searches of 25 steps at most (tests)")
    a = ap.parse_args(argv)
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    paths = []

    def save(fig, name):
        paths.append(out / name)
        fig.savefig(paths[-1], dpi=80)

    for sc in ("song-100", "otto-2d", "hajieghrary"):
        ep = r.run(sc, "random-walk", seed=0, params={"n_steps": 1}, agents=1, figures=True)
        save(rate_field_figure(ep, title=f"{sc}: true mean hits per step"), f"rate_{sc}.png")
    for name, turn, s in (("free-energy", 30, a.seed), ("infotaxis", 30, a.seed), ("infotaxis", 3, 1)):
        ep = r.run(_scenario("song-100", a.quick), name, seed=s, world={"max_turn": turn}, figures=True)
        save(search_figure(ep, title=f"{name}, ±{turn}°: {ep.summary['steps']} steps, {ep.summary['stop']}"),
             f"search_{name}_turn{turn}.png")
    teams = {label: r.run(_scenario("hajieghrary", a.quick), "voi", seed=0, agents=agents,
                          params={"share": share}, figures=True)
             for label, agents, share in (("1 searcher", 1, "all"), ("3, share all", 3, "all"),
                                          ("3, share by VoI", 3, "voi"))}
    save(voi_figure(teams), "voi.png")
    print("wrote", ", ".join(str(p) for p in paths))
    return paths


if __name__ == "__main__":
    main()
