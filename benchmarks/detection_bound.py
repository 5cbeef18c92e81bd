"""Where the core search's readings go (issue 33): finding the source's neighbourhood, then
pinning the source, against a coverage bound on the first.

A reading far from the source reads noise: the belief stays as wide as the prior until one
reading lands where the source's signal stands out. So a search's readings split in two:

* **detection**: the readings up to and including the first that reads at least ``κ σ``
  (``--kappa``, default 2; σ the stated noise), and
* **pinning**: the readings after it, until the stop.

The detection readings have a bound that needs no true source. With the strategy's own
model (its P1 Green's functions on the believed arena at h = 1 cm, the arena's strength
``c``), a reading at ``z`` *can detect* a source at ``x`` when ``c G(z, x) ≥ κ σ``: its
*footprint* is the share of the prior (sources uniform over the lattice points at least the
source clearance from the walls, at most 600 of them evenly spread) it can detect. A
sequence of readings ``z_1, z_2, …`` needs, on average over the prior,
``E = Σ_k P(no detection in z_1..z_{k-1})`` readings up to the detecting one. With every
footprint at most ``f_max`` of the prior, no sequence does
better than ``Σ_{k ≥ 1} max(0, 1 − (k − 1) f_max)`` (disjoint footprints of the largest
size); the greedy sequence (each reading where it detects most of what is still undetected)
reaches ``E_greedy``. Both treat a reading as detect / no detect: a reading below ``κ σ``
still tells a little, so the bound is a guide, not a theorem. Sources no reading can detect
are reported apart.

Each draw is also searched (point observer, map known, ``reciprocity`` at its defaults,
episode seed = draw), and its readings are split at the first detection.

    python benchmarks/detection_bound.py --draws 10 --out benchmarks/unseen_arenas/detection_bound.jsonl
    python benchmarks/detection_bound.py --table benchmarks/unseen_arenas/detection_bound.jsonl

One JSON line per draw is appended to ``--out`` as draws finish; a rerun resumes.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

from arguments import Parser, listed, among, number, whole

FAMILIES = ("rooms", "spiral", "ring", "pillars", "maze", "office")
#: Lattice spacing (cm) of the readings and sources of the bound, and the most lattice points.
SPACING, MAX_LATTICE = 4.0, 1500
#: Mesh size (cm) of the model (the reciprocity strategy's default; at 2 cm the largest
#: footprint of maze-1 is 11 % smaller, which would raise the bound).
H = 1.0
#: Most prior sources solved for (an even stride over the lattice's): each is one solve.
MAX_SOURCES = 600
#: The observer's clearance from the walls (cm; the reciprocity strategy's default).
CLEARANCE = 3.0


def footprints(arena, noise: float, kappa: float) -> tuple[np.ndarray, float]:
    """The detection matrix of `arena`'s model: ``D[z, x]`` for reading points ``z`` and
    prior sources ``x`` (lattice points), and the share of the prior no reading detects.

    Parameters
    ----------
    arena : Arena
        The generated arena (its geometry, strength and source clearance are used).
    noise, kappa : float
        Reading noise σ (signal units) and detection threshold in σ.
    """
    from reciprocity.models.green import cached_solver
    from reciprocity.strategies.information import lattice_nodes
    geometry = arena.without_scenario()
    solver = cached_solver(geometry, H)
    spacing = SPACING
    while len(idx := lattice_nodes(solver.nodes, spacing)) > MAX_LATTICE:
        spacing *= 1.25
    pts = solver.nodes[idx]
    gap = geometry.wall_distance(pts)
    sources = idx[gap >= max(arena.source_clearance - H, 0.0)]
    sources = sources[np.linspace(0, len(sources) - 1, min(len(sources), MAX_SOURCES)).round().astype(int)]
    readers = idx[gap >= CLEARANCE]
    c = float(arena.strength)
    detect = np.zeros((len(readers), len(sources)), dtype=bool)
    for lo in range(0, len(sources), 500):                   # G(·, x) for a block of sources
        block = sources[lo:lo + 500]
        rhs = np.zeros((solver.basis.N, len(block)))
        rhs[block, np.arange(len(block))] = 1.0
        detect[:, lo:lo + len(block)] = c * solver.solve(rhs)[readers] >= kappa * noise
    return detect, float(1.0 - detect.any(axis=0).mean())


def coverage_bounds(detect: np.ndarray) -> tuple[float, float, float]:
    """``(f_max, lower, greedy)``: the largest footprint (share of the prior), the bound on
    the expected readings up to a detection, and the greedy sequence's expected readings
    (both over the detectable sources; see the module's text)."""
    detectable = detect.any(axis=0)
    d = detect[:, detectable]
    if d.shape[1] == 0:
        return 0.0, float("inf"), float("inf")
    f = d.mean(axis=1)
    f_max = float(f.max())
    k = np.arange(int(np.ceil(1.0 / f_max)))
    lower = float(np.sum(np.maximum(0.0, 1.0 - k * f_max)))
    left = np.ones(d.shape[1], dtype=bool)
    greedy, undetected = 0.0, 1.0
    while left.any():
        greedy += undetected
        gain = d[:, left].sum(axis=1)
        left &= ~d[int(np.argmax(gain))]
        undetected = left.mean()
    return f_max, lower, greedy


def search(arena, seed: int, noise: float, kappa: float) -> dict:
    """The default search on `arena`: readings in all, and the index (1-based) of the first
    reading at least ``κ σ`` (None if none is)."""
    from reciprocity.env import SearchEnv, rollout
    from reciprocity.scenarios import load_scenario
    from reciprocity.strategies import STRATEGIES
    from reciprocity.strategies.agent import StrategyAgent
    episode = rollout(SearchEnv(load_scenario(arena), world={"noise": noise}),
                      StrategyAgent(STRATEGIES["reciprocity"], {}), seed)
    readings = [float(r) for step in episode.trace if step.get("kind") == "signal"
                for r in np.atleast_1d(step.get("readings", []))]
    first = next((k + 1 for k, r in enumerate(readings) if r >= kappa * noise), None)
    s = episode.summary
    return dict(n=int(s["n_measurements"]), first_detection=first, success=bool(s["success"]),
                error=s["error"])


def record(out: Path, families, draws: int, start: int, noise: float, kappa: float) -> None:
    """Append one line per (family, draw) not yet in `out`."""
    import arenas
    done = set()
    if out.exists():
        done = {(r["family"], r["draw"], r["noise"], r["kappa"]) for r in map(json.loads, out.read_text().splitlines())}
    with out.open("a") as f:
        for i in range(start, start + draws):
            for fam in families:
                if (fam, i, noise, kappa) in done:
                    continue
                arena = arenas.generate(fam, i)
                detect, never = footprints(arena, noise, kappa)
                f_max, lower, greedy = coverage_bounds(detect)
                row = dict(family=fam, draw=i, noise=noise, kappa=kappa, f_max=f_max, lower=lower,
                           greedy=greedy, never=never, **search(arena, i, noise, kappa))
                f.write(json.dumps(row) + "\n")
                f.flush()


def table(paths) -> str:
    """The per-family table of the rows in `paths` (JSON lines)."""
    rows = [json.loads(line) for p in paths for line in Path(p).read_text().splitlines() if line]
    out = ["| noise | family | draws | largest footprint (share of prior), median | detection readings: "
           "bound / greedy / search, median | pinning readings, median | readings, median | "
           "undetectable share, max |",
           "|---|---|---:|---:|---|---:|---:|---:|"]
    keys = sorted({(r["noise"], r["family"]) for r in rows}, key=lambda k: (k[0], FAMILIES.index(k[1])))
    for noise in sorted({k[0] for k in keys}):
        for fam in [k[1] for k in keys if k[0] == noise] + ["all"]:
            sel = [r for r in rows if r["noise"] == noise and fam in ("all", r["family"])]
            det = [r["first_detection"] if r["first_detection"] is not None else r["n"] for r in sel]
            pin = [r["n"] - d for r, d in zip(sel, det)]
            med = lambda v: f"{np.median(v):.3g}"
            out.append(f"| {noise:g} | {fam} | {len(sel)} | {med([r['f_max'] for r in sel])} | "
                       f"{med([r['lower'] for r in sel])} / {med([r['greedy'] for r in sel])} / {med(det)} | "
                       f"{med(pin)} | {med([r['n'] for r in sel])} | {max(r['never'] for r in sel):.3f} |")
    return "\n".join(out)


def main(argv=None) -> int:
    p = Parser.of(__file__, __doc__)
    p.add_argument("--families", type=listed(among(FAMILIES)), default=list(FAMILIES),
                   help="comma-separated families")
    p.add_argument("--draws", type=whole(1, 500), default=10, help="draws per family")
    p.add_argument("--start", type=whole(0), default=0, help="first draw")
    p.add_argument("--noise", type=number(0, low_open=True), default=12.0, help="reading noise (signal units)")
    p.add_argument("--kappa", type=number(0, low_open=True), default=2.0, help="detection threshold, in noise sd")
    p.add_argument("--out", default="detection_bound.jsonl", help="JSON lines, appended to (a rerun resumes)")
    p.add_argument("--table", nargs="+", help="print the table of these JSON-lines files instead")
    args = p.parse_args(argv)
    if args.table:
        for path in args.table:
            if not Path(path).is_file():
                p.error(f"--table: {path!r} is not a file")
        print(table(args.table))
        return 0
    out = Path(args.out)
    p.output_folder(out.parent)
    if out.is_symlink():
        p.error(f"--out: {args.out!r} is a symbolic link; give a real file")
    out = p.output_file(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    record(out, args.families, args.draws, args.start, args.noise, args.kappa)
    print(table([out]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
