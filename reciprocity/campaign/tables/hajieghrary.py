"""Hajieghrary, Mox & Hsieh (2017): one searcher vs three sharing every reading vs three
sharing by value of information.

``hajieghrary-voi`` runs ``infotaxis`` (one searcher) and ``voi`` (three, ``share=all``
and ``share=voi``) on the scenario ``hajieghrary``; ``hajieghrary-misleading`` runs
three teams of three (``share=none``, ``all``, ``voi``) in the worlds of
:data:`MISLEADING_WORLDS`, where one searcher's sensor is wrong and no strategy is told.
The paper prints bar charts, no numbers. ``hajieghrary-misleading --protocol paper`` runs
the same worlds and teams with the paper's own searcher (``voi`` with ``preset="paper"``:
Gaussian basis functions, the pose-uncertainty mixture, its Remark 3).

``hajieghrary-fig1`` is the particle-count sweep of its Fig. 1 (three searchers, the
paper's particle filter, which resamples without moving the particles), with every
sharing rule; ``--protocol rejuvenated`` is the same sweep with Metropolis-Hastings moves
after each resampling (the control for particle depletion). ``hajieghrary-basis`` sweeps
the number of Gaussian basis functions of the paper's Section 3.2 the same way.

The set-up, our results with their verdicts: ``docs/papers/hajieghrary.md``.
"""

from __future__ import annotations

from ..paper_table import PaperTable, PaperValue, register

__all__ = ["HAJIEGHRARY_VOI", "HAJIEGHRARY_MISLEADING", "HAJIEGHRARY_FIG1", "HAJIEGHRARY_BASIS",
           "MISLEADING_WORLDS", "FIG1_PARTICLES", "BASIS_COUNTS", "EVERY_STEP"]

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
    protocols={"paper": (
        lambda runs: {"strategies": {"voi": {"preset": "paper", "share": ["none", "all", "voi"]}},
                      "scenarios": [name for name, _ in MISLEADING_WORLDS], "seeds": runs},
        "Protocol 'paper': each searcher as the paper builds it (voi with preset='paper'): 300 "
        "Gaussian basis functions scattered at random (its Sec. 3.2, Fig. 7), weighted by the "
        "likelihood averaged over each function and the robot's pose uncertainty Sigma = 2 I "
        "(Sec. 3.1), the mixture entropy of eq. (12), and a robot's own hits filtered by value "
        "of information (Remark 3). The faulty worlds are beyond the paper (it assumes perfect "
        "sensors). No numbers in the paper ('–')."),
    },
))

_SHARES = ("none", "all", "voi")
_SHARE_LABEL = dict(none="independent", all="share all", voi="share by VoI")


def _sweep(axis: str, counts, what: str) -> tuple[PaperValue, ...]:
    """Ours for each (count, sharing rule) of a sweep, '–' for the paper."""
    return _values((f"voi[{axis}={n},share={share}]", None, f"{n} {what}: {_SHARE_LABEL[share]}")
                   for n in counts for share in _SHARES)


#: Particle counts of ``hajieghrary-fig1`` (the paper's Fig. 1 axis runs to 1.9 × 10⁴; it
#: prints no other value).
FIG1_PARTICLES = (1000, 3000, 10000, 19000)


#: ``--protocol every-step``: resample whenever the weights are not all equal, i.e. after
#: every reading (eq. (6) of the paper: "a hypothesis that survived the re-sampling
#: procedure of the previous step").
EVERY_STEP = 0.9999


def _fig1_spec(rejuvenate: bool, resample_below: float | None = None):
    extra = {} if resample_below is None else {"resample_below": resample_below}
    return lambda runs: {"strategies": {"voi": {"rejuvenate": rejuvenate, **extra,
                                                "particles": list(FIG1_PARTICLES), "share": list(_SHARES)}},
                         "scenarios": ["hajieghrary"], "seeds": runs}


def _fig1_values() -> tuple[PaperValue, ...]:
    """The sweep, with the one number Fig. 1 prints: no success at 1.9 × 10⁴ particles
    when the three share every event."""
    top = f"voi[particles={FIG1_PARTICLES[-1]},share=all]"
    return tuple(PaperValue(v.variant, v.metric, 0.0, v.scenario, v.among, row=v.row)
                 if (v.variant, v.metric) == (top, "success") else v
                 for v in _sweep("particles", FIG1_PARTICLES, "particles"))


HAJIEGHRARY_FIG1 = register(PaperTable(
    name="hajieghrary-fig1",
    title="three searchers with the paper's particle filter: particle count × sharing rule "
          "(search time, success, messages)",
    reference="Hajieghrary, Mox & Hsieh (2017), Fig. 1 (bar chart, 10 trials per count)",
    build_spec=_fig1_spec(False),
    paper=_fig1_values(),
    default_runs=20,
    note="The paper's particle filter: weights by eq. (7), resampled (systematic) when the "
         "effective size falls below a third, particles never moved (its Remark 1); sharing "
         "every event (its Sec. 3.3.1) is the paper's Fig. 1, which prints one number: no "
         "success at 1.8 and 1.9 × 10⁴ particles. Success: a searcher reached the source "
         "(the paper's criterion includes the particles' mean distance to it).",
    protocols={"rejuvenated": (
        _fig1_spec(True),
        "Protocol 'rejuvenated': the same sweep with one Metropolis-Hastings move per "
        "particle after each resampling (our particle filter): the control for particle "
        "depletion, the cause the paper names."),
        "every-step": (
        _fig1_spec(False, EVERY_STEP),
        "Protocol 'every-step': the paper's particle filter resampling after every reading "
        "(its eq. (6): each hypothesis 'survived the re-sampling procedure of the previous "
        "step'), particles never moved; the paper prints one number, no success at 1.8 and "
        "1.9 × 10⁴ particles when the three share every event."),
        "every-step-rejuvenated": (
        _fig1_spec(True, EVERY_STEP),
        "Protocol 'every-step-rejuvenated': the paper's every-step resampling with one "
        "Metropolis-Hastings move per particle after each resampling: the control that changes "
        "only the particle moves of the 'every-step' protocol.")},
))

#: Numbers of Gaussian basis functions of ``hajieghrary-basis`` (the paper: 100 to 300).
BASIS_COUNTS = (100, 300)

def _basis_spec(scenario: str):
    return lambda runs: {"strategies": {"voi": {"preset": "paper", "basis": list(BASIS_COUNTS),
                                                "share": list(_SHARES)}},
                         "scenarios": [scenario], "seeds": runs}


HAJIEGHRARY_BASIS = register(PaperTable(
    name="hajieghrary-basis",
    title="three searchers with the paper's Gaussian basis belief: number of basis functions × "
          "sharing rule (search time, success, messages)",
    reference="Hajieghrary, Mox & Hsieh (2017), Secs. 3.2, 4.1 (Figs. 5, 7: 100 and 300 functions)",
    build_spec=_basis_spec("hajieghrary"),
    paper=_sweep("basis", BASIS_COUNTS, "basis functions"),
    default_runs=20,
    note="voi with preset='paper' (basis functions scattered at random, pose variance 2, own "
         "hits filtered by value of information, Remark 3). The paper shows trajectories, no "
         "numbers ('–').",
    protocols={"directional": (
        _basis_spec("hajieghrary-directional"),
        "Protocol 'directional': the same teams with the paper's directional sensor (eq. (14), "
        "read as its words say: more hits facing the source), in the world and in every belief. "
        "The paper uses it for one robot (its Fig. 3) and the oil-spill run (Fig. 9), not for "
        "the team comparison (Fig. 7: 'independent of the bearing'); no numbers ('–').")},
))
