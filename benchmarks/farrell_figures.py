"""Farrell, Pang & Li (2003), Figs. 5–8: what the paper states of its maps against ours.

    nice -n 5 python benchmarks/farrell_figures.py --seeds 30

The maps are :func:`reciprocity.beliefs.farrell_maps.farrell_maps` of the record
:func:`reciprocity.worlds.filament_figures.farrell_record` simulates (the ``farrell``
scenario's plume; the vehicle drives down from (60, 45) at 1 m/s), measured by
:func:`reciprocity.beliefs.farrell_measures.farrell_measures`: the maps' largest cells,
their spreads along and across the mean measured flow (standard deviations and the
widths holding 50 % and 90 % of the mass) and how the crossflow spread grows away from
the reference cell, and the odour and detection paths of Figs. 7–8 under the uniform
flow of eq. (18). Figs. 5–6 depend on the plume's seed: ``--seeds N`` records (seeds 0
to N - 1) give 95 % intervals (Student-t for means, Wilson for the share of seeds in
which a statement holds); ``--figure-seed`` is the record drawn by the ``farrell-hmm``
table's figures. Figs. 7–8 depend on eq. (18) only (the same for every seed).

Prints one Markdown table (figure, quantity, the paper, ours on the figure's seed, ours
over the seeds, verdict). Results: ``docs/papers/farrell2003.md``.
"""

from __future__ import annotations

import argparse
import functools
import math

import numpy as np
from scipy import stats

from arguments import Parser, whole

from reciprocity.beliefs.farrell_maps import farrell_maps
from reciprocity.beliefs.farrell_measures import BANDS, farrell_measures, odour_distribution, paper_ij
from reciprocity.models.hmm import CellGrid
from reciprocity.scenarios import load_scenario
from reciprocity.wiring.filament import filament_params
from reciprocity.worlds.filament_figures import START, farrell_record, uniform_flow

#: The paper's cells (Sect. V and the captions of Figs. 5–8).
SOURCE, START_CELL, DETECTION, ODOUR_END, DETECTION_END = 488, 64, 619, 388, 471
#: The paper's times, s: the detection of Fig. 6, the odour path's end, the detection path's map.
DETECTION_T, ODOUR_T, DETECTION_MAP_T = 54, 44, 48
#: Eq. (18): the flow turns from x to y at this second.
TURN_T = 30
#: A neighbour lies "directly" down- or upflow when its centre is within this of the flow's axis, m
#: (half the cell's 4 m height).
AXIS = 2.0
#: A cell's centre within this of the reference cell's is its neighbour, m (the cell's diagonal).
NEIGHBOUR = float(np.hypot(2.5, 4.0))


@functools.lru_cache(maxsize=None)
def measure(seed: int) -> tuple[CellGrid, dict]:
    """The grid and :func:`farrell_measures` of the record of `seed` (kept: the figure's
    seed is usually among the others)."""
    record = farrell_record(filament_params(load_scenario("farrell").params), seed=seed)
    maps = farrell_maps(record)
    return maps["grid"], farrell_measures(record, maps)


def t_interval(x) -> tuple[float, float, float]:
    """Mean of `x` and its Student-t 95 % interval."""
    x = np.asarray(x, dtype=float)
    half = float(stats.t.ppf(0.975, x.size - 1) * x.std(ddof=1) / math.sqrt(x.size))
    return float(x.mean()), float(x.mean()) - half, float(x.mean()) + half


def wilson(k: int, n: int) -> tuple[float, float]:
    """Wilson 95 % interval of the rate ``k / n``."""
    ci = stats.binomtest(k, n).proportion_ci(method="wilson")
    return float(ci.low), float(ci.high)


def mean_text(x, unit: str = "m", digits: int = 1) -> str:
    m, lo, hi = t_interval(x)
    return f"{m:.{digits}f} [{lo:.{digits}f}, {hi:.{digits}f}] {unit}".rstrip()


def share(flags) -> tuple[str, str]:
    """``"k/n [lo, hi] %"`` of the seeds where a statement holds, and a verdict: agrees
    when the Wilson interval lies above 1/2, disagrees when below, else undecided."""
    k, n = int(np.sum(flags)), len(flags)
    lo, hi = wilson(k, n)
    verdict = "agrees" if lo > 0.5 else "disagrees" if hi < 0.5 else "undecided"
    return f"{k}/{n} [{100 * lo:.0f}, {100 * hi:.0f}] %", verdict


