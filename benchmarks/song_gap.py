"""Why are our Song et al. (2019) Table 1 times shorter than the paper's? One set-up difference at a
time.

Every variant is the scenario ``song-<side>`` with world overrides (``world``), strategy
parameters (``params``, per strategy name or ``"*"`` for all), a step cap (``max_steps``)
and, for a few filter questions the strategies have no parameter for, a patch applied in
the worker (``patch``). Seeds are shared, so a variant is compared with the baseline
seed by seed (paired Δ with a 95 % interval). Steps are counted over all runs, a run
that stops at the cap counting with the cap; the mean over the runs that found the
source is printed beside it.

    nice -n 10 python benchmarks/song_gap.py --side 100 --seeds 40 \
        --variant base --variant corners --variant q0_0.5

Results are cached per (side, variant spec, strategy, seed) in ``--out`` (JSON lines).
See benchmarks/song_gap.md for the findings.
"""

from __future__ import annotations

import argparse
import json
import math
import time
from multiprocessing import Pool

import numpy as np

from plume_bench import cached_seeds, mean_ci

from reciprocity.campaign.tables.song2019 import SONG_SCALES, SONG_TABLE1


def corners(side, inset=0.0):
    h = side / 2 - inset
    return {"source": [-h, h], "start": [h, -h, math.pi / 2]}      # world overrides: radians


#: name -> spec; ``world`` values may be callables of the side.
VARIANTS = {
    # our reproduction (the table's setting): 1/3 of the side from the centre, wind +x,
    # heading +y, turns of at most 30 degrees
    "base": {"world": {"max_turn": 30}},
    # -- geometry -------------------------------------------------------------------------
    "corners": {"world": lambda L: dict(max_turn=30, **corners(L))},
    "corners_in5": {"world": lambda L: dict(max_turn=30, **corners(L, 5))},
    "head0": {"world": lambda L: dict(max_turn=30, start=[L / 3, -L / 3, 0.0])},
    "head180": {"world": lambda L: dict(max_turn=30, start=[L / 3, -L / 3, math.pi])},
    "head135": {"world": lambda L: dict(max_turn=30, start=[L / 3, -L / 3, 0.75 * math.pi])},
    # wind -y (Vergassola's direction): the mirror image of +x when the heading is mirrored too
    "wind270_head180": {"world": lambda L: dict(max_turn=30, wind_direction=270, start=[L / 3, -L / 3, math.pi])},
    "wind270": {"world": {"max_turn": 30, "wind_direction": 270}},
    # searcher upwind of the source: the plume leaves the area
    "wind180": {"world": {"max_turn": 30, "wind_direction": 180}},
    "wind90": {"world": {"max_turn": 30, "wind_direction": 90}},
    # wind along the diagonal from source to start (start straight downwind)
    "wind315": {"world": {"max_turn": 30, "wind_direction": 315}},
    # -- hit rate -------------------------------------------------------------------------
    "q0_1": {"world": {"max_turn": 30, "rate": 1}},
    "q0_0.5": {"world": {"max_turn": 30, "rate": 0.5}},
    "q0_0.25": {"world": {"max_turn": 30, "rate": 0.25}},
    "q0_4": {"world": {"max_turn": 30, "rate": 4}},
    "dt0.25": {"world": {"max_turn": 30, "dt": 0.25}},
    # -- motion ---------------------------------------------------------------------------
    "turn3": {"world": {"max_turn": 3}},
    "turn12": {"world": {"max_turn": 12}},
    "turn60": {"world": {"max_turn": 60}},
    "turn180": {"world": {"max_turn": 180, "n_turns": 13}},
    # "delta = 0.25" read as the step: 0.25 per step, exposure 0.25 per step, the same
    # turning radius per unit length as +-30 deg per unit step; steps are 4 per time unit
    "step0.25": {"world": {"max_turn": 7.5, "step": 0.25, "dt": 0.25, "found_radius": 3}, "max_steps": 8000},
    # -- filter ---------------------------------------------------------------------------
    "no_exclude": {"world": {"max_turn": 30}, "patch": "no_exclude"},
    "uniform_prior": {"world": {"max_turn": 30}, "patch": "uniform_prior"},
    "mcmc5": {"world": {"max_turn": 30}, "params": {"*": {"mcmc_steps": 5}}},
    "particles2000": {"world": {"max_turn": 30}, "params": {"*": {"particles": 2000}}},
    "particles200": {"world": {"max_turn": 30}, "params": {"*": {"particles": 200}}},
    # -- free-energy parameters -----------------------------------------------------------
    "fe_T0": {"world": {"max_turn": 30}, "params": {"free-energy": {"alpha": 1e-12}}},
    "fe_alpha1": {"world": {"max_turn": 30}, "params": {"free-energy": {"alpha": 1.0}}},
    "fe_alpha100": {"world": {"max_turn": 30}, "params": {"free-energy": {"alpha": 100.0}}},
    "fe_alpha1e4": {"world": {"max_turn": 30}, "params": {"free-energy": {"alpha": 1e4}}},
}


