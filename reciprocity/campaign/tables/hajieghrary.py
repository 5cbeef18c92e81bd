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
"""

from __future__ import annotations

from ..paper_table import PaperTable, PaperValue, register

__all__ = ["HAJIEGHRARY_VOI"]

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
