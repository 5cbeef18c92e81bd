"""Imaging-function figure (the paper's Fig. 4) for a reciprocity search on `paper`.

    python examples/imaging_figure.py [--out out/examples] [--seed 3]
"""

import argparse
from pathlib import Path

import arenas
from reciprocity.viz.figures import imaging_steps_figure
from reciprocity import execute


def main(out_dir="out/examples", seed: int = 3) -> float:
    """Run the search, write ``imaging_steps.png`` into `out_dir`; return the error (cm)."""
    arena = arenas.load("paper")
    episode, strategy, _ = execute(arena, "reciprocity", seed=seed)
    n = episode.summary["n_measurements"]
    fig = imaging_steps_figure(episode, strategy.imaging, arena, eps=strategy.eps,
                               steps=range(1, n + 1), ncols=min(n, 4))
    out = Path(out_dir) / "imaging_steps.png"
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=150)
    s = episode.summary
    print(f"{n} measurements, estimate ({s['estimate'][0]:.2f}, {s['estimate'][1]:.2f}), "
          f"error {s['error']:.2f} cm -> {out}")
    return s["error"]


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="out/examples", help="output folder (created)")
    ap.add_argument("--seed", type=int, default=3)
    a = ap.parse_args()
    main(a.out, seed=a.seed)