def cell(number: int, grid: CellGrid) -> str:
    i, j = paper_ij(number, grid)
    return f"C{number} (i={i}, j={j})"


def pair(p, digits: int = 1) -> str:
    return f"({p[0]:.{digits}f}, {p[1]:.{digits}f})"


def shape_rows(fig: str, shapes: list, fig_shape, grid: CellGrid, ref: str, sense: int, paper: dict) -> list:
    """The rows of a map figure: its maximum, its spreads, the growth of its crossflow spread."""
    word = "downflow" if sense > 0 else "upflow"
    at_ref = share([s.peak_offset == (0.0, 0.0) for s in shapes])
    next_to = share([s.peak_offset == (0.0, 0.0) or (sense * s.peak_offset[0] > 0 and abs(s.peak_offset[1]) < AXIS
                                                      and np.hypot(*s.peak_offset) <= NEIGHBOUR) for s in shapes])
    peak_on_axis = share([sense * s.peak_offset[0] > 0 and abs(s.peak_offset[1]) < AXIS for s in shapes])
    on_axis = share([sense * s.runner_up_offset[0] > 0 and abs(s.runner_up_offset[1]) < AXIS for s in shapes])
    narrow = share([s.sd[1] < s.sd[0] and s.extent90[1] < s.extent90[0] for s in shapes])
    narrow50 = share([s.extent50[1] < s.extent50[0] for s in shapes])
    ratio = [s.sd[1] / s.sd[0] for s in shapes]
    r90 = [s.extent90[1] / s.extent90[0] for s in shapes]
    grows = share([s.band_sd_across[0] < s.band_sd_across[1] < s.band_sd_across[2] for s in shapes])
    m, lo, hi = t_interval(ratio)
    bands = ", ".join(f"{a:g}–{b:g} m" for a, b in zip(BANDS[:-1], BANDS[1:]))
    return [
        (fig, "largest cell", paper["peak"], f"{cell(fig_shape.peak, grid)}, the {ref}'s",
         f"the {ref}'s cell in {at_ref[0]}; it or its {word} neighbour in {next_to[0]}",
         f"partly: the maximum is the {ref}'s own cell, else its {word} neighbour" if at_ref[1] == "agrees"
         else f"{peak_on_axis[1]} ({word} on the axis in {peak_on_axis[0]})"),
        (fig, f"largest cell besides the {ref}'s: offset (along, across)", paper["peak"],
         f"{cell(fig_shape.runner_up, grid)}, {pair(fig_shape.runner_up_offset)} m",
         f"{word} and within {AXIS:g} m of the axis in {on_axis[0]}; along "
         + mean_text([s.runner_up_offset[0] for s in shapes]),
         f"{on_axis[1]}: the next largest is the {word} neighbour"),
        (fig, "s.d. (along, across); 90 % width (along, across)", paper["spread"],
         f"{pair(fig_shape.sd)} m; {pair(fig_shape.extent90)} m",
         f"along {mean_text([s.sd[0] for s in shapes])}, across {mean_text([s.sd[1] for s in shapes])}; "
         f"90 % along {mean_text([s.extent90[0] for s in shapes])}, across "
         f"{mean_text([s.extent90[1] for s in shapes])}; both narrower across in {narrow[0]}",
         f"{narrow[1]} (narrower across)"),
        (fig, "50 % width (along, across)", paper["spread"], f"{pair(fig_shape.extent50)} m",
         f"along {mean_text([s.extent50[0] for s in shapes])}, across {mean_text([s.extent50[1] for s in shapes])}; "
         f"narrower across in {narrow50[0]}", f"{narrow50[1]} (narrower across)"),
        (fig, "ratio across / along: s.d.; 90 % width", paper["spread"],
         f"{fig_shape.sd[1] / fig_shape.sd[0]:.2f}; {fig_shape.extent90[1] / fig_shape.extent90[0]:.2f}",
         f"{mean_text(ratio, '', 2)}; {mean_text(r90, '', 2)}",
         "agrees (narrower across)" if hi < 1 else "disagrees" if lo > 1 else "undecided"),
        (fig, f"crossflow s.d. at {bands} {word}", paper["growth"],
         ", ".join(f"{v:.1f}" for v in fig_shape.band_sd_across) + " m",
         ", ".join(mean_text([s.band_sd_across[b] for s in shapes]) for b in range(len(BANDS) - 1))
         + f"; increasing in {grows[0]}", f"{grows[1]}"),
    ]


