"""Hajieghrary, Mox & Hsieh (2017): one searcher vs three sharing every reading vs three
sharing by value of information.

Set-up (papers/001; scenario ``hajieghrary``): a 200 × 200 field, isotropic K0 hit rate
(its Section 2), searchers reaching 2 units per step from (20, 20), (20, 180),
(180, 20), found within 2 units, 1500 steps at most. ``infotaxis`` is the single
searcher (it directs one observer: the scenario's first start); ``voi`` directs the
scenario's three searchers, each with its own particle belief and infotaxis moves,
offering every reading to the others (``share=all``, Section 3.3.1) or only those whose
value of information passes its threshold (``share=voi``, Section 3.3.2). At least 50
runs per team.

The paper's results are bar charts over 10 trials, not numbers: the table prints ours
(mean steps of the successful runs, success rate, messages per run) with 95 % intervals
and "–" for the paper. The single searcher sends no messages (its row has none).

``hajieghrary-misleading`` tests the paper's argument for filtering (its Section 3.3.1):
"incorporating all the events ... is misleading", a teammate's null events dilute what
another detects. That cannot happen when every reading is right and the model is the
truth, so the table adds two worlds where one searcher's data are wrong and no strategy
is told (the scenarios ``hajieghrary-dead-sensor`` and ``hajieghrary-false-alarms``:
searcher 3, the one starting nearest the source, counts no hits, or adds 0.05 spurious
hits per step). Three teams of three meet each world: independent searchers
(``share=none``), sharing every reading and sharing by value of information. The paper
assumes perfect sensors (its Remark 3) and prints no number for any of this.

Measured (``reciprocity reproduce hajieghrary-misleading``, 50 runs per row, seeds 0-49;
mean steps over the successful runs with Student-t 95 % intervals, success with Wilson
intervals, messages per run):

=============  ============  ======================  ================  ========
world          team          steps (successful)      success           messages
=============  ============  ======================  ================  ========
matched        independent   157.9 [140.7, 175.2]    100 % [93, 100]   0
matched        share all     72.6 [67.6, 77.5]       100 % [93, 100]   218
matched        share by VoI  135.9 [122.3, 149.5]    100 % [93, 100]   34
dead sensor    independent   159.9 [143.1, 176.7]    100 % [93, 100]   0
dead sensor    share all     181.1 [123.3, 238.9]    100 % [93, 100]   543
dead sensor    share by VoI  133.3 [120.7, 145.9]    100 % [93, 100]   33
false alarms   independent   135.5 [121.0, 150.0]    100 % [93, 100]   0
false alarms   share all     312.6 [233.4, 391.9]    90 % [79, 96]     1294
false alarms   share by VoI  545.5 [427.7, 663.2]    80 % [67, 89]     209
=============  ============  ======================  ================  ========

Verdicts:

- **Sharing everything misleads, as the paper argues**, once one sensor is wrong. With
  every sensor right, sharing all is the fastest team (2.2× faster than independent
  searchers). A dead sensor on the searcher nearest the source makes sharing all 2.5×
  slower (72.6 → 181.1 steps), no faster than not sharing at all (159.9; the intervals
  overlap). The mechanism the paper names, null readings near the plume diluting the
  others' hits, fits this, but we did not measure it separately.
- **Value-of-information filtering protects against the dead sensor** (135.9 → 133.3
  steps, unchanged). A null reading is unsurprising under a teammate's belief, so it
  rarely passes the threshold: 33 readings taken per run, against 34 in the matched world.
- **It does not protect against false alarms; it is hurt more than sharing all** (80 %
  success, 545.5 steps, against 90 % and 312.6). A spurious hit far from the plume is the
  most surprising event a teammate can receive, so the filter keeps exactly the readings
  that are wrong: 209 readings taken per run, six times the matched world's 34. Independent searchers are unharmed (the two healthy searchers find the
  source). Filtering by surprise is no defence against a sensor that lies; a team needs a
  model of its members' faults for that (beyond the paper).
"""

from __future__ import annotations

from ..paper_table import PaperTable, PaperValue, register

__all__ = ["HAJIEGHRARY_VOI", "HAJIEGHRARY_MISLEADING", "MISLEADING_WORLDS"]

_TEAMS = (("infotaxis", "1 searcher"), ("voi[share=all]", "3, share all"),
          ("voi[share=voi]", "3, share by VoI"))


def _values(rows) -> tuple[PaperValue, ...]:
    """Ours only ('–' for the paper): steps over the successful runs, success and, for
    teams, messages per row; `rows` holds (variant, scenario or None, row label)."""
    return tuple(v for variant, scenario, row in rows
                 for v in (PaperValue(variant, "steps", None, scenario, among="success", row=row),
                           PaperValue(variant, "success", None, scenario, row=row))
                 + ((PaperValue(variant, "messages", None, scenario, row=row),)
                    if variant != "infotaxis" else ()))


HAJIEGHRARY_VOI = register(PaperTable(
    name="hajieghrary-voi",
    title="one searcher vs three sharing all readings vs three sharing by value of "
          "information: search time, success, messages",
    reference="Hajieghrary, Mox & Hsieh (2017), Figs. (bar charts)",
    build_spec=lambda runs: {"strategies": {"infotaxis": {}, "voi": {"share": ["all", "voi"]}},
                             "scenarios": ["hajieghrary"], "seeds": runs},
    paper=_values((variant, None, row) for variant, row in _TEAMS),
    default_runs=50,
    note="The paper shows bar charts over 10 trials, no numbers ('–'); ours are means with "
         "Student-t 95 % intervals (Wilson for the success rate). Messages: readings a "
         "teammate took, per run.",
))

#: The worlds of ``hajieghrary-misleading``: the matched one, then those where one
#: searcher's sensor is wrong (scenario name, row label).
MISLEADING_WORLDS = (("hajieghrary", "matched"), ("hajieghrary-dead-sensor", "dead sensor"),
                     ("hajieghrary-false-alarms", "false alarms"))
_SHARING = (("voi[share=none]", "independent"), ("voi[share=all]", "share all"),
            ("voi[share=voi]", "share by VoI"))

HAJIEGHRARY_MISLEADING = register(PaperTable(
    name="hajieghrary-misleading",
    title="three searchers independent, sharing all readings or sharing by value of information, "
          "when every sensor is right and when one is dead or raises false alarms",
    reference="Hajieghrary, Mox & Hsieh (2017), Section 3.3.1 (an argument, no numbers)",
    build_spec=lambda runs: {"strategies": {"voi": {"share": ["none", "all", "voi"]}},
                             "scenarios": [name for name, _ in MISLEADING_WORLDS], "seeds": runs},
    paper=_values((variant, scenario, f"{world}: {team}")
                  for scenario, world in MISLEADING_WORLDS for variant, team in _SHARING),
    default_runs=50,
    note="The paper argues that sharing every event can mislead but assumes perfect sensors "
         "(its Remark 3): no numbers ('–'). Searcher 3, nearest the source, has the faulty "
         "sensor; no strategy is told. Mean steps over the successful runs, success (Wilson), "
         "messages per run, each with its 95 % interval.",
))
