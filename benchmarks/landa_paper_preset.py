"""Which ε and A_ε stop eq. (8) on the car, measured offline (issue 33, the paper preset).

Records the readings of reciprocity searches under the paper's rules on the simulated car
as the paper ran it (``--protocol paper``'s car: one raw 30 Hz sample per reading, the
bank of value functions 12.7 cm apart; σ of eq. (7) the readings' own noise), each run
to ``MAX_READINGS`` readings with its stop switched off, then re-evaluates the stop rule
on the recorded readings over a grid of ε and A_ε: at which reading each pair would have
stopped, and how far off its estimate was then. Where the paper's region (eq. (8), the
mean of the maps) gives no pair that stops with a good estimate, the same grid is run
for the smallest deviations from it: the product of the same maps, and a credible region
(the smallest set of nodes holding a share of the normalised ``P_M``).

The readings up to any reading do not depend on ε and A_ε: the paper's next-point rule
(step 13, the nearest point of ``{v_k > I_k}``) does not look at the region. So one
recording serves every pair.

Usage (one process; the recording takes about a minute of computing per run and is
resumed when re-run; the evaluation a few seconds)::

    python benchmarks/landa_paper_preset.py record --runs 10 --out runs/landa_paper_preset
    python benchmarks/landa_paper_preset.py evaluate --out runs/landa_paper_preset

Results: ``benchmarks/landa_paper_preset.md``.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np
from scipy import stats

#: Readings per recorded run: the search's cap (MAX_STEPS of the preset's table runs).
MAX_READINGS = 30
#: The car as the paper ran it (the table's ``--protocol paper``).
PAPER_CAR = {"planner": "bank", "bank_spacing": 12.7, "dwell": 1 / 30}
#: Separation of observation points, cm: one bank spacing. The car measures at the bank's
#: lattice point nearest to the requested one, so with a smaller d (the earlier preset's
#: 6 cm) every next point snaps back to the lattice point already read and the car never
#: moves (measured: 30 of 30 runs read 30 times at the start).
D = 12.7
#: The paper's success radius, cm.
SUCCESS_RADIUS = 5.0
EPS = (0.1, 0.2, 0.3, 0.5, 0.7, 0.8, 0.9, 0.95)
AREAS = (20.0, 40.0, 80.0, 200.0, 500.0, 1000.0, 2000.0)
#: Shares of the normalised P_M held by the credible regions tried.
CREDIBLE = (0.5, 0.9, 0.95)


def record(out: Path, runs: int, seed0: int = 0, platform: str = "car") -> None:
    """Run `runs` searches (seeds seed0, seed0 + 1, ...) on `platform` (the car as the
    paper ran it, or the point observer: the world's readings, noise 12) and write each
    run's readings to ``out/run-SEED.json`` (skipped when there)."""
    from reciprocity import api
    out.mkdir(parents=True, exist_ok=True)
    for seed in range(seed0, seed0 + runs):
        path = out / f"run-{seed}.json"
        if path.exists():
            continue
        params = {"preset": "paper", "d": D, "area_tol": 1e-3, "max_steps": MAX_READINGS}
        options = dict(PAPER_CAR) if platform == "car" else None
        episode, strategy, _ = api.execute("paper", "reciprocity", seed=seed, params=params,
                                           platform=platform, platform_options=options)
        im, s = strategy.imaging, episode.summary
        path.write_text(json.dumps(dict(seed=seed, source=s["source"], sigma=strategy.sigma_used,
                                        strength=float(im.strength), points=im.points.tolist(),
                                        readings=im.readings.tolist(), saturated=im.saturated.tolist(),
                                        stop_reason=s["stop_reason"], sim_time_s=s["sim_time_s"])))
        print(f"seed {seed}: {len(im.readings)} readings, sigma {strategy.sigma_used:.2f}, "
              f"stop {s['stop_reason']}", flush=True)


def credible_area(im, share: float) -> float:
    """Area (cm²) of the smallest set of nodes holding `share` of the normalised ``P_M``
    (each node weighted by its area)."""
    w = im.weights()
    order = np.argsort(-w / im._node_areas)
    inside = order[: int(np.searchsorted(np.cumsum(w[order]), share)) + 1]
    return float(im._node_areas[inside].sum())


def replay(run: dict, solver, combine: str):
    """The imaging maps after each reading of `run`: yields (k, ImagingMap)."""
    from reciprocity.beliefs.imaging import ImagingMap
    im = ImagingMap(solver, run["sigma"], strength=run["strength"], combine=combine)
    for k, (z, r, sat) in enumerate(zip(run["points"], run["readings"], run["saturated"]), 1):
        im.add(z, r, saturated=sat)
        yield k, im


def regions(runs: list[dict], solver) -> dict:
    """Per region rule and run: per reading, the region's area for every threshold and
    the estimate's error (cm)."""
    out = {}
    for combine in ("mean", "product"):
        for run in runs:
            src = np.asarray(run["source"], dtype=float)
            for k, im in replay(run, solver, combine):
                err = float(np.hypot(*(im.estimate() - src)))
                out.setdefault((combine, "eps"), {}).setdefault(run["seed"], []).append(
                    ([im.area(e) for e in EPS], err))
                out.setdefault((combine, "credible"), {}).setdefault(run["seed"], []).append(
                    ([credible_area(im, c) for c in CREDIBLE], err))
    return out


def t_interval(x) -> tuple[float, float, float]:
    x = np.asarray(x, dtype=float)
    m = float(x.mean())
    if len(x) < 2:
        return m, math.nan, math.nan
    half = float(stats.t.ppf(0.975, len(x) - 1) * x.std(ddof=1) / math.sqrt(len(x)))
    return m, m - half, m + half


def wilson(k: int, n: int) -> tuple[float, float, float]:
    z = 1.959963984540054
    p = k / n
    c = (p + z * z / (2 * n)) / (1 + z * z / n)
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return p, max(0.0, c - h), min(1.0, c + h)


def stops(per_run: dict, j: int, area_tol: float) -> list[tuple[int, float, bool, bool]]:
    """Per run: (readings at the stop, error then, whether the rule stopped it, whether
    the region was empty then) for threshold index `j` and tolerance `area_tol` (a run
    that never stops: its last reading)."""
    out = []
    for steps in per_run.values():
        hit = next((k for k, (areas, _) in enumerate(steps, 1) if areas[j] < area_tol), None)
        k = hit or len(steps)
        out.append((k, steps[k - 1][1], hit is not None, hit is not None and steps[k - 1][0][j] == 0))
    return out


def table(per_run: dict, thresholds, what: str) -> list[str]:
    """Markdown rows: readings (mean, t interval), stopped (of which on an empty region),
    success (Wilson), median and 90th percentile of the error."""
    lines = [f"| {what} | A_ε cm² | readings | stopped (empty) | success (≤ 5 cm) | error median | error p90 |",
             "|---|---:|---|---:|---|---:|---:|"]
    for j, t in enumerate(thresholds):
        for a in AREAS:
            res = stops(per_run, j, a)
            n = len(res)
            k = [r[0] for r in res]
            ok = sum(1 for r in res if r[2] and r[1] <= SUCCESS_RADIUS)
            err = np.array([r[1] for r in res])
            m, lo, hi = t_interval(k)
            p, plo, phi = wilson(ok, n)
            lines.append(f"| {t:g} | {a:g} | {m:.1f} [{lo:.1f}, {hi:.1f}] | "
                         f"{sum(r[2] for r in res)}/{n} ({sum(r[3] for r in res)}) | "
                         f"{ok}/{n} [{100 * plo:.0f}, {100 * phi:.0f} %] | {np.median(err):.2f} | "
                         f"{np.percentile(err, 90):.1f} |")
    return lines


def evaluate(out: Path) -> str:
    """The re-evaluation of every recorded run in `out`, as Markdown."""
    import arenas
    from reciprocity.models.green import cached_solver
    runs = [json.loads(p.read_text()) for p in sorted(out.glob("run-*.json"))]
    if not runs:
        raise SystemExit(f"no recorded runs in {out}: run 'record' first")
    solver = cached_solver(arenas.load("paper").without_scenario(), 1.0)
    res = regions(runs, solver)
    sigma = np.mean([r["sigma"] for r in runs])
    parts = [f"{len(runs)} runs, σ = {sigma:.2f} signal units, "
             f"{min(len(r['readings']) for r in runs)}-{max(len(r['readings']) for r in runs)} readings each.", ""]
    for (combine, kind), per_run in res.items():
        name = {"mean": "eq. (8), the mean of the maps", "product": "the product of the maps"}[combine]
        if kind == "eps":
            parts += [f"### {name}: region {{P_M ≥ ε}}", ""] + table(per_run, EPS, "ε") + [""]
        else:
            parts += [f"### {name}: credible region (share of the normalised P_M)", ""] + \
                table(per_run, CREDIBLE, "share") + [""]
    return "\n".join(parts)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("what", choices=("record", "evaluate"))
    ap.add_argument("--out", type=Path, default=Path("runs/landa_paper_preset"))
    ap.add_argument("--runs", type=int, default=10, help="runs to record (seeds 0, 1, ...)")
    ap.add_argument("--platform", choices=("car", "point"), default="car",
                    help="the car as the paper ran it (default), or the point observer")
    a = ap.parse_args(argv)
    if a.what == "record":
        record(a.out, a.runs, platform=a.platform)
    else:
        print(evaluate(a.out))


if __name__ == "__main__":
    main()
