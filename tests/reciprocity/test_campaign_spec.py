"""Campaign specs: parsing, grids, seeds and one-line validation errors."""

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
    ({"seeds": 0}, "seeds must be an integer >= 1"),
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
                       "scenarios": [{"name": "song-100", "world": {"start": [33.33, -33.33, 90]}}]})
    episode, _, _ = execute_task(next(iter(spec.tasks())))
    # one step from heading +y with turns of at most 3 degrees (song-100's printed limit)
    pose = episode.records[0].pose
    assert abs(pose[2] - np.pi / 2) <= np.radians(3) + 1e-9