def path_text(p, grid: CellGrid) -> str:
    """A path by its corners: its first cell, each cell where its direction of motion
    changes, its last cell (``C488 → C508 → C388``)."""
    ij = np.array([paper_ij(c, grid) for c in p.cells])
    corners, last = [0], None
    for k in range(1, len(ij)):
        d = tuple(np.sign(ij[k] - ij[k - 1]))
        if d == (0, 0):
            continue
        if last is not None and d != last:
            corners.append(k - 1)
        last = d
    corners.append(len(ij) - 1)
    return " → ".join(f"C{p.cells[k]}" for k in dict.fromkeys(corners))


def bottom_up_reach(grid: CellGrid) -> float:
    """Probability that odour in C488 at 0 s is in the cell (i, j) of C388 at 44 s under
    eq. (18) if the paper's rows counted from the bottom of the region (y up)."""
    i, j = paper_ij(ODOUR_END, grid)
    flows = [uniform_flow(t) for t in range(ODOUR_T)]
    return float(odour_distribution(grid, flows, grid.from_paper(SOURCE))[(i - 1) + (j - 1) * grid.m])


def path_rows(m: dict, grid: CellGrid) -> list:
    """The rows of Figs. 7 and 8 (no seed dependence)."""
    mlop, mldp, free, text = m["fig7"], m["fig8"], m["fig8_free"], m["fig8_text"]
    prob, rank, mode = m["fig7_arrival"]
    ends = (mlop.start, mlop.end, mlop.steps) == (SOURCE, ODOUR_END, ODOUR_T)
    ell = max(mlop.x_moves) <= TURN_T < min(mlop.y_moves)
    ties = math.comb(TURN_T, len(mlop.x_moves)) * math.comb(ODOUR_T - TURN_T, len(mlop.y_moves))
    det_ends = (mldp.start, mldp.end, mldp.steps) == (ODOUR_END, DETECTION_END, 25)
    return [
        ("7", "ends and times", f"{cell(SOURCE, grid)} at 0 s → {cell(ODOUR_END, grid)} at {ODOUR_T} s",
         f"C{mlop.start} at 0 s → C{mlop.end} at {mlop.steps} s ({mlop.steps + 1} cells)", "deterministic",
         "agrees (the end is imposed, the start is π's one cell)" if ends else "disagrees"),
        ("7", "cells and moves", "a path the reader can check against eq. (18): x until 30 s, then y",
         f"{path_text(mlop, grid)}: {len(mlop.x_moves)} moves along x (all at t ≤ 30 s), "
         f"{len(mlop.y_moves)} along y (all after); {mlop.distinct} distinct cells, {mlop.length:.0f} m",
         "deterministic", "agrees (x, then y)" if ell else "disagrees"),
        ("7", "row numbering", f"C{ODOUR_END} is j = {paper_ij(ODOUR_END, grid)[1]}, C{SOURCE} j = "
         f"{paper_ij(SOURCE, grid)[1]}; the flow is +y after {TURN_T} s",
         f"reached with probability {prob:.1e} if rows count from the top, {bottom_up_reach(grid):g} from the bottom",
         "deterministic", "rows count from the top (as C64 at the top edge says)"),
        ("7", "equally likely paths", "one path drawn",
         f"{ties:.2e}: every order of the {len(mlop.x_moves)} x-moves in 30 s and {len(mlop.y_moves)} y-moves "
         "in 14 s; same cells, other times (we draw the first maximiser's)", "exact", "no statement to test"),
        ("7", f"odour from C{SOURCE} at 0 s in C{ODOUR_END} at {ODOUR_T} s", "–",
         f"probability {prob:.1e}, rank {rank} of {grid.N}; most probable: {cell(mode, grid)}",
         "deterministic", f"no statement to test; the end is {paper_ij(ODOUR_END, grid)[0] - paper_ij(mode, grid)[0]} "
         "columns downflow of where eq. (18) most likely carries the odour"),
        ("8", "ends, steps, map time",
         f"caption: {cell(ODOUR_END, grid)} → {cell(DETECTION_END, grid)}, 25 steps, α at {DETECTION_MAP_T} s "
         f"(text: C{ODOUR_END} → C{SOURCE} at {ODOUR_T} s)",
         f"C{mldp.start} → C{mldp.end}, {mldp.steps} steps, α at {DETECTION_MAP_T} s", "deterministic",
         "agrees with the caption (ends imposed)" if det_ends else "disagrees"),
        ("8", "distinct from Fig. 7's path", "the two paths differ",
         f"shared cells: {', '.join(f'C{c}' for c in m['fig8_shared'])}", "deterministic",
         "agrees" if len(m["fig8_shared"]) <= 1 else "disagrees"),
        ("8", "cells", "no numbers (grey cells in the figure)",
         f"{path_text(mldp, grid)}: {mldp.distinct} distinct cells, {mldp.length:.0f} m", "deterministic",
         "no statement to test"),
        ("8", "25-step path from C388 to its best end at 48 s", "–",
         f"{path_text(free, grid)}: ends in C{free.end}", "deterministic",
         "no statement to test" + (": the best end is the text's C488" if free.end == SOURCE else "")),
        ("8", f"the text's path C{ODOUR_END} → C{SOURCE} on α at {ODOUR_T} s", f"C{ODOUR_END} → C{SOURCE}, 25 cells",
         f"{path_text(text, grid)}: {text.distinct} distinct cells, {text.length:.0f} m", "deterministic",
         "no statement to test (the text and the caption name different ends)"),
    ]


