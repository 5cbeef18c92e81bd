"""``reciprocity reproduce``: the registered paper tables, their specs, and the comparison
(averages over successful runs, values without a paper number, the ``after`` hook)."""

import duckdb
import numpy as np
import pytest

from reciprocity.campaign import parse_spec
from reciprocity.campaign.reproduce import (TABLES, PaperTable, PaperValue, compare,
                                            comparison_markdown, reproduce)
from reciprocity.campaign.spec import entry_scenario, world_overrides
from reciprocity.campaign.store import episodes_sql
from reciprocity.cli import main
from reciprocity.errors import SearchError
from reciprocity.scenarios import load_scenario, scenario_names
from reciprocity.strategies import STRATEGIES

#: The tables DESIGN.md's public contract names.
DESIGN_TABLES = ("landa2020-testbed", "ristic2014-table1", "ristic2014-table2", "song2019-table1",
                 "otto-2d", "hajieghrary-voi", "farrell-hmm")


def test_every_design_table_is_registered():
    assert set(DESIGN_TABLES) <= set(TABLES)


@pytest.mark.parametrize("name", DESIGN_TABLES)
def test_table_spec_validates_and_names_existing_things(name):
    table = TABLES[name]
    spec = table.spec(2)                      # parse and check only, no episode runs
    assert spec.seeds == 2 and spec.name == name
    assert table.spec().seeds == table.default_runs
    assert all(v.strategy in STRATEGIES for v in spec.variants)
    assert all(s.ref in scenario_names() for s in spec.scenarios)
    variants = {v.label for v in spec.variants}
    scenarios = {s.label for s in spec.scenarios}
    for pv in table.paper:                    # every printed value is a row of the campaign
        assert pv.variant in variants, (name, pv)
        assert pv.scenario is None or pv.scenario in scenarios, (name, pv)


def test_the_papers_numbers_and_settings():
    t1, t2 = TABLES["ristic2014-table1"], TABLES["ristic2014-table2"]
    steps = {pv.row: pv.value for pv in t1.paper if pv.metric == "steps"}
    assert steps == {"(0, 7)": 42.1, "(0, 1)": 34.0, "(2, −5)": 28.8}
    assert all(pv.among == "success" for pv in t1.paper + t2.paper if pv.metric == "steps")
    assert {pv.row: pv.value for pv in t2.paper if pv.metric == "success"} == {
        "A0 = 8": 0.78, "A0 = 12": 0.94, "A0 = 16": 0.93}
    assert t1.default_runs == t2.default_runs == 100
    song = TABLES["song2019-table1"].spec(1)
    assert all(s.world == {"max_turn": 3} for s in song.scenarios) and len(song.scenarios) == 6
    assert "±3°" in TABLES["song2019-table1"].note
    assert all(s.world == {"max_turn": 30} for s in TABLES["song2019-table1"].protocol("turn30").spec(1).scenarios)
    half = TABLES["song2019-table1-halfstep"]
    spec = half.spec(1)
    assert [s.label for s in spec.scenarios] == [f"song-{L}.halfstep" for L in (100, 150, 200, 250, 300, 350)]
    assert {pv.scenario for pv in half.paper} == {s.label for s in spec.scenarios}
    # the run starts 5 in from the bottom-right corner heading +y (degrees in a spec)
    sc = load_scenario("song-100").with_world(world_overrides(spec.scenarios[0].world))
    assert np.allclose(sc.starts[0], [45.0, -45.0, np.pi / 2])
    assert sc.params["step"] == 0.5 and sc.params["max_turn"] == 15
    otto = {pv.variant: (pv.value, pv.pm) for pv in TABLES["otto-2d"].paper if pv.metric == "steps"}
    assert otto == {"infotaxis": (11.72, 0.45), "space-aware-infotaxis": (11.52, 0.45)}
    assert TABLES["otto-2d"].default_runs >= 1000
    assert TABLES["hajieghrary-voi"].default_runs >= 50 and TABLES["farrell-hmm"].default_runs >= 50
    assert all(pv.value is None for n in ("hajieghrary-voi", "farrell-hmm") for pv in TABLES[n].paper)
    assert TABLES["farrell-hmm"].after is not None


def test_random_start_draws_the_worlds_default_start_per_seed():
    spec = TABLES["farrell-hmm"].spec(2)
    sc = entry_scenario(spec.scenarios[0])
    assert sc.starts is None
    w = sc.build_world(0)
    a, b = sc.start_poses(w, 1, 1), sc.start_poses(w, 1, 2)
    assert not np.allclose(a, b) and np.allclose(a, sc.start_poses(w, 1, 1))
    assert all(np.hypot(*(p[:2] - w.source)) >= 10.0 for p in (a[0], b[0]))
    with pytest.raises(SearchError, match="random_start draws the start"):
        parse_spec({"strategies": ["hmm"], "seeds": 1,
                    "scenarios": [{"name": "farrell", "random_start": True,
                                   "world": {"start": [50, 0]}}]})


