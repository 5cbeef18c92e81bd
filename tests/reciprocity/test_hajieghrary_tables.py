"""The tables of papers/001: the Fig. 1 sweep, the basis sweep and the paper protocol."""

from __future__ import annotations

from reciprocity.campaign.reproduce import TABLES
from reciprocity.campaign.tables.hajieghrary import BASIS_COUNTS, EVERY_STEP, FIG1_PARTICLES


def test_fig1_sweeps_every_count_and_sharing_rule_and_prints_the_papers_one_number():
    table = TABLES["hajieghrary-fig1"]
    variants = {v.label: v.params for v in table.spec(1).variants}
    assert len(variants) == 3 * len(FIG1_PARTICLES)
    assert all(p["rejuvenate"] is False for p in variants.values())
    printed = [pv for pv in table.paper if pv.value is not None]
    assert [(pv.variant, pv.metric, pv.value) for pv in printed] == [
        (f"voi[particles={FIG1_PARTICLES[-1]},share=all]", "success", 0.0)]
    every = {v.label: v.params for v in table.protocol("every-step").spec(1).variants}
    assert every.keys() == variants.keys() and all(p["resample_below"] == EVERY_STEP for p in every.values())
    assert all(p["rejuvenate"] is True for p in
               (v.params for v in table.protocol("rejuvenated").spec(1).variants))
    # the control: the every-step schedule with moves, one thing changed
    both = {v.label: v.params for v in table.protocol("every-step-rejuvenated").spec(1).variants}
    assert both.keys() == variants.keys()
    assert all(p["resample_below"] == EVERY_STEP and p["rejuvenate"] is True for p in both.values())


def test_fig1_rows_run_one_count():
    part = TABLES["hajieghrary-fig1"].rows("1000 particles: share all,1000 particles: independent")
    assert {v.label for v in part.spec(1).variants} == {"voi[particles=1000,share=all]",
                                                        "voi[particles=1000,share=none]"}


def test_the_paper_set_up_runs_the_papers_searcher_in_every_world():
    mis = TABLES["hajieghrary-misleading"].protocol("paper").spec(1)
    assert all(v.params["preset"] == "paper" for v in mis.variants)
    assert [v.label for v in mis.variants] == [v.label for v in TABLES["hajieghrary-misleading"].spec(1).variants]
    basis = TABLES["hajieghrary-basis"].spec(1)
    assert {v.params["basis"] for v in basis.variants} == set(BASIS_COUNTS)
    assert [s.ref for s in TABLES["hajieghrary-basis"].protocol("directional").spec(1).scenarios] == [
        "hajieghrary-directional"]
