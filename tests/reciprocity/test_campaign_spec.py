"""Campaign specs: parsing, grids, seeds and one-line validation errors."""

from pathlib import Path

import pytest

from reciprocity.campaign import episode_seed, load_spec, parse_spec
from reciprocity.errors import SearchError
from reciprocity.strategies import STRATEGIES

BASE = {"strategies": ["reciprocity", "gradient"], "scenarios": ["empty"], "seeds": 3}


def test_grid_expands_to_cartesian_variants_with_labels():
    spec = parse_spec({**BASE, "strategies": {"reciprocity": {"h": 4.0, "eps": [0.05, 0.1],
                                                              "d": [4, 6]}, "gradient": None}})
    labels = [v.label for v in spec.variants]
    assert labels == ["reciprocity[eps=0.05,d=4]", "reciprocity[eps=0.05,d=6]",
                      "reciprocity[eps=0.1,d=4]", "reciprocity[eps=0.1,d=6]", "gradient"]
    assert spec.variants[1].params == {"h": 4.0, "eps": 0.05, "d": 6}
    assert spec.n_episodes == 3 * 5 == len(list(spec.tasks()))


def test_seeds_are_shared_by_strategies_and_independent_of_order():
    spec = parse_spec({**BASE, "seed": 7})
    tasks = list(spec.tasks())
    by_index = {}
    for t in tasks:
        by_index.setdefault(t.seed_index, set()).add(t.seed)
    assert all(len(s) == 1 for s in by_index.values())
    assert len({t.episode_id for t in tasks}) == len(tasks)
    assert tasks[0].seed == episode_seed(7, 0) != episode_seed(8, 0)
    assert len({episode_seed(7, i) for i in range(100)}) == 100


def test_digest_ignores_seeds_but_not_the_rest():
    a, b = parse_spec(BASE), parse_spec({**BASE, "seeds": 10})
    assert a.digest == b.digest
    assert parse_spec({**BASE, "seed": 1}).digest != a.digest
    assert parse_spec({**BASE, "strategies": {"reciprocity": {"h": 4.0}}}).digest != a.digest


def test_platform_options_reach_every_episode_and_the_digest():
    """``platform_options`` go to every episode's platform and into the digest; a spec
    without them hashes as before (earlier campaigns resume)."""
    car = dict(BASE, platform="car", scenarios=["paper"], seeds=2)
    plain = parse_spec(car)
    spec = parse_spec({**car, "platform_options": {"planner": "bank", "bank_spacing": 12.7, "dwell": 1 / 30}})
    assert plain.platform_options is None and "platform_options" not in plain.source
    assert spec.platform_options == {"planner": "bank", "bank_spacing": 12.7, "dwell": 1 / 30}
    assert {t.platform_options["planner"] for t in spec.tasks()} == {"bank"}
    assert spec.digest != plain.digest


@pytest.mark.parametrize("change, match", [
    ({"platform_options": {"planner": "bank"}}, "platform_options needs platform"),
    ({"platform": "car", "platform_options": ["bank"]}, "platform_options must be a mapping"),
    ({"platform": "car", "platform_options": {"plannr": "bank"}}, "unknown car option.*plannr"),
    ({"platform": "car", "platform_options": {"dwell": 0}}, "dwell"),
    ({"platform": "car", "platform_options": {"planner": "astar"}}, "planner must be one of"),
])
def test_bad_platform_options_are_refused_at_parse_time(change, match):
    with pytest.raises(SearchError, match=match) as info:
        parse_spec({**BASE, "scenarios": ["paper"], **change})
    assert "\n" not in str(info.value)


def test_spec_file_with_scenario_entries(tmp_path):
    f = tmp_path / "c.yaml"
    f.write_text("seeds: 2\nrandom_source: true\nstrategies: [gradient]\n"
                 "scenarios: [empty, {name: maze, label: maze-noisy, world: {noise: 20}}]\n")
    spec = load_spec(f, seed=5)
    assert spec.name == "c" and spec.seed == 5
    assert [s.label for s in spec.scenarios] == ["empty", "maze-noisy"]
    assert spec.scenarios[1].world == {"noise": 20} and spec.scenarios[1].random_source