def test_paper_value_rejects_unknown_averaging():
    with pytest.raises(SearchError, match="among"):
        PaperValue("x", "steps", 1.0, among="failures")


def test_success_averaging_none_values_and_after_hook(tmp_path, monkeypatch):
    """A tiny real campaign (empty arena, reciprocity h = 4, 6 steps at most: some runs
    converge, some hit the cap), compared through :func:`reproduce`. Without the
    likelihood's position term: at h = 4 cm it keeps the region wider than ``area_tol``
    for longer, and every run of these 8 would reach the cap."""
    called = []

    def after(directory, spec):
        called.append((directory, spec.name))
        f = directory / "figure.txt"
        f.write_text("x")
        return [f]

    table = PaperTable(
        name="tiny-test", title="tiny", reference="nobody (2026)",
        build_spec=lambda runs: {"strategies": {"reciprocity": {"h": 4.0, "max_steps": 6,
                                                                 "position_error": False}},
                                 "scenarios": ["empty"], "seeds": runs},
        paper=(PaperValue("reciprocity", "steps", 5.0, among="success", row="ok only"),
               PaperValue("reciprocity", "steps", None, row="all"),
               PaperValue("reciprocity", "success", None),
               PaperValue("reciprocity", "no_such_column", None, row="missing")),
        default_runs=8, note="a note", after=after)
    monkeypatch.setitem(TABLES, table.name, table)
    out = tmp_path / "tiny"
    _, result, rows, files = reproduce("tiny-test", out, workers=1, progress=False)
    assert result.n_run == 8 and result.n_failed == 0
    assert files == [out / "figure.txt"] and called == [(out, "tiny-test")]

    df = duckdb.sql(f"SELECT steps, success, distance_at_stop FROM {episodes_sql(out)}").fetchnumpy()
    ok = df["success"].astype(bool)
    assert 0 < ok.sum() < ok.size                       # a mix, so the two means differ
    assert np.all(df["distance_at_stop"] >= 0)
    success_only, everything, rate, missing = rows
    assert success_only["runs"] == ok.sum() and success_only["of"] == ok.size
    assert success_only["ours"] == pytest.approx(df["steps"][ok].mean())
    assert everything["ours"] == pytest.approx(df["steps"].mean())
    assert rate["rate"] and rate["ours"] == pytest.approx(ok.mean())
    assert rate["lo"] <= rate["ours"] <= rate["hi"]
    assert missing["runs"] == 0 and missing["ours"] is None

    text = comparison_markdown(table, rows)
    lines = {line.split(" | ")[0].lstrip("| "): line for line in text.splitlines() if line.startswith("| ")}
    assert "steps (successful runs) | 5 |" in lines["ok only"]
    assert f"| {ok.sum()} of {ok.size} |" in lines["ok only"]
    assert "| steps | – |" in lines["all"]            # no paper number: a dash
    assert "| success | – | " in lines["reciprocity"] and " %" in lines["reciprocity"]
    assert text.rstrip().endswith("a note")
    assert "| [–, –] | 0 |" in lines["missing"]
    assert [r["ours"] for r in compare(table, out)] == [r["ours"] for r in rows]


def test_reproduce_list_names_every_table(capsys):
    assert main(["reproduce", "--list"]) == 0
    out = capsys.readouterr().out
    names = [line.split()[0] for line in out.splitlines()]
    assert [n for n in names if n in DESIGN_TABLES] == list(DESIGN_TABLES)
    assert set(TABLES) <= set(names)
    assert all(TABLES[n].reference in out for n in DESIGN_TABLES)


@pytest.mark.parametrize("name", ["ristic2014-table1", "ristic2014-table2"])
def test_the_ristic_tables_run_under_the_papers_protocol(name):
    """--protocol paper: every row on the one shipped lattice (ristic-lattice-paper), in a
    campaign of its own name; other protocols are refused with the allowed ones."""
    table = TABLES[name].protocol("paper")
    spec = table.spec(2)
    assert spec.name == f"{name}-paper" and {s.ref for s in spec.scenarios} == {"ristic-lattice-paper"}
    assert "Fig. 2" in table.note and TABLES[name].protocol("default") is TABLES[name]
    with pytest.raises(SearchError, match="default, paper"):
        TABLES[name].protocol("nope")