def resolve(name: str, side: int) -> dict:
    """A variant spec made concrete for `side`; ``name`` may combine variants with ``+``
    (later ones win), or give world keys inline as ``key=json``."""
    world, params, patch, max_steps = {}, {}, [], None
    for part in name.split("+"):
        if "=" in part:
            k, v = part.split("=", 1)
            world[k] = json.loads(v)
            continue
        spec = VARIANTS[part]
        w = spec.get("world", {})
        world.update(w(side) if callable(w) else w)
        for s, p in spec.get("params", {}).items():
            params.setdefault(s, {}).update(p)
        if spec.get("patch"):
            patch.append(spec["patch"])
        max_steps = spec.get("max_steps", max_steps)
    return dict(world=world, params=params, patch=sorted(patch), max_steps=max_steps)


def _apply_patches(patches):
    from reciprocity.beliefs import particles as P
    from reciprocity.strategies import infotaxis as I
    if "no_exclude" in patches:
        # the paper's filter (eq. 7) weighs particles by the Poisson likelihood only; ours
        # also rules out particles within R_s of every place visited
        orig = P.ParticleBelief.update

        def update(self, obs):
            fr = self.found_radius
            self.found_radius = 0.0
            try:
                orig(self, obs)
            finally:
                self.found_radius = fr
        P.ParticleBelief.update = update
    if "uniform_prior" in patches:
        orig_make = I.make_belief

        def make_belief(nominal, rng, **kw):
            b = orig_make(nominal, rng, **kw)
            (x0, x1), (y0, y1) = nominal["bounds"]
            b.x = np.column_stack([rng.uniform(x0, x1, b.M), rng.uniform(y0, y1, b.M)])
            return b
        I.make_belief = make_belief


def _scenario(side: int, max_steps: int | None):
    """``song-<side>``, with another step cap where the variant sets one."""
    name = f"song-{side}"
    if max_steps is None:
        return name
    from dataclasses import replace
    from reciprocity.scenarios import load_scenario
    return replace(load_scenario(name), max_steps=int(max_steps))


_PATCHED = None


def _one(job):
    global _PATCHED
    side, spec, strategy, seed = job
    if _PATCHED is None:
        _apply_patches(spec["patch"])
        _PATCHED = tuple(spec["patch"])
    assert _PATCHED == tuple(spec["patch"]), "one patch set per worker pool"
    from reciprocity.api import run
    params = dict(spec["params"].get("*", {}), **spec["params"].get(strategy, {}))
    c0 = time.process_time()
    s = run(_scenario(side, spec["max_steps"]), strategy, seed=seed, params=params,
            world=spec["world"]).summary
    return dict(seed=seed, steps=int(s["steps"]), success=bool(s["success"]),
                cpu=time.process_time() - c0)



def collect(side, names, strategies, seeds, out, workers):
    """Results per (variant, strategy); one worker pool per set of patches (a patch
    changes a worker's modules for good)."""
    specs = {name: resolve(name, side) for name in names}
    results = {}
    for patch in sorted({tuple(sp["patch"]) for sp in specs.values()}):
        with Pool(workers) as pool:
            for name, spec in specs.items():
                if tuple(spec["patch"]) != patch:
                    continue
                for strat in strategies:
                    results[name, strat] = cached_seeds(out, [side, spec, strat], seeds, _one,
                                                        lambda s: (side, spec, strat, s), pool)
    return {(n, st): results[n, st] for n in names for st in strategies}