@pytest.mark.parametrize("change, match", [
    ({"strategies": ["nope"]}, "unknown strategy 'nope'"),
    ({"scenarios": ["atlantis"]}, "unknown scenario 'atlantis'"),
    ({"strategies": {"reciprocity": {"eps": []}}}, "empty grid"),
    ({"strategies": {"reciprocity": {"epsilon": 0.1}}}, "has no parameter"),
    ({"seeds": 0}, "seeds must be a whole number from 1 to 100000; got 0"),
    ({"seedz": 3}, "unknown campaign spec key"),
    ({"platform": "boat"}, "platform 'boat'"),
    ({"scenarios": [{"name": "empty", "world": {"source": [1, 2]}}], "random_source": True},
     "random_source draws the source"),
    ({"scenarios": ["empty", "empty"]}, "appear twice"),
])
def test_invalid_specs_raise_one_line_errors(change, match):
    with pytest.raises(SearchError, match=match) as info:
        parse_spec({**BASE, **change})
    assert "\n" not in str(info.value)


def test_unsupported_pair_is_refused(monkeypatch):
    monkeypatch.setattr(STRATEGIES["gradient"], "worlds", ("lattice",), raising=False)
    with pytest.raises(SearchError, match="'gradient' does not apply to scenario 'empty'"):
        parse_spec(BASE)


def test_missing_and_malformed_files(tmp_path):
    with pytest.raises(SearchError, match="cannot read campaign spec"):
        load_spec(tmp_path / "none.yaml")
    (tmp_path / "bad.yaml").write_text("strategies: [a\n")
    with pytest.raises(SearchError, match="not valid YAML"):
        load_spec(tmp_path / "bad.yaml")


def test_pairs_supported_runs_only_the_pairs_that_apply():
    data = {"seeds": 2, "strategies": ["reciprocity", "rbpf", "random-walk"],
            "scenarios": ["empty", "ristic-lattice"]}
    with pytest.raises(SearchError, match="does not apply"):
        parse_spec(data)
    spec = parse_spec({**data, "pairs": "supported"})
    pairs = {(t.scenario.label, t.variant.label) for t in spec.tasks()}
    assert pairs == {("empty", "reciprocity"), ("empty", "random-walk"),
                     ("ristic-lattice", "rbpf"), ("ristic-lattice", "random-walk")}
    assert spec.n_episodes == 2 * len(pairs) == len(list(spec.tasks()))
    assert spec.digest != parse_spec({**data, "strategies": ["random-walk"]}).digest
    with pytest.raises(SearchError, match="no strategy of the spec applies to scenario 'ristic-lattice'"):
        parse_spec({**data, "strategies": ["reciprocity"], "pairs": "supported"})
    with pytest.raises(SearchError, match="pairs must be"):
        parse_spec({**data, "pairs": "some"})


def test_a_start_heading_in_a_spec_is_in_degrees_like_scenario_files():
    import numpy as np
    from reciprocity.campaign.spec import world_overrides
    from reciprocity.campaign.worker import execute_task
    assert world_overrides({"start": [1, 2, 90], "rate": 1}) == {"start": [1, 2, np.pi / 2], "rate": 1}
    assert world_overrides({"start": [[1, 2, 180], [3, 4]]}) == {"start": [[1, 2, np.pi], [3, 4]]}
    spec = parse_spec({"name": "h", "strategies": ["infotaxis"], "seeds": 1,
                       "scenarios": [{"name": "song-100-printed", "world": {"start": [33.33, -33.33, 90]}}]})
    episode, _, _ = execute_task(next(iter(spec.tasks())))
    # one step from heading +y with turns of at most 3 degrees (the printed limit)
    pose = episode.records[0].pose
    assert abs(pose[2] - np.pi / 2) <= np.radians(3) + 1e-9


@pytest.mark.parametrize("text, match", [
    ("seeds: 1\nseeds: 2\nstrategies: [gradient]\nscenarios: [empty]\n", "duplicate key 'seeds'"),
    ("seeds: 1\nscenarios: [empty]\nstrategies:\n  gradient: {h: 4.0}\n  gradient: {h: 2.0}\n",
     "duplicate key 'gradient'"),
    ("seeds: 1\nscenarios: [empty]\nstrategies: [gradient, reciprocity, gradient]\n",
     "strategy 'gradient' is listed twice"),
    ("seeds: 1\nscenarios: [empty]\nstrategies: {gradient: {h: [4.0, 2.0, 4.0]}}\n",
     r"gradient\[h=4.0\] appear twice"),
])
def test_duplicate_keys_strategies_and_variants_are_refused(tmp_path, text, match):
    f = tmp_path / "dup.yaml"
    f.write_text(text)
    with pytest.raises(SearchError, match=match) as info:
        load_spec(f)
    assert "\n" not in str(info.value)