def test_reproduce_protocol_on_the_command_line(tmp_path, capsys):
    out = tmp_path / "r"
    assert main(["reproduce", "ristic2014-table1", "--protocol", "paper", "--runs", "1", "--workers", "1",
                 "--out", str(out), "--quiet"]) == 0
    text = capsys.readouterr().out
    assert "Protocol 'paper'" in text and (out / "comparison.md").exists()
    assert main(["reproduce", "ristic2014-table1", "--protocol", "nope", "--out", str(tmp_path / "x")]) == 2
    assert not (tmp_path / "x").exists()


@pytest.mark.slow
def test_protocols_found_beside_are_printed_side_by_side(tmp_path, capsys):
    """A protocol's run prints, after its own table, every protocol whose results lie in
    the default folders beside it, one column and verdict each; a lone protocol does not."""
    common = ["--runs", "1", "--workers", "1", "--quiet"]
    assert main(["reproduce", "ristic2014-table1", "--out", str(tmp_path / "reproduce_ristic2014-table1"),
                 *common]) == 0
    assert "side by side" not in capsys.readouterr().out
    out = tmp_path / "reproduce_ristic2014-table1-paper"
    assert main(["reproduce", "ristic2014-table1", "--protocol", "paper", "--out", str(out), *common]) == 0
    text = capsys.readouterr().out
    side = text[text.index("protocols side by side"):]
    assert "| default | verdict | paper | verdict |" in side and (out / "protocols.md").read_text() in text
    rows = [line for line in side.splitlines() if line.startswith("| (")]
    assert len(rows) == len(TABLES["ristic2014-table1"].paper)


@pytest.mark.parametrize("paper, lo, hi, at_least, expected", [
    (7.0, 3.0, 8.0, 0.2, "in our 95 % CI"),
    (7.0, 3.0, 5.0, 0.1, "above our CI; 10 % of ours ≥ paper"),
    (1.0, 3.0, 5.0, 1.0, "below our CI; 100 % of ours ≥ paper"),
    (0.5, 0.7, 0.9, None, "below our CI"),
    (None, 3.0, 5.0, None, "–"),
    (7.0, None, None, None, "–"),
])
def test_verdict_says_where_the_paper_falls_among_ours(paper, lo, hi, at_least, expected):
    from reciprocity.campaign.reproduce import verdict
    assert verdict(dict(paper=paper, lo=lo, hi=hi, at_least=at_least)) == expected


@pytest.mark.parametrize("name, protocol", [(n, p) for n, t in TABLES.items() for p in t.protocols])
def test_every_protocol_spec_validates_and_prints_every_paper_value(name, protocol):
    table = TABLES[name].protocol(protocol)
    spec = table.spec(2)
    assert spec.name == f"{name}-{protocol}" and table.note
    variants = {v.label for v in spec.variants}
    scenarios = {s.label for s in spec.scenarios}
    assert all(s.ref in scenario_names() for s in spec.scenarios)
    for pv in table.paper:
        assert pv.variant in variants and (pv.scenario is None or pv.scenario in scenarios), (name, pv)


def test_rows_run_the_same_episodes_as_the_whole_table():
    """``reproduce TABLE --rows``: part of a table, with the whole table's episode ids and seeds."""
    from reciprocity.campaign.reproduce import TABLES
    table = TABLES["song2019-table1"]
    whole = {(t.episode_id, t.seed) for t in table.spec(3).tasks()}
    part = table.rows("song-100")
    assert {v.scenario for v in part.paper} == {"song-100"} and len(part.paper) < len(table.paper)
    tasks = {(t.episode_id, t.seed) for t in part.spec(3).tasks()}
    assert len(tasks) == 6 * 3 and tasks <= whole                     # six strategies, three seeds
    both = table.rows("song-100,free-energy")                         # union of what each names
    assert {(v.variant, v.scenario) for v in both.paper} >= {("free-energy", "song-350"), ("infotaxis", "song-100")}
    assert TABLES["ristic2014-table1"].rows("(0, 7)").paper[0].label == "(0, 7)"   # a label with a comma
    with pytest.raises(SearchError, match="names no row"):
        table.rows("song-999")


def test_reproduce_rows_on_the_command_line(tmp_path, monkeypatch, capsys):
    from reciprocity.cli import main
    monkeypatch.chdir(tmp_path)
    assert main(["reproduce", "ristic2014-table1", "--runs", "1", "--rows", "source_0_7", "--workers", "1",
                 "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "1 episodes run" in out and "| (0, 7) |" in out and "(0, 1)" not in out
    assert (tmp_path / "reproduce_ristic2014-table1-rows-source_0_7" / "comparison.md").is_file()
