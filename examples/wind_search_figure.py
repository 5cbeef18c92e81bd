"""Reciprocity in wind step by step: the posterior over the source after each doubling of the readings.

    python examples/wind_search_figure.py --out DIR [--seed 3] [--h 2] [--truth-h 0.5] [--max-steps 80] [--video]

One ``reciprocity-wind`` episode on ``paper-wind`` (the source and start drawn for
`--seed` as campaigns draw them). The figure is drawn from the episode's record alone
(``run(..., figures=True)``): the strategy's posterior after readings 1, 2, 4, 8, ... and
the last (:meth:`CountPosterior.first <reciprocity.beliefs.counts.CountPosterior.first>`),
the readings as dots, and, from the truth of the finished episode, the wind's
streamlines and the true source (red star). Writes ``wind_search_steps.png``, and with
``--video`` the video of the search, ``wind_search.mp4`` (:func:`reciprocity.viz.count_video.write_count_video`).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from reciprocity.api import run
from reciprocity.campaign.worker import world_draw
from reciprocity.scenarios import load_scenario
from reciprocity.viz.count_video import write_count_video
from reciprocity.viz.figures import count_steps_figure


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=".", help="folder for the PNG file")
    ap.add_argument("--seed", type=int, default=3, help="episode seed (source and start)")
    ap.add_argument("--h", type=float, default=2.0, help="mesh size of the strategy's model, cm")
    ap.add_argument("--truth-h", type=float, default=0.5, help="mesh size of the truth's solver, cm")
    ap.add_argument("--max-steps", type=int, default=80, help="readings before the search stops at its cap")
    ap.add_argument("--video", action="store_true", help="also write the video, wind_search.mp4")
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    sc = load_scenario("paper-wind").with_world({"truth_h": args.truth_h})
    episode = run(sc, "reciprocity-wind", seed=args.seed, params=dict(h=args.h, max_steps=args.max_steps),
                  world=world_draw(sc, args.seed), figures=True)
    belief = episode.belief
    fig = count_steps_figure(episode, belief["posterior"], belief["triangulation"], sc.arena,
                             wind=episode.truth["wind"])
    path = out / "wind_search_steps.png"
    fig.savefig(path, dpi=110)
    if args.video:
        write_count_video(out / "wind_search.mp4", episode, sc.arena, dpi=80)
    s = episode.summary
    print(f"{path}: {s['n_measurements']} readings, error {s['error']:.2f} cm, {s['stop_reason']}")
    return s


if __name__ == "__main__":
    main()
