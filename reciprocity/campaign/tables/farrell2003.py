"""Farrell, Pang & Li (2003): hidden-Markov plume mapping, its Figs. 5–8 and a search
comparison the paper does not have.

``farrell-hmm`` runs ``hmm`` (two planners), ``surge-cast`` and ``detection-infotaxis``
(:data:`FARRELL_VARIANTS`) on the scenario ``farrell`` from the same random start per
seed index; :func:`figures` (the table's ``after``) writes the paper's Figs. 5–8 and one
track per strategy. The paper reports maps only, no search statistics.

The set-up and what the table prints: ``docs/papers/farrell2003.md``.
"""

from __future__ import annotations

from pathlib import Path

from ..paper_table import PaperTable, PaperValue, register
from ..spec import CampaignSpec

__all__ = ["FARRELL_HMM", "FARRELL_STRATEGIES", "FARRELL_VARIANTS", "figures"]

#: The strategies compared.
FARRELL_STRATEGIES = ("hmm", "surge-cast", "detection-infotaxis")
#: Their variants in the campaign: hmm's default planner and its ``target="verify"``.
FARRELL_VARIANTS = ("hmm[target=bisect]", "hmm[target=verify]", "surge-cast", "detection-infotaxis")
_METRICS = ("success", "sim_time_s", "distance_at_stop", "error")


def figures(directory: Path, spec: CampaignSpec) -> list[Path]:
    """The paper's Figs. 5–8 and one track per strategy (seed index 0), in ``directory/figures``.

    Parameters
    ----------
    directory : Path
        The table's results folder.
    spec : CampaignSpec
        Its campaign (the tracks re-run its first episode of each strategy).

    Returns
    -------
    list of Path
    """
    from ...wiring.filament import filament_params
    from ...scenarios import load_scenario
    from ...viz.hmm import farrell_figures, plot_search
    from ...worlds.filament_figures import farrell_record
    from ..worker import execute_task
    out = Path(directory) / "figures"
    files = list(farrell_figures(farrell_record(filament_params(load_scenario("farrell").params)), out))
    for task in spec.tasks():
        if task.seed_index != 0:
            break
        episode = execute_task(task, figures=True)[0]
        label = task.variant.label.replace('[', '_').replace(']', '').replace('=', '-')
        files.append(plot_search(episode, out / f"track_{label}.png"))
    return files


FARRELL_HMM = register(PaperTable(
    name="farrell-hmm",
    title="hidden-Markov source map (hmm, two planners) vs surge-cast vs detection-infotaxis "
          "from random starts: success, search time, distance to the source at the stop",
    reference="Farrell, Pang & Li (2003), search comparison (the paper has Figs. 5-8 only)",
    build_spec=lambda runs: {"strategies": {"hmm": {"target": ["bisect", "verify"]}, "surge-cast": {},
                                            "detection-infotaxis": {}}, "seeds": runs,
                             "scenarios": [{"name": "farrell", "random_start": True}]},
    paper=tuple(PaperValue(s, m, None) for s in FARRELL_VARIANTS for m in _METRICS),
    default_runs=50,
    note="The paper reports maps (its Figs. 5-8, written to DIR/figures with one track per "
         "strategy), no search statistics ('–'). Starts are uniform over the region at least "
         "10 m from the source, drawn per seed index, the same for every strategy; search "
         "time in s over all runs (300 s when a run does not stop), distances in m.",
    after=figures,
))
