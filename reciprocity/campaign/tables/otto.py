"""otto (Loisy & Eloy 2022), 2-D grid, λ/Δx = 1, R·Δt = 2: infotaxis and space-aware infotaxis.

Set-up (scenario ``otto-2d``, otto's protocol): a 19 × 19 grid, the searcher starts at
the centre after a forced first hit, the source is drawn from the posterior after that
hit, Poisson hits of mean μ(d) = I/ln(2L)·K0(d/L), the episode ends on the source cell
(or at 1000 steps). otto's numbers were measured with otto's own evaluation script; its
mean number of steps is conditioned on success, and so is ours. At least 1000 episodes
per policy.
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
