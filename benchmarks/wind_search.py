"""Reciprocity in wind against the wall-blind baseline on ``flow`` scenarios (issue 38).

    PYTHONPATH=. python benchmarks/wind_search.py [--scenario paper-wind] [--seeds 20] [--h 2]
        [--strategies reciprocity-wind,free-space-wind] [--set KEY=VALUE ...] [--json FILE]
        [--speeds 0.3,1,3] [--results FILE.jsonl] [--near 10]

``--scenario`` takes a comma-separated list: flow scenario names or files
(``paper-wind``, ``maze-wind``) and ``generate:FAMILY:SEED``, a flow scenario on the
arena :func:`arenas.generate` draws (the wind enters on the left edge of its bounding
box and leaves on the right one, :func:`generated_flow`; families whose boundary is not
that rectangle are refused). ``--speeds`` runs each scenario at every inflow speed given
(cm/s; ``D`` and ``τ`` as the scenario has them), default the scenario's own.

Each seed draws the true source and the start as campaigns do (``random_source``:
:func:`reciprocity.campaign.worker.world_draw`), and every strategy runs on the same
draws. Prints one row per (scenario, speed, strategy): success with its Wilson 95 %
interval, converged, mean readings (= steps: one reading per round on the point
observer), mean path, mean and median error of the converged runs (cm), and the median
wall time per episode (the first episode on an arena and speed also builds the truth's
solver); then success split by the source's distance to the nearest wall
(below ``--near`` cm or not), pooled over the speeds.

With ``--results FILE.jsonl`` every episode is appended to FILE as one JSON line as soon
as it ends, and episodes already in FILE (same scenario, speed, strategy, seed, h and
``--set``) are not run again: a long table resumes where it stopped, and the table is
printed from the file.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np
from scipy.stats import binomtest

import arenas
from reciprocity.api import run
from reciprocity.campaign.worker import world_draw
from reciprocity.scenarios import from_dict, load_scenario

#: The physics of a generated arena's flow scenario: that of ``paper-wind``.
GENERATED_FLOW = dict(speed=1.0, D=5.0, tau=60.0, walls="impermeable", strength=100.0, detector=1.0,
                      success_radius=5.0, max_steps=80)
#: Share of each side edge left closed at both ends (``paper-wind``: 10 cm of 140).
EDGE_INSET = 1.0 / 14.0
#: Free boundary kept between an inflow or outflow segment and a wall meeting the edge, cm.
OBSTACLE_GAP = 0.5
#: Shortest inflow or outflow opening, cm.
MIN_OPENING = 4.0


def _value(text: str):
    try:
        return json.loads(text)
    except json.JSONDecodeError:
        return text


def _open_parts(arena, x: float, lo: float, hi: float) -> list:
    """The parts of the vertical edge ``x``, ``lo <= y <= hi`` no obstacle touches (less
    :data:`OBSTACLE_GAP` cm at each end), longer than :data:`MIN_OPENING` cm."""
    from shapely.geometry import LineString, Polygon
    from shapely.ops import unary_union
    walls = unary_union([Polygon(o).buffer(OBSTACLE_GAP) for o in arena.obstacles])
    rest = LineString([(x, lo), (x, hi)]).difference(walls)
    parts = getattr(rest, "geoms", [rest])
    out = []
    for part in parts:
        ys = sorted(float(y) for _, y in part.coords)
        if ys and ys[-1] - ys[0] >= MIN_OPENING:
            out.append([[x, ys[0]], [x, ys[-1]]])
    return out


def generated_flow(family: str, seed: int):
    """A flow scenario on ``arenas.generate(family, seed)``: the wind enters on the left
    edge of its rectangular boundary and leaves on the right one (each edge less
    :data:`EDGE_INSET` of its length at both ends, and less the walls that meet it), with
    :data:`GENERATED_FLOW`.

    Raises
    ------
    ValueError
        The arena's boundary is not its bounding box (ring, an L-shaped hall), or walls
        close a side edge.
    """
    arena = arenas.generate(family, seed)
    (x0, x1), (y0, y1) = arena.bounds
    corners = {(x0, y0), (x1, y0), (x1, y1), (x0, y1)}
    if len(arena.boundary) != 4 or {tuple(map(float, p)) for p in arena.boundary} != corners:
        raise ValueError(f"arena {arena.name!r} has no rectangular boundary: no left and right edge "
                         "to blow the wind through; choose another family")
    lo, hi = y0 + EDGE_INSET * (y1 - y0), y1 - EDGE_INSET * (y1 - y0)
    inflow, outflow = _open_parts(arena, x0, lo, hi), _open_parts(arena, x1, lo, hi)
    if not inflow or not outflow:
        raise ValueError(f"arena {arena.name!r}: walls close its left or right edge; choose another seed")
    data = dict(world="flow", arena={"generate": family, "seed": seed}, inflow=inflow, outflow=outflow,
                **GENERATED_FLOW)
    return from_dict(data, f"{arena.name}-wind")


def scenario_of(text: str):
    """A flow scenario by name or file, or ``generate:FAMILY:SEED``."""
    if text.startswith("generate:"):
        _, family, seed = text.split(":")
        return generated_flow(family, int(seed))
    return load_scenario(text)


def _done(path: Path | None) -> dict:
    """Episodes already in the results file, by (scenario, speed, strategy, seed, h, set)."""
    if path is None or not path.exists():
        return {}
    rows = [json.loads(line) for line in path.read_text().splitlines() if line.strip()]
    return {_key(r): r for r in rows}


def _key(r: dict) -> tuple:
    team = (r["agents"],) if r.get("agents", 1) > 1 else ()
    return (r["scenario"], r["speed"], r["strategy"], r["seed"], r["h"], json.dumps(r["set"], sort_keys=True)) + team


def episode(sc, name: str, seed: int, h: float, extra: dict, agents: int = 1) -> dict:
    """One episode on the seed's draw, as one results line (``agents`` observers, all
    starting at the draw's start)."""
    draw = world_draw(sc, seed)
    t0 = time.perf_counter()
    s = run(sc, name, seed=seed, params=dict(h=h, **extra), world=draw, agents=agents).summary
    wall = time.perf_counter() - t0
    source = np.asarray(draw["source"], dtype=float)
    return dict(scenario=sc.name, speed=float(sc.params["speed"]), strategy=name, seed=seed, h=h, set=extra,
                success=bool(s["success"]), converged=bool(s["converged"]), stop=s["stop_reason"],
                error=None if s["error"] is None else float(s["error"]), n_measurements=int(s["n_measurements"]),
                steps=int(s["steps"]), **({"agents": agents} if agents > 1 else {}),
                path_length=float(s["path_length"]), wall_s=wall, source=source.tolist(),
                wall_distance=float(sc.arena.wall_distance(source[None])[0]), estimate=s["estimate"])