def table(seeds: list[int], figure_seed: int) -> list[tuple]:
    """All rows: Figs. 5 and 6 over `seeds` (and on `figure_seed`), Figs. 7 and 8."""
    grid, fig = measure(figure_seed)
    runs = [measure(s)[1] for s in seeds]
    fives = [r["fig5"] for r in runs]
    sixes = [r["fig6"] for r in runs if r["fig6"] is not None]
    rows = [("5", "source cell", f"{cell(SOURCE, grid)}, holding (20, 0) m",
             f"{cell(SOURCE, grid)}: x 17.5–20 m, y −2–2 m; (20, 0) lies on its edge with C489", "fixed",
             "agrees")]
    rows += shape_rows("5", fives, fig["fig5"], grid, "source", +1, dict(
        peak="largest straight down flow from the source",
        spread="falls fast across the flow, slowly along it",
        growth="widens with the distance downflow"))
    detected = share([r["fig6"] is not None for r in runs])
    start = grid.to_paper(int(grid.index(START)[0]))
    rows += [("6", "start", f"{cell(START_CELL, grid)} at 0 s",
              f"({START[0]:g}, {START[1]:g}) m, on the edge of C64 and C65 (our floor rule: C{start})", "fixed",
              "agrees to a cell"),
             ("6", "detection: cell, time", f"{cell(DETECTION, grid)} at {DETECTION_T} s",
              "none" if fig["fig6"] is None else f"{cell(fig['fig6'][1], grid)} at {fig['fig6'][0]} s",
              f"detected after 20 s in {detected[0]}; t " + mean_text([r[0] for r in sixes], "s", 0),
              "differs (our vehicle drives straight down x = 60 m)")]
    if fig["fig6"] is None or len(sixes) < 2:
        return rows + path_rows(fig, grid)
    rows += shape_rows("6", [r[2] for r in sixes], fig["fig6"][2], grid, "vehicle", -1, dict(
        peak="largest just upflow of the vehicle",
        spread="falls fast across the flow, slowly upflow",
        growth="widens farther upflow"))
    return rows + path_rows(fig, grid)


def parse(argv=None) -> argparse.Namespace:
    """The checked command line (exit 2 with one ``error:`` line on a bad one)."""
    ap = Parser.of(__file__, __doc__)
    ap.add_argument("--seeds", type=whole(2, 500), default=30, help="plume records 0 .. N-1 for the intervals")
    ap.add_argument("--figure-seed", type=whole(0), default=3,
                    help="the record of the ours column (3: the one the farrell-hmm table draws)")
    return ap.parse_args(argv)


def main(argv=None) -> list[tuple]:
    args = parse(argv)
    rows = table(list(range(args.seeds)), args.figure_seed)
    print(f"| Fig. | quantity | paper | ours (seed {args.figure_seed}) | ours, {args.seeds} seeds (95 %) | verdict |")
    print("|---|---|---|---|---|---|")
    for r in rows:
        print("| " + " | ".join(r) + " |")
    return rows


if __name__ == "__main__":
    main()
