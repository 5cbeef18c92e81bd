"""otto (Loisy & Eloy 2022), 2-D grid, λ/Δx = 1, R·Δt = 2: infotaxis and space-aware infotaxis.

``otto-2d`` runs both on the scenario ``otto-2d`` (otto's protocol) against otto's mean
number of steps (:data:`OTTO_2D`); the set-up: ``docs/papers/otto.md``.
"""

from __future__ import annotations

from ..paper_table import PaperTable, PaperValue, register

__all__ = ["OTTO_2D", "OTTO_2D_TABLE"]

#: otto's mean number of steps and the ± it reports, 2-D, λ/Δx = 1, R·Δt = 2.
OTTO_2D = {"infotaxis": (11.72, 0.45), "space-aware-infotaxis": (11.52, 0.45)}

OTTO_2D_TABLE = register(PaperTable(
    name="otto-2d",
    title="mean steps to the source on otto's 2-D grid (λ/Δx = 1, R·Δt = 2), infotaxis vs "
          "space-aware infotaxis",
    reference="Loisy & Eloy (2022), otto 2-D benchmark",
    build_spec=lambda runs: {"strategies": list(OTTO_2D), "scenarios": ["otto-2d"], "seeds": runs},
    paper=tuple(v for s, (mean, pm) in OTTO_2D.items()
                for v in (PaperValue(s, "steps", mean, among="success", pm=pm),
                          PaperValue(s, "success", None))),
    default_runs=1000,
    note="otto's ± is as otto's evaluation script reports it; its mean, like ours, is over "
         "the episodes that reached the source (our found rate is printed below it).",
))
