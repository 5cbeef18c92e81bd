"""Generated arenas (arenas.families): valid, one piece, reachable through MIN_GAP, deterministic."""

import math

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

import arenas
from arenas import ArenaError
from arenas.families import CLEARANCE, MAX_GENERATED_VERTICES, MIN_GAP, from_text, size_keys

SEEDS = range(6)


def _core(arena):
    """The free region shrunk by MIN_GAP / 2: what the guarantee says is one piece."""
    return arena.free_region.buffer(-(MIN_GAP / 2 - 0.02), quad_segs=4)


def check_arena(arena) -> None:
    assert arena.free_region.geom_type == "Polygon"
    core = _core(arena)
    assert core.geom_type == "Polygon", f"{arena.name}: a gap under {MIN_GAP} cm"
    assert arena.contains(arena.source, clearance=CLEARANCE - 1e-9)[0]
    assert arena.contains(arena.start[:2], clearance=CLEARANCE - 1e-9)[0]
    assert core.contains(shapely.Point(arena.source)) and core.contains(shapely.Point(arena.start[:2]))
    assert 0 <= arena.start[2] < 2 * math.pi
    assert sum(len(o) for o in arena.obstacles) <= MAX_GENERATED_VERTICES


def test_at_least_six_families():
    assert set(arenas.FAMILIES) >= {"rooms", "spiral", "ring", "pillars", "maze", "office"}


@pytest.mark.parametrize("family", arenas.FAMILIES)
def test_every_family_is_valid_connected_and_reachable(family):
    for seed in SEEDS:
        a = arenas.generate(family, seed)
        check_arena(a)
        assert a.name == f"{family}-{seed}"
        # the size of the paper arena, so that episodes cost about the same
        assert 10_000 < a.area <= 140 * 140


@pytest.mark.parametrize("family", arenas.FAMILIES)
def test_same_seed_same_arena_other_seed_other_arena(family):
    a, b, c = arenas.generate(family, 5), arenas.generate(family, 5), arenas.generate(family, 6)
    assert np.array_equal(a.boundary, b.boundary) and np.array_equal(a.source, b.source)
    assert all(np.array_equal(x, y) for x, y in zip(a.obstacles, b.obstacles, strict=True))
    assert not np.array_equal(a.source, c.source)


@pytest.mark.parametrize("family, size", [
    ("rooms", dict(cols=5, rows=4, door=16, loops=0.0, wall=3)),
    ("spiral", dict(turns=3, width=200, height=160)),
    ("ring", dict(rings=3, radius=100, gap=16)),
    ("pillars", dict(pillars=14, pillar=6, width=200, notch=0.5)),
    ("maze", dict(cols=6, rows=7, loops=0.3, wall=2)),
    ("office", dict(offices=5, corridor=16, door=16, width=200, wall=3)),
])
def test_the_hardest_sizes_keep_the_guarantee(family, size):
    for seed in range(3):
        a = arenas.generate(family, seed, **size)
        check_arena(a)
        assert a.name.startswith(f"{family}-{seed}-")


@settings(max_examples=25, deadline=None, derandomize=True, database=None)
@given(family=st.sampled_from(arenas.FAMILIES), seed=st.integers(0, 2 ** 63 - 1))
def test_any_seed_gives_a_reachable_arena(family, seed):
    check_arena(arenas.generate(family, seed))


def test_the_text_and_mapping_forms():
    a = arenas.load("generate:maze:7:cols=6,rows=5")
    b = arenas.generate("maze", 7, cols=6, rows=5)
    assert a.name == b.name == "maze-7-cols6-rows5"
    assert np.array_equal(a.source, b.source)
    assert from_text("generate:rooms").name == "rooms-0"
    c = arenas.from_dict({"generate": "ring", "seed": 2, "rings": 1})
    assert c.name == "ring-2-rings1" and len(c.obstacles) == 1


def test_size_keys_name_their_bounds():
    keys = size_keys("spiral")
    assert keys["turns"][:3] == (2, 1, 6)
    assert set(size_keys("rooms")) >= {"width", "height", "wall", "cols", "rows", "door", "loops"}


@pytest.mark.parametrize("call, words", [
    (lambda: arenas.generate("castle", 1), ["family", "'castle'", "rooms, spiral"]),
    (lambda: arenas.generate("rooms", -1), ["seed", "-1", "[0, 2**63 - 1]"]),
    (lambda: arenas.generate("rooms", 1.5), ["seed", "1.5"]),
    (lambda: arenas.generate("rooms", True), ["seed", "True"]),
    (lambda: arenas.generate("rooms", 1, turns=2), ["turns", "allowed keys are", "door"]),
    (lambda: arenas.generate("rooms", 1, door=3), ["door", "got 3", "[16, 100]"]),
    (lambda: arenas.generate("maze", 1, cols=2.5), ["cols", "an integer in [2, 12]", "2.5"]),
    (lambda: arenas.generate("maze", 1, width=float("nan")), ["width", "nan"]),
    (lambda: arenas.generate("maze", 1, width="wide"), ["width", "'wide'", "[60, 300]"]),
    (lambda: arenas.generate("spiral", 1, turns=5), ["turns=5", "at most 2 turns"]),
    (lambda: arenas.generate("rooms", 1, cols=8), ["cols=8", "fewer rooms"]),
    (lambda: arenas.generate("ring", 1, rings=6), ["rings=6", "at most"]),
    (lambda: arenas.generate("pillars", 1, pillars=80), ["pillars=80", "fit"]),
    (lambda: arenas.generate("office", 1, offices=8), ["offices=8", "fewer offices"]),
    (lambda: arenas.load("generate:rooms:x"), ["seed", "'x'"]),
    (lambda: arenas.load("generate:rooms:1:door"), ["'door'", "KEY=VALUE"]),
    (lambda: arenas.load("generate:rooms:1:2:3"), ["generate:FAMILY"]),
    (lambda: arenas.from_dict({"generate": "maze", "seed": 1, "colour": 2}, where="scenario arena"),
     ["scenario arena", "colour", "allowed keys"]),
])
def test_bad_input_names_the_key_the_value_and_what_is_allowed(call, words):
    with pytest.raises(ArenaError) as exc:
        call()
    for w in words:
        assert w in str(exc.value)


def test_a_generated_arena_states_the_clearance_its_source_was_drawn_with():
    a = arenas.generate("rooms", 3)
    assert a.source_clearance == CLEARANCE
    assert a.wall_distance(a.source)[0] >= CLEARANCE
    assert arenas.from_dict(arenas.to_dict(a)).source_clearance == CLEARANCE      # an arena file keeps it
    moved = a.with_scenario(source=[20.0, 20.0])        # a new source says nothing of how it was drawn
    assert moved.source_clearance == 0.0
    assert a.with_scenario(strength=500.0).source_clearance == CLEARANCE
    with pytest.raises(ArenaError, match="nearer than its source_clearance of 30 cm"):
        a.with_scenario(source_clearance=30.0)
    with pytest.raises(ArenaError, match="source_clearance must be a distance"):
        a.with_scenario(source_clearance=-1)
