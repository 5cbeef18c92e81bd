"""Tables 1 and 2 of Ristic, Skvortsov & Walker (2014): RBPF search on a random lattice.

Set-up (papers/000, Sec. 5; scenario ``ristic-lattice``): R0 = 9, 35 % of the links
missing, entry and start (9, −4), slip p_e = 0.04, ``rbpf`` with its defaults (N = 4000,
M = 400), 100 steps at most, 100 runs per row. Table 1 moves the source to (0, 7),
(0, 1), (2, −5) at A0 = 12; Table 2 keeps it at (0, 7) with A0 = 8, 12, 16 (world
overrides per row). Every run draws its own lattice from its episode seed; the paper's
runs all used the lattice of its Fig. 2, which is not published.

A run succeeds as in the paper (Sec. 5.1): the searcher steps on the source within 100
steps *and* its true node then lies in the support of its searcher-position particles.
The episode's own ``success`` is only the first part; the campaign row's ``success`` is
both (the environment tests the position support the strategy declares,
:meth:`reciprocity.strategies.rbpf.RBPFStrategy.position_support`), ``reached`` the first
and ``self_localised`` the second. The mean number of steps is over the successful runs
(the paper's averaging).

Measured with the former runner (100 runs per row, a lattice per run), success % with
Wilson 95 % intervals: (0, 7) 31 [23, 41], (0, 1) 30 [22, 40], (2, −5) 38 [29, 48];
A0 = 8 21 [14, 30], A0 = 16 15 [9, 23]; the paper has 94, 95, 99 and 78, 93. Why,
from controlled runs: with the eq. (25) field as truth on the complete lattice and no
slips the searcher reaches (0, 7) in 10/10 runs (36.8 steps); the same truth on a
random lattice drops to 3/10 (myopic control trapped in dead ends); random lattices'
shortest paths (median 22, 16, 10) exceed the paper's 20, 14, 8, which only 3 % of
draws match; and the lattice truth differs from eq. (25) by factors 0.02 to 1.9 in
the far field, depending on the lattice.

**The paper's protocol** (``reproduce ristic2014-table1 --protocol paper``, scenario
``ristic-lattice-paper``): every run on one lattice meeting everything the paper says of
its Fig. 2 (connected, 200 of 572 links missing, shortest paths exactly 20, 14 and 8 links
from the entry; chosen by ``benchmarks/ristic_lattice_search.py``, seed 32). 100 runs per
row, success with Wilson 95 % intervals against the paper's:

=============  ==============  ==================  =====  ================================
row            success         steps (successes)   paper  verdict
=============  ==============  ==================  =====  ================================
(0, 7)         41 % [32, 51]   54.2 [47.3, 61.2]   94 %   not reproduced: the control
(0, 1)         69 % [59, 77]   30.4 [26.0, 34.8]   95 %   not reproduced: the control
(2, −5)        72 % [63, 80]   21.4 [17.6, 25.3]   99 %   not reproduced: the control
A0 = 8         38 % [29, 48]   55.3 [48.5, 62.1]   78 %   not reproduced: the control
A0 = 16        37 % [28, 47]   51.6 [45.2, 58.0]   93 %   not reproduced: the control
=============  ==============  ==================  =====  ================================

**Where the success is lost** (``benchmarks/ristic_ladder.py``, source (0, 7), 100 runs
per rung on that lattice, seeds 0-99):

==============================================  ===============  =======  ===========
rung                                            success          reached  mean steps
==============================================  ===============  =======  ===========
1. map known, the lattice's own field           55 % [45, 64]    55 %     70.5
1'. as 1, shortest-path planner                 100 % [96, 100]  100 %    32.4
2. map known, eq. (25)                          44 % [35, 54]    44 %     47.2
3. map unknown, eq. (25), perfect localisation  48 % [38, 58]    48 %     52.1
4. the paper: map unknown, eq. (25)             34 % [25, 44]    41 %     52.9
==============================================  ===============  =======  ===========

Rung 3 (``localisation: known``: every reading carries the searcher's true node, an
oracle; the filter weighs its particles by it, so those whose slips or map put them
elsewhere lose their weight) separates the map from the searcher's position. Given its
position, the searcher does about as well without the map as with it (48 % against 44 %,
intervals overlapping). Between rungs 3 and 4 lie 14 points, within the intervals' reach
of each other ([38, 58] and [25, 44]): 7 points of runs that no longer reach the source
(48 % → 41 %), and 7 points of runs that reach it but fail the paper's self-localisation
test (41 % → 34 %). Estimating its own position costs the searcher something, but much
less than the control does.

Given the truth's own model and the map, the paper's one-step Bhattacharyya-gain control
still reaches the source in only 55 % of the runs, and a shortest-path planner on the same
belief reaches it in all of them in 32 steps. The conformal model costs about 10 points
and self-localisation about 14, but most of the gap to the paper's 94 % lies in the control. So either the paper's controller differs from ours in something it does
not print (its anti-oscillation rule, the ideal measurements, the horizon), or its Fig. 2
lattice is kinder than the figure's stated properties.

**The control's settings, one at a time on rung 1** (``benchmarks/ristic_ladder.py
--experiment control``, 100 runs each): as above 55 % [45, 64]; ideal measurements drawn
from G(η, θ) (Sec. 4.3) 54 % [44, 63]; M = 4000 ideal measurements 49 % [39, 59]; no
anti-oscillation rule 9 % [5, 16] (the rule is essential); "stay" only when no move is
admissible 78 % [69, 85]. The stay control is the one setting that matters: the one-step
gain often prefers reading again where it stands. In the full set-up it does not carry over
(``--experiment stay``: 34 % [25, 44] with stay, 33 % [25, 43] without; reached 41 % and
51 %): the searcher reaches the source more often, but then fails to localise itself more
often. Algorithm 2's text scores all five controls every step, where ``rbpf`` by default
scores only stay and the moves along links not believed missing; read literally
(``controls="all"``, ``--experiment controls``) it loses most runs: 6 % [3, 12] in the
full set-up, 27 % [19, 36] on rung 1. So the literal text is further from the paper's
94 % than our reading, and the gap is not in the control set either.

**What the paper leaves open, each choice named and measured** (the paper's set-up, rung
4, source (0, 7), 100 runs each):

- *The link sensor's reach.* The paper fixes it (primary links p_d 1, p_fa 0; secondary
  links 0.8, 0.1) and we keep it. Changing it moves success within the noise
  (``--experiment sensor``): primary links only (secondary p_d = p_fa = 0.5, no
  information) 41 % [32, 51]; secondary links seen perfectly 45 % [36, 55]; the paper's
  34 % [25, 44]. The sensor is not where the 94 % is lost.
- *Look-ahead.* The paper's control is one step ahead and says so (multi-step control is
  its future work); we keep one step. A longer horizon on the known map (rung 1') reaches
  the source in every run, so this is where a better searcher would gain.
- *Dead ends.* The paper handles them only through its anti-oscillation rule (a random
  control after more than 3 visits to a node in 10 steps); we keep that rule as printed.
  Without it rung 1 falls from 55 % to 9 % (above). Moves along links the searcher
  believes missing are not scored (``controls="believed"``, named as a deviation above
  with its measurement).
"""

