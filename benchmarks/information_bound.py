"""How few readings can a Poisson search need? The information bound of issue 24, computed.

    python benchmarks/information_bound.py [--arenas paper,maze] [--points 400] [--campaign DIR ...]

The search starts with the source uniform over the free region Ω (area A, cm²) and stops
once its region of possible sources is below ``area_tol`` (40 cm², the reciprocity
strategy's default). It must remove about ``log(A / area_tol)`` nats of entropy. One
reading ``y = c G(z, S) + ε``, ε ~ N(0, σ²), carries

    I(S; y_z) = h(y_z) − ½ log(2π e σ²)     nats,

where ``y_z`` is the mixture of N(c G(z, s), σ²) over the sources s of the belief. Under the
uniform prior this is computed at many candidate points z of Ω (the strategy's own P1
Green's functions at h = 1 cm, node areas as weights, h(y) by quadrature on a grid of σ/20);
the largest is I_max. The issue's bound is

    n ≥ log(A / area_tol) / I_max.

It holds only for a searcher whose every reading carries at most I_max, and a belief
narrower than the prior makes a reading carry more; the measured searches do need fewer
readings than it says. A bound that holds for every belief caps each reading by the
Gaussian's entropy at the largest variance a signal in ``[x_min, x_max]`` can have,

    I(S; y_z) ≤ ½ log(1 + (x_max(z) − x_min(z))² / (4σ²)) ≤ C,   n ≥ log(A / area_tol) / C,

with ``x = c G(z, ·)`` over the nodes of Ω and C its largest value over the candidate points.
Both depend on no true source (the prior is uniform): one number per arena and noise. With ``--campaign`` (folders of `reciprocity
campaign` runs, e.g. of benchmarks/search_point.yaml) it prints the median readings of each
strategy beside it.
"""

from __future__ import annotations

import argparse
import math

import numpy as np

import arenas
from reciprocity.fem import GreenSolver
from reciprocity.fem.mesh import node_areas


def mixture_entropy(x: np.ndarray, w: np.ndarray, sigma: float) -> float:
    """Differential entropy (nats) of ``Σ_i w_i N(x_i, σ²)``: the weights binned on a grid of
    σ/20, convolved with the Gaussian, ``−∫ p log p`` by the midpoint rule."""
    step = sigma / 20.0
    lo, hi = x.min() - 8 * sigma, x.max() + 8 * sigma
    n = int(math.ceil((hi - lo) / step)) + 1
    if n > 5_000_000:
        raise ValueError(f"signal range {hi - lo:.3g} too wide for a grid of sigma/20")
    mass = np.bincount(np.clip(((x - lo) / step).astype(np.int64), 0, n - 1), weights=w, minlength=n)
    k = np.arange(-int(8 * 20), int(8 * 20) + 1) * step
    kernel = np.exp(-0.5 * (k / sigma) ** 2)
    kernel /= kernel.sum() * step
    p = np.convolve(mass, kernel, mode="same")
    p = p[p > 0]
    return float(-np.sum(p * np.log(p)) * step)


def reading_information(solver: GreenSolver, z: np.ndarray, strength: float, sigma: float,
                        weights: np.ndarray) -> float:
    """I(S; y_z) in nats under the prior `weights` over the solver's nodes."""
    x = strength * solver.green(z).dofs
    return mixture_entropy(x, weights, sigma) - 0.5 * math.log(2 * math.pi * math.e * sigma ** 2)


def bound(arena_name: str, n_points: int, sigma: float, area_tol: float, h: float = 1.0) -> dict:
    """The bound's parts for one arena: area, entropy to remove, I at the start and I_max."""
    arena = arenas.load(arena_name)
    solver = GreenSolver(arena, h=h)
    areas = node_areas(solver.nodes, solver.triangles)
    weights = areas / areas.sum()
    pts = arena.random_free_points(n_points, np.random.default_rng(0), clearance=2.0)
    info = np.array([reading_information(solver, z, arena.strength, sigma, weights) for z in pts])
    spans = np.array([np.ptp(arena.strength * solver.green(z).dofs) for z in pts])
    cap = float(np.max(0.5 * np.log1p(spans ** 2 / (4 * sigma ** 2))))
    start = reading_information(solver, np.asarray(arena.start[:2]), arena.strength, sigma, weights)
    need = math.log(arena.area / area_tol)
    best = int(np.argmax(info))
    return dict(arena=arena_name, area=arena.area, need=need, i_start=start, i_max=float(info[best]),
                z_max=pts[best].tolist(), i_median=float(np.median(info)), n_issue=need / float(info[best]),
                cap=cap, n_valid=need / cap)


def measured(directories) -> dict:
    """Median readings per (scenario, strategy) over campaign folders."""
    import duckdb

    from reciprocity.campaign import episodes_sql
    out = {}
    for d in directories:
        rows = duckdb.sql(f"SELECT scenario, strategy, median(n_measurements), count(*) FROM {episodes_sql(d)} "
                          "WHERE error_message IS NULL GROUP BY ALL").fetchall()
        for sc, st, med, n in rows:
            out[(sc, st)] = (med, n)
    return out


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--arenas", default="paper,maze")
    ap.add_argument("--points", type=int, default=400, help="candidate reading points per arena")
    ap.add_argument("--sigma", type=float, default=12.0, help="noise sd (the point observer's default)")
    ap.add_argument("--area-tol", type=float, default=40.0, help="cm², the reciprocity strategy's default")
    ap.add_argument("--campaign", action="append", default=[], help="campaign folder(s) to compare with")
    args = ap.parse_args(argv)
    seen = measured(args.campaign) if args.campaign else {}
    print(f"sigma {args.sigma:g}, area_tol {args.area_tol:g} cm², {args.points} candidate points, P1 at h = 1 cm\n")
    print("| arena | free area cm² | log(A / area_tol) nats | I at the start | I median | I_max (at) | "
          "the issue's n ≥ | cap C | valid n ≥ | measured median readings |")
    print("|---|---:|---:|---:|---:|---|---:|---:|---:|---|")
    for name in args.arenas.split(","):
        b = bound(name, args.points, args.sigma, args.area_tol)
        meas = ", ".join(f"{st} {med:g} ({n} runs)" for (sc, st), (med, n) in sorted(seen.items()) if sc == name)
        print(f"| {name} | {b['area']:.0f} | {b['need']:.2f} | {b['i_start']:.2f} | {b['i_median']:.2f} | "
              f"{b['i_max']:.2f} ({b['z_max'][0]:.0f}, {b['z_max'][1]:.0f}) | {b['n_issue']:.2f} | "
              f"{b['cap']:.2f} | {b['n_valid']:.2f} | {meas or '–'} |",
              flush=True)


if __name__ == "__main__":
    main()
