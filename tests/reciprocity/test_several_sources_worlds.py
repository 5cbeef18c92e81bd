"""Several true sources in the plume and lattice worlds: superposition, ``found`` near any
source, a task that never tells them, refused inputs, and the judgement of one episode."""

import numpy as np
import pytest

from reciprocity import api
from reciprocity.errors import SearchError
from reciprocity.outcome import MAX_SOURCES
from reciprocity.scenarios import from_dict, load_scenario
from reciprocity.worlds.lattice import LatticeWorld, clusters

# -- plume -----------------------------------------------------------------------------
PLUME = dict(world="plume", bounds=[-50, 50, -50, 50], sources=[[-33.33, 33.33], [20.0, -10.0]],
             strengths=[2.0, 3.0], rate=2, V=0.5, wind_direction=0, found_radius=3, step=1,
             start=[33.33, -33.33, 90], max_steps=5, mismatch={"rate_factor": 1.5})
HIDDEN = {"source", "sources", "strengths", "n_sources"}


def plume(**over):
    return from_dict({**PLUME, **over}, name="two-plumes")


def test_the_plume_rate_of_two_sources_is_the_sum_of_their_rates():
    two = plume().build_world(0)
    one = [plume(sources=None, strengths=None, source=s, rate=c).build_world(0)
           for s, c in zip(PLUME["sources"], PLUME["strengths"])]
    pts = np.random.default_rng(0).uniform(-50, 50, (40, 2))
    assert np.allclose(two.rate(pts), one[0].rate(pts) + one[1].rate(pts), rtol=1e-12, atol=0)
    # true rates carry the mismatch; the nominal rate stays the scenario's
    assert two.strengths.tolist() == pytest.approx([3.0, 4.5])
    assert two.n_sources == 2 and two.source.tolist() == PLUME["sources"][0]


def test_a_plume_search_ends_near_any_source():
    w = plume().build_world(0)
    assert w.found([20.5, -9.0]) and w.found([-33.0, 33.0])
    assert not w.found([0.0, 0.0])


def test_the_plume_task_tells_the_bound_never_the_sources():
    w = plume(max_sources=3).build_world(0)
    nominal = w.nominal()
    assert nominal["max_sources"] == 3 and nominal["plume"].rate == 2.0
    assert not HIDDEN & set(nominal)
    assert plume().build_world(0).nominal()["max_sources"] == MAX_SOURCES
    assert "max_sources" not in load_scenario("song-100").build_world(0).nominal()
    d = w.describe()
    assert (d["n_sources"], d["max_sources"], d["sources"]) == (2, 3, PLUME["sources"])


def test_one_source_replaces_several_and_back():
    sc = load_scenario("song-100").with_world({"sources": [[-33.33, 33.33], [10.0, 10.0]]})
    assert sc.build_world(0).n_sources == 2
    back = sc.with_world({"source": [0.0, 20.0]}).build_world(0)
    assert back.n_sources == 1 and back.max_sources == 1 and "sources" not in back.describe()


@pytest.mark.parametrize("over, message", [
    (dict(sources=[[-33.33, 33.33], [60.0, 0.0]]), "plume sources[1] [60.0, 0.0] is outside the area"),
    (dict(sources=[], strengths=None), f"plume sources must be a list of 1 to {MAX_SOURCES} points"),
    (dict(sources=[[0.0, 0.0]] * (MAX_SOURCES + 1), strengths=None), "plume sources must be a list of 1 to"),
    (dict(sources=[[0.0, 0.0], "a"]), "plume sources[1] must be [x, y]"),
    (dict(sources=[[1.0, 2.0], [1.0, 2.0]]), "plume sources[1] [1.0, 2.0] repeats an earlier source"),
    (dict(strengths=[2.0]), "plume strengths must give one release rate per source (2); got [2.0]"),
    (dict(strengths=[2.0, -1.0]), "plume strengths[1] must be a number in [1e-09, 1e+06]; got -1.0"),
    (dict(max_sources=1), "plume max_sources (1) is less than the number of sources (2)"),
    (dict(max_sources=9), f"plume max_sources must be a whole number from 1 to {MAX_SOURCES}; got 9"),
    (dict(source=[0.0, 0.0]), "plume source [0.0, 0.0] is not the first of sources"),
    (dict(source="drawn", motion="grid"), "plume source 'drawn' is not the first of sources"),
    (dict(sources=None), "plume strengths [2.0, 3.0] needs sources"),
])
def test_bad_plume_sources_are_refused_naming_the_key(over, message):
    data = {**PLUME, **over}
    if over.get("sources", ...) is None:
        data.update(source=[0.0, 0.0])
    with pytest.raises(SearchError) as err:
        from_dict(data, name="bad")
    assert message in str(err.value) and "\n" not in str(err.value)