from __future__ import annotations

from ..paper_table import PaperTable, PaperValue, register

__all__ = ["RISTIC2014_TABLE1", "RISTIC2014_TABLE2", "TABLE1_ROWS", "TABLE2_ROWS"]

#: Table 1 (A0 = 12): (scenario label, row label, world overrides, paper mean steps,
#: paper success rate).
TABLE1_ROWS = (("source_0_7", "(0, 7)", {"source": [0, 7]}, 42.1, 0.94),
               ("source_0_1", "(0, 1)", {"source": [0, 1]}, 34.0, 0.95),
               ("source_2_-5", "(2, −5)", {"source": [2, -5]}, 28.8, 0.99))
#: Table 2 (source (0, 7)): the same for A0 = 8, 12, 16.
TABLE2_ROWS = (("A0_8", "A0 = 8", {"strength": 8.0}, 49.5, 0.78),
               ("A0_12", "A0 = 12", {"strength": 12.0}, 42.1, 0.94),
               ("A0_16", "A0 = 16", {"strength": 16.0}, 38.2, 0.93))

_NOTE = ("Success as in the paper (Sec. 5.1): the searcher steps on the source within 100 "
         "steps and its particles then hold its true node; mean steps over the successful "
         "runs; 'reached' is the first condition alone. Each run draws its own lattice (the "
         "paper's Fig. 2 lattice is not published); random lattices have longer shortest "
         "paths than the paper's 20, 14, 8 and dead ends that trap the one-step control, so "
         "our success rates are far lower (see reciprocity.campaign.tables.ristic2014).")


_PAPER_NOTE = ("Protocol 'paper' (Sec. 2 and 5): every run on one lattice, the paper's Fig. 2 as "
               "far as it is described (R0 = 9, 200 of 572 links missing, all nodes connected, shortest "
               "paths 20, 14 and 8 links from the entry; scenario ristic-lattice-paper, chosen by "
               "benchmarks/ristic_lattice_search.py), so runs differ only in noise, slips and the "
               "filter's randomness; lattice truth A0 F, the filter's eq. (25), N = 4000, M = 400. "
               "Success as in Sec. 5.1: the searcher steps on the source within 100 steps and its "
               "particles then hold its true node; mean steps over the successful runs. The oracle "
               "ladder in this table's doc (benchmarks/ristic_ladder.py) puts most of the gap in the "
               "one-step control: with the map and the lattice's own field it succeeds in 55 %, with a "
               "shortest-path planner in 100 %.")


def _spec(rows, scenario: str = "ristic-lattice"):
    def build(runs: int) -> dict:
        return {"strategies": ["rbpf"], "seeds": runs,
                "scenarios": [{"name": scenario, "label": label, "world": dict(world)}
                              for label, _, world, _, _ in rows]}
    return build


def _values(rows) -> tuple[PaperValue, ...]:
    out = []
    for label, row, _, steps, success in rows:
        out += [PaperValue("rbpf", "steps", steps, label, among="success", row=row),
                PaperValue("rbpf", "success", success, label, row=row),
                PaperValue("rbpf", "reached", None, label, row=row)]
    return tuple(out)


RISTIC2014_TABLE1 = register(PaperTable(
    name="ristic2014-table1",
    title="RBPF search on a random lattice: mean steps and success rate per source (A0 = 12)",
    reference="Ristic, Skvortsov & Walker (2014), Table 1",
    build_spec=_spec(TABLE1_ROWS), paper=_values(TABLE1_ROWS), default_runs=100, note=_NOTE,
    protocols={"paper": (_spec(TABLE1_ROWS, "ristic-lattice-paper"), _PAPER_NOTE)}))

RISTIC2014_TABLE2 = register(PaperTable(
    name="ristic2014-table2",
    title="RBPF search on a random lattice: mean steps and success rate per release rate A0 "
          "(source (0, 7))",
    reference="Ristic, Skvortsov & Walker (2014), Table 2",
    build_spec=_spec(TABLE2_ROWS), paper=_values(TABLE2_ROWS), default_runs=100, note=_NOTE,
    protocols={"paper": (_spec(TABLE2_ROWS, "ristic-lattice-paper"), _PAPER_NOTE)}))
