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
"""

from __future__ import annotations

from ..paper_table import PaperTable, PaperValue, register

__all__ = ["HAJIEGHRARY_VOI", "HAJIEGHRARY_MISLEADING", "MISLEADING_WORLDS"]

_TEAMS = (("infotaxis", "1 searcher"), ("voi[share=all]", "3, share all"),
          ("voi[share=voi]", "3, share by VoI"))

HAJIEGHRARY_VOI = register(PaperTable(
    name="hajieghrary-voi",
    title="one searcher vs three sharing all readings vs three sharing by value of "
          "information: search time, success, messages",
    reference="Hajieghrary, Mox & Hsieh (2017), Figs. (bar charts)",
    build_spec=lambda runs: {"strategies": {"infotaxis": {}, "voi": {"share": ["all", "voi"]}},
                             "scenarios": ["hajieghrary"], "seeds": runs},
    paper=tuple(v for variant, row in _TEAMS
                for v in (PaperValue(variant, "steps", None, among="success", row=row),
                          PaperValue(variant, "success", None, row=row))
                + ((PaperValue(variant, "messages", None, row=row),)
                   if variant != "infotaxis" else ())),
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
    paper=tuple(PaperValue(variant, metric, None, scenario, among="success" if metric == "steps" else None,
                           row=f"{world}: {team}")
                for scenario, world in MISLEADING_WORLDS for variant, team in _SHARING
                for metric in ("steps", "success", "messages")),
    default_runs=50,
    note="The paper argues that sharing every event can mislead but assumes perfect sensors "
         "(its Remark 3): no numbers ('–'). Searcher 3, nearest the source, has the faulty "
         "sensor; no strategy is told. Mean steps over the successful runs, success (Wilson), "
         "messages per run, each with its 95 % interval.",
))
