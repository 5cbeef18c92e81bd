"""Landa et al. (2020): the testbed run of the reciprocity search and of gradient ascent."""

from __future__ import annotations

from ..paper_table import PaperTable, PaperValue, register

__all__ = ["LANDA2020_TESTBED"]

LANDA2020_TESTBED = register(PaperTable(
    name="landa2020-testbed",
    title="reciprocity search vs gradient ascent on the car testbed, from the paper arena's "
          "start to its source",
    reference="Landa et al. (2020), testbed experiment (Sec. 5)",
    build_spec=lambda runs: {"strategies": ["reciprocity", "gradient"], "scenarios": ["paper"],
                             "platform": "car", "seeds": runs},
    paper=(PaperValue("reciprocity", "n_measurements", 7.0),
           PaperValue("reciprocity", "error", 4.35),
           PaperValue("gradient", "n_samples", 18.0),
           PaperValue("gradient", "error", 5.0)),
    default_runs=20,
    note="The paper reports a single run of each strategy (no interval); our runs differ in "
         "the sensor noise and the car's actuation only (same arena, source and start).",
))