def _wilson(k: int, n: int) -> str:
    ci = binomtest(k, n).proportion_ci(method="wilson")
    return f"[{100 * ci.low:.0f}, {100 * ci.high:.0f}]"


def table(runs: list[dict], length: dict) -> str:
    """One row per (scenario, speed, strategy), in the order first run."""
    lines = ["| scenario | speed cm/s (Pe = U L / D) | strategy | success [95 % CI] | converged | readings "
             "(= steps) | path cm | error cm (mean, converged) | error cm (median, converged) | s / episode (median) |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    cells: dict[tuple, list] = {}
    for r in runs:
        cells.setdefault((r["scenario"], r["speed"], r["strategy"]), []).append(r)
    for (scen, speed, name), rs in cells.items():
        ok = [r["error"] for r in rs if r["converged"]]
        err = np.array(ok if ok else [np.nan])
        k = sum(r["success"] for r in rs)
        pe = speed * length[scen]
        lines.append(f"| {scen} | {speed:g} ({pe:.0f}) | {name} | {k / len(rs):.0%} {_wilson(k, len(rs))} "
                     f"| {len(ok) / len(rs):.0%} | {np.mean([r['n_measurements'] for r in rs]):.1f} "
                     f"| {np.mean([r['path_length'] for r in rs]):.0f} | {np.mean(err):.2f} | {np.median(err):.2f} "
                     f"| {np.median([r['wall_s'] for r in rs]):.1f} |")
    return "\n".join(lines)


def near_walls(runs: list[dict], near: float) -> str:
    """Success by the source's distance to the nearest wall, pooled over speeds."""
    lines = [f"| scenario | strategy | success, source < {near:g} cm from a wall | success, ≥ {near:g} cm |",
             "|---|---|---|---|"]
    cells: dict[tuple, list] = {}
    for r in runs:
        cells.setdefault((r["scenario"], r["strategy"]), []).append(r)
    for (scen, name), rs in cells.items():
        parts = []
        for close in (True, False):
            sub = [r for r in rs if (r["wall_distance"] < near) == close]
            k = sum(r["success"] for r in sub)
            parts.append(f"{k}/{len(sub)}" + (f" ({k / len(sub):.0%})" if sub else ""))
        lines.append(f"| {scen} | {name} | {parts[0]} | {parts[1]} |")
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenario", default="paper-wind",
                    help="comma-separated flow scenarios: names, files, generate:FAMILY:SEED")
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--h", type=float, default=2.0, help="mesh size of the strategies' model, cm")
    ap.add_argument("--strategies", default="reciprocity-wind,free-space-wind")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="a strategy parameter")
    ap.add_argument("--json", help="write every episode's results line here (one JSON list)")
    ap.add_argument("--speeds", help="comma-separated inflow speeds, cm/s (default: the scenario's)")
    ap.add_argument("--results", type=Path, help="append every episode here as a JSON line; skip those in it")
    ap.add_argument("--near", type=float, default=10.0, help="wall distance of the split table, cm")
    ap.add_argument("--agents", type=int, default=1, help="observers (a team strategy for more than one)")
    args = ap.parse_args()
    extra = {k: _value(v) for k, v in (s.split("=", 1) for s in args.set)}
    done = _done(args.results)
    runs, length = [], {}
    for text in args.scenario.split(","):
        base = scenario_of(text)
        (x0, x1), (y0, y1) = base.arena.bounds
        length[base.name] = max(x1 - x0, y1 - y0) / base.params["D"]
        speeds = [float(v) for v in args.speeds.split(",")] if args.speeds else [base.params["speed"]]
        for speed in speeds:
            sc = base.with_world({"speed": speed})
            for name in args.strategies.split(","):
                for seed in range(args.seeds):
                    key = (sc.name, speed, name, seed, args.h, json.dumps(extra, sort_keys=True)) \
                        + ((args.agents,) if args.agents > 1 else ())
                    if key not in done:
                        done[key] = episode(sc, name, seed, args.h, extra, args.agents)
                        if args.results:
                            with args.results.open("a") as fh:
                                fh.write(json.dumps(done[key]) + "\n")
                    runs.append(done[key])
    print(f"{args.seeds} seeds (random source and start), strategy h = {args.h:g} cm"
          + (f", {extra}" if extra else "") + "; Pe over the arena's longer side")
    print(table(runs, length))
    print()
    print(near_walls(runs, args.near))
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(runs, fh, indent=1, default=float)


if __name__ == "__main__":
    main()