def test_binary_files_and_folders_are_refused_as_specs(tmp_path):
    (tmp_path / "bin.yaml").write_bytes(b"seeds: 1\0\xff")
    with pytest.raises(SearchError, match="binary"):
        load_spec(tmp_path / "bin.yaml")
    with pytest.raises(SearchError, match="is a folder"):
        load_spec(tmp_path)


@pytest.mark.parametrize("change, match", [
    ({"seeds": 100_001}, "seeds must be a whole number from 1 to 100000; got 100001"),
    ({"seeds": 2.5}, "seeds must be a whole number"),
    ({"seed": -1}, "seed must be a whole number from 0 to 9223372036854775807"),
    ({"seed": 2**63}, "seed must be a whole number from 0"),
    ({"agents": 65}, "agents must be a whole number from 1 to 64; got 65"),
    ({"seeds": 100_000, "strategies": {"reciprocity": {"h": [1.0, 2.0, 3.0, 4.0, 5.0, 6.0,
                                                             7.0, 8.0, 9.0, 10.0, 11.0]}}},
     "= 1100000 episodes; at most 1000000"),
    # 20^6 = 64 million variants: refused from the axis lengths, never expanded
    ({"strategies": {"reciprocity": {k: list(range(20)) for k in
                                     ("h", "eps", "d", "sigma", "reach", "combine")}}},
     "give 64000000 variants; at most 10000"),
    ({"strategies": {"reciprocity": {"h": list(range(1, 101))}},
      "scenarios": [{"name": "empty", "label": f"e{i}"} for i in range(101)]},
     "= 10100 pairs; at most 10000"),
    ({"platform": ["point"]}, "platform must be a name"),
    ({"strategies": [["gradient"]]}, "strategies must be a list of names"),
    ({"scenarios": [{"label": "x"}]}, "a scenario must be a name or a mapping with 'name'"),
])
def test_sizes_and_numbers_are_bounded_at_parse_time(change, match):
    with pytest.raises(SearchError, match=match) as info:
        parse_spec({**BASE, **change})
    assert "\n" not in str(info.value)


def test_every_scenario_is_checked_before_the_first_episode(tmp_path):
    (tmp_path / "bad_lattice.yaml").write_text("world: lattice\nradius: 9\np: 2.0\n")
    with pytest.raises(SearchError, match=r"unknown poisson world parameter\(s\) colour"):
        parse_spec({**BASE, "scenarios": ["empty", {"name": "maze", "world": {"colour": 1}}]})
    with pytest.raises(SearchError, match="scenario 'empty'.*(start|corner)"):
        parse_spec({**BASE, "scenarios": [{"name": "empty", "world": {"start": "corner"}}]})
    with pytest.raises(SearchError, match="p must be a fraction"):
        parse_spec({"seeds": 1, "strategies": ["random-walk"],
                    "scenarios": ["otto-2d", "bad_lattice.yaml"]}, base_dir=tmp_path)


def test_a_scenario_starting_outside_its_arena_is_refused_up_front(tmp_path):
    (tmp_path / "outside.yaml").write_text("world: poisson\narena: empty\nstart: [500, 500, 0]\n")
    with pytest.raises(SearchError, match="start"):
        parse_spec({"seeds": 1, "strategies": ["gradient"], "scenarios": ["outside.yaml"]},
                   base_dir=tmp_path)


def test_a_plain_arena_file_is_a_campaign_scenario(tmp_path):
    import numpy as np
    from reciprocity.campaign.worker import run_task
    (tmp_path / "my_arena.yaml").write_text(
        "boundary: [[0, 0], [140, 0], [140, 140], [0, 140]]\n"
        "obstacles:\n  - [[40, 50], [46, 50], [46, 96], [94, 96], [94, 76], [100, 76], "
        "[100, 102], [40, 102]]\n"
        "source: [70.21, 70.21]\nstrength: 850\nstart: [128, 12, 135]\n")
    spec = parse_spec({"seeds": 1, "strategies": {"random-walk": {"n_steps": 2}},
                       "scenarios": ["my_arena.yaml"]}, base_dir=tmp_path)
    (entry,) = spec.scenarios
    assert entry.label == "my_arena" and entry.file_digest is not None
    row = run_task(next(spec.tasks()))
    assert row["error_message"] is None and row["world"] == "poisson"
    assert row["source"] == [70.21, 70.21] and row["steps"] == 2
    assert np.allclose(row["start"], [128, 12, np.radians(135)])   # degrees in the file