def test_a_plume_episode_is_judged_source_by_source():
    ep, _, _ = api.execute(plume(), "infotaxis", seed=0, params={"particles": 100})
    s = ep.summary
    assert s["steps"] <= 5 and s["n_sources"] == 2
    assert s["n_sources_estimated"] == len(s["estimates"]) <= 1      # infotaxis reports one source
    assert len(s["errors"]) == 2 and None in s["errors"] and s["success"] is False


# -- lattice ---------------------------------------------------------------------------
LATTICE = dict(world="lattice", radius=9, p=0.35, links="ristic-fig2", sources=[[0, 7], [-3, -2]],
               strengths=[12, 5], entry=[9, -4], start=[9, -4], platform="lattice", max_steps=5)


def lattice(**over):
    return from_dict({**LATTICE, **over}, name="two-lattice")


def test_the_lattice_counts_of_two_sources_are_the_sum_of_their_counts():
    two = lattice().build_world(0)
    one = [LatticeWorld(two.space, s, c) for s, c in zip(LATTICE["sources"], LATTICE["strengths"])]
    assert np.allclose(two.lam, one[0].lam + one[1].lam, rtol=1e-12, atol=0)
    assert two.n_sources == 2 and two.strengths.tolist() == [12.0, 5.0] and two.strength == 12.0
    assert two.found([-3, -2]) and two.found([0, 7]) and not two.found([-3, -1])
    # the evaluator's shortest path is to the nearest source
    paths = [w.describe_start([9, -4])["shortest_path"] for w in one]
    assert two.describe_start([9, -4])["shortest_path"] == min(paths)


def test_a_drawn_lattice_keeps_every_source_in_the_entry_cluster():
    w = lattice(links=None, lattice_seed=3, connectivity="nodes", p=0.45).build_world(0)
    lab = clusters(w.space)
    entry = int(w.space.index_of([9, -4])[0])
    assert set(lab[w.source_nodes].tolist()) == {lab[entry]}


def test_the_lattice_task_tells_the_bound_never_the_sources():
    w = lattice().build_world(0)
    assert w.nominal()["max_sources"] == MAX_SOURCES and not HIDDEN & set(w.nominal())
    assert "max_sources" not in load_scenario("ristic-lattice").build_world(0).nominal()
    d = w.describe()
    assert (d["n_sources"], d["strengths"], d["sources"]) == (2, [12.0, 5.0], [[0.0, 7.0], [-3.0, -2.0]])


@pytest.mark.parametrize("over, message", [
    (dict(sources=[[0, 7], [0.5, 2]]), "sources[1] [0.5, 2.0] is not a node of the lattice"),
    (dict(sources=[[0, 7], [9, 1]]), "sources[1] [9.0, 1.0] is not a node of the lattice: integers with "
                                     "x² + y² <= R0²"),
    (dict(sources=[[0, 7], [0, 7]]), "sources[1] [0, 7] repeats an earlier source"),
    (dict(sources=[], strengths=None), f"sources must be a list of 1 to {MAX_SOURCES} lattice nodes"),
    (dict(strengths=[12]), "strengths must give one release rate A0 per source (2); got [12]"),
    (dict(strengths=[12, 0]), "strengths[1] must be a number in (0, 1e+06]; got 0"),
    (dict(max_sources=1), "max_sources (1) is less than the number of sources (2)"),
    (dict(max_sources=0), f"max_sources must be a whole number from 1 to {MAX_SOURCES}; got 0"),
    (dict(source=[1, 1]), "source [1, 1] is not the first of sources"),
    (dict(sources=None, source=[0, 7]), "strengths [12, 5] needs sources"),
])
def test_bad_lattice_sources_are_refused_naming_the_key(over, message):
    with pytest.raises(SearchError) as err:
        lattice(**over)
    assert message in str(err.value) and "\n" not in str(err.value)


def test_a_lattice_episode_is_judged_source_by_source():
    ep, _, _ = api.execute(lattice(), "rbpf", seed=0, params={"n_particles": 300, "n_gain": 50})
    s = ep.summary
    assert s["steps"] <= 5 and s["n_sources"] == 2 and s["max_sources"] == MAX_SOURCES
    assert s["n_sources_estimated"] == len(s["estimates"]) <= 1
    assert len(s["errors"]) == 2 and None in s["errors"] and s["success"] is False
