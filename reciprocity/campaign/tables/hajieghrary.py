"""Hajieghrary, Mox & Hsieh (2017): one searcher vs three sharing every reading vs three
sharing by value of information.

``hajieghrary-voi`` runs ``infotaxis`` (one searcher) and ``voi`` (three, ``share=all``
and ``share=voi``) on the scenario ``hajieghrary``; ``hajieghrary-misleading`` runs
three teams of three (``share=none``, ``all``, ``voi``) in the worlds of
:data:`MISLEADING_WORLDS`, where one searcher's sensor is wrong and no strategy is told.
The paper prints bar charts, no numbers.

The set-up, our results with their verdicts: ``docs/papers/hajieghrary.md``.
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