def test_scheduler_of_a_spec_is_checked_and_not_hashed(tmp_path):
    spec = parse_spec({**BASE, "scheduler": {"address": "tls://10.0.0.5:8786", "tls": {
        "ca_file": "ca.pem", "cert": "client.pem", "key": "client.key"}}}, base_dir=tmp_path)
    assert spec.scheduler == "tls://10.0.0.5:8786"
    assert spec.tls.ca_file == str(tmp_path / "ca.pem") and spec.tls.key == str(tmp_path / "client.key")
    assert spec.digest == parse_spec(BASE).digest      # where episodes run does not change them
    assert parse_spec({**BASE, "scheduler": "127.0.0.1:8786"}).scheduler == "127.0.0.1:8786"
    for bad, match in ((["x"], "scheduler must be an address"),
                       ({"address": "http://h:1"}, "tcp://HOST:PORT"),
                       ({"address": "tcp://h:70000"}, "port 1 to 65535"),
                       ({"address": "tls://h:1", "tls": {"ca_file": "a"}}, "scheduler tls must be"),
                       ({"address": "tls://h:1", "hosts": 2}, "unknown key")):
        with pytest.raises(SearchError, match=match):
            parse_spec({**BASE, "scheduler": bad})



#: The campaign specs among the benchmarks' YAML files (the others configure a script).
BENCH_SPECS = sorted(p for p in (Path(__file__).resolve().parents[2] / "benchmarks").glob("*.yaml")
                     if "\nstrategies:" in p.read_text())


@pytest.mark.parametrize("path", BENCH_SPECS, ids=lambda p: p.name)
def test_every_campaign_spec_of_the_benchmarks_is_valid(path):
    """The specs the benchmark docs tell users to run still parse and check."""
    spec = load_spec(path)
    assert spec.n_episodes >= 1


def test_generated_arenas_as_scenarios_and_world_overrides():
    from reciprocity.campaign.spec import entry_scenario, world_overrides
    spec = parse_spec({**BASE, "scenarios": [
        "generate:rooms:3",
        {"name": "generate:maze:2:cols=3", "label": "small-maze"},
        {"name": "paper", "label": "paper-as-spiral", "world": {"arena": {"generate": "spiral", "seed": 4}}}]})
    assert [s.label for s in spec.scenarios] == ["rooms-3", "small-maze", "paper-as-spiral"]
    rooms = entry_scenario(spec.scenarios[0])
    assert rooms.arena.name == "rooms-3" and rooms.params["source"] == rooms.arena.source.tolist()
    spiral = entry_scenario(spec.scenarios[2]).with_world(world_overrides(spec.scenarios[2].world))
    # the spiral's own source, not paper's (which may lie in the spiral's wall)
    assert spiral.arena.name == "spiral-4" and spiral.params["source"] == spiral.arena.source.tolist()


def test_a_list_of_pairs_runs_only_those_pairs():
    full = parse_spec({"strategies": ["reciprocity", "gradient"], "scenarios": ["empty", "paper"], "seeds": 2})
    part = parse_spec({"strategies": ["reciprocity", "gradient"], "scenarios": ["empty", "paper"], "seeds": 2,
                       "pairs": [["paper", "gradient"], ["empty", "gradient"]]})
    ids = [t.episode_id for t in part.tasks()]
    assert ids == ["empty/gradient/0", "empty/gradient/1", "paper/gradient/0", "paper/gradient/1"]
    assert part.n_episodes == 4 and part.digest != full.digest
    assert part.source["pairs"] == [["empty", "gradient"], ["paper", "gradient"]]
    seeds = {t.episode_id: t.seed for t in full.tasks()}
    assert all(seeds[t.episode_id] == t.seed for t in part.tasks())      # the same episodes
    for bad, match in (([["maze", "gradient"]], "names scenario 'maze'"), ([["empty", "rbpf"]], "variant 'rbpf'"),
                       ([], "empty list"), ([["empty"]], r"\[scenario label, variant label\]")):
        with pytest.raises(SearchError, match=match):
            parse_spec({"strategies": ["gradient"], "scenarios": ["empty"], "seeds": 1, "pairs": bad})