def parse(argv=None) -> argparse.Namespace:
    """The checked command line (exit 2 with one ``error:`` line on a bad one): every
    variant resolved and its world overrides validated on ``song-<side>``."""
    from arguments import Parser, among, whole
    ap = Parser.of(__file__, __doc__)
    ap.add_argument("--side", type=among(SONG_SCALES, int), default=100,
                    help=f"area side, among {', '.join(map(str, SONG_SCALES))}")
    ap.add_argument("--variant", action="append", required=True,
                    help="a variant: names of VARIANTS joined by '+', or world keys as key=json")
    ap.add_argument("--strategy", action="append", type=among(SONG_TABLE1), default=None,
                    help="a strategy of song2019-table1 (default: infotaxis and free-energy)")
    ap.add_argument("--baseline", default="base", help="the variant compared with, seed by seed")
    ap.add_argument("--seeds", type=whole(1), default=40)
    ap.add_argument("--first-seed", type=whole(0), default=0)
    ap.add_argument("--workers", type=whole(1), default=2)
    ap.add_argument("--out", default="/tmp/song_gap_cache2", help="cache folder (JSON lines; a rerun resumes)")
    a = ap.parse_args(argv)
    for option, name in [("--baseline", a.baseline)] + [("--variant", v) for v in a.variant]:
        problem = variant_problem(name, a.side)
        if problem:
            ap.error(f"{option} {name!r}: {problem}")
    a.out = ap.output_folder(a.out)
    return a


def variant_problem(name: str, side: int) -> str | None:
    """What is wrong with the variant `name` on ``song-<side>`` (None: nothing)."""
    from reciprocity.errors import SearchError
    from reciprocity.scenarios import load_scenario
    try:
        spec = resolve(name, side)
    except KeyError as exc:
        return f"no variant {exc.args[0]!r}; the variants: {', '.join(VARIANTS)}, or key=json"
    except ValueError as exc:
        return f"a key=json part is not JSON ({exc})"
    try:
        load_scenario(f"song-{side}").with_world(spec["world"])
    except SearchError as exc:
        return str(exc)
    return None


def main(argv=None):
    a = parse(argv)
    strategies = a.strategy or ["infotaxis", "free-energy"]
    seeds = list(range(a.first_seed, a.first_seed + a.seeds))
    out = a.out
    out.mkdir(parents=True, exist_ok=True)
    names = list(dict.fromkeys([a.baseline] + a.variant))
    res = collect(a.side, names, strategies, seeds, out, a.workers)
    print(f"\nsong-{a.side}, seeds {seeds[0]}..{seeds[-1]} (n = {len(seeds)}), baseline {a.baseline}")
    print("| variant | strategy | mean steps ± 95 % (cap counted) | found % | mean found | "
          "paired Δ ± 95 % | Δ both found ± 95 % | CPU s/run |")
    print("|---|---|---|---|---|---|---|---|")
    for strat in strategies:
        b = res[a.baseline, strat]
        bs = np.array([r["steps"] for r in b], float)
        bok = np.array([r["success"] for r in b])
        for name in names:
            rs = res[name, strat]
            st = np.array([r["steps"] for r in rs], float)
            ok = np.array([r["success"] for r in rs])
            m, h = mean_ci(st)
            d, dh = mean_ci(st - bs)
            both = ok & bok
            d2, d2h = mean_ci(st[both] - bs[both])
            mf = st[ok].mean() if ok.any() else float("nan")
            cpu = np.mean([r["cpu"] for r in rs])
            print(f"| {name} | {strat} | {m:.1f} ± {h:.1f} | {100 * ok.mean():.0f} | {mf:.1f} | "
                  f"{d:+.1f} ± {dh:.1f} | {d2:+.1f} ± {d2h:.1f} | {cpu:.2f} |")


if __name__ == "__main__":
    main()
