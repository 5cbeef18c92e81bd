"""The stop rule of the reciprocity search: step 12 with its extent, tail and credible
rules, the modes, and the unreachable stop (reciprocity.strategies.imaging_search.stop_rule),
on hand-built beliefs."""

import numpy as np
import pytest

import arenas
from reciprocity.beliefs.imaging import ImagingMap
from reciprocity.errors import SearchError
from reciprocity.models.green import cached_solver
from reciprocity.strategies.imaging_search.presets import DEFAULTS, PRESETS
from reciprocity.strategies.imaging_search.stop_rule import (MAX_STEPS, MAX_STEPS_SEVERAL, UNREACH_MASS, StopRule,
                                                             likely_out_of_reach, out_of_reach)

KEYS = ("eps", "area_tol", "extent_tol", "tail_tol", "credible_radius", "credible_mass")


@pytest.fixture(scope="module")
def solver():
    return cached_solver(arenas.load("empty").without_scenario(), 2.0)


def rule(**kw):
    return StopRule(**{**{k: DEFAULTS[k] for k in KEYS}, **kw})


def belief(solver, P):
    """A map whose P_M is `P` (one reading, so that it counts as read)."""
    im = ImagingMap(solver, 12.0, strength=850.0, combine="product")
    im.add((20.0, 20.0), 0.0)
    im._cache["P"] = np.asarray(P, dtype=float)
    return im


def blob(solver, centre, width=1.0):
    return np.exp(-np.sum((solver.nodes - centre) ** 2, axis=1) / (2 * width ** 2))


def test_a_tight_single_blob_converges(solver):
    im = belief(solver, blob(solver, (70.0, 70.0)))
    estimate, area, extent, converged = rule().judge(im)
    assert converged and area < DEFAULTS["area_tol"] and extent <= DEFAULTS["extent_tol"]
    assert np.hypot(*(estimate - 70.0)) < 1.0 and rule().converged(im)


def test_a_second_mode_keeps_the_default_going_and_not_the_paper(solver):
    """A small second mode 30 cm off: under eps (area and extent pass) but above TAIL_EPS
    and beyond the credible radius; the paper's rules do not look at it."""
    im = belief(solver, blob(solver, (70.0, 70.0)) + 0.05 * blob(solver, (100.0, 70.0)))
    assert not rule().converged(im)
    assert rule(tail_tol=np.inf, credible_radius=np.inf).converged(im)
    paper = StopRule(**{**{k: DEFAULTS[k] for k in KEYS}, **{k: v for k, v in PRESETS["paper"].items() if k in KEYS},
                        "eps": 0.1})
    assert paper.converged(im)


def test_an_empty_region_is_not_a_source(solver):
    im = belief(solver, np.full(len(solver.nodes), 0.05))
    assert not rule().judge(im)[3] and rule().judge(im)[1] == 0.0


def test_region_before_a_reading_is_everywhere(solver):
    im = ImagingMap(solver, 12.0, strength=850.0)
    assert rule().region(im).all()


def test_modes_and_their_note(solver):
    im = belief(solver, blob(solver, (40.0, 70.0), 4.0) + 0.8 * blob(solver, (100.0, 70.0), 4.0))
    modes = rule().modes(im, solver.triangles)
    assert len(modes) == 2 and modes[0][0] > modes[1][0]
    assert np.hypot(*(modes[0][1] - (40.0, 70.0))) <= solver.h
    gap = np.hypot(*(modes[0][1] - modes[1][1]))
    assert abs(gap - 60.0) <= 2 * solver.h
    assert rule().modes_note(im, solver.triangles) == f"; 2 modes, the two largest {gap:.0f} cm apart"
    assert rule().modes_note(belief(solver, blob(solver, (70.0, 70.0), 4.0)), solver.triangles) == ""


def test_the_step_cap():
    assert rule().cap(False) == MAX_STEPS and rule().cap(True) == MAX_STEPS_SEVERAL
    assert rule(max_steps=7).cap(True) == 7


def test_out_of_reach(solver):
    im = belief(solver, (solver.nodes[:, 0] > 110).astype(float))    # sources on the right
    area = np.ones(len(solver.nodes))
    nowhere = np.zeros(len(solver.nodes), dtype=bool)
    assert out_of_reach(im, rule().region(im), lambda: nowhere, nowhere, area, 12.0)[0] == \
        "no observation point is reachable"
    left = solver.nodes[:, 0] < 40
    why, notes = out_of_reach(im, rule().region(im), lambda: left, left, area, 12.0)
    assert why.startswith("the whole region of possible sources") and notes == {}
    im.add((20.0, 60.0), 0.0)
    im._cache["P"] = np.where(solver.nodes[:, 0] > 110, 1.0, 0.01)     # a little within reach
    why, notes = out_of_reach(im, np.zeros(len(solver.nodes), dtype=bool), lambda: left, left, area, 12.0)
    assert notes["mass_out_of_reach"] > 1 - UNREACH_MASS and why.startswith("the source lies out of reach")
    assert notes["reachable_area"] == left.sum() and likely_out_of_reach(im, notes)
    assert not likely_out_of_reach(im, {})


@pytest.mark.parametrize("bad, message", [
    (dict(eps=1.0), "eps must lie strictly between 0 and 1"), (dict(area_tol=0.0), "area_tol must be"),
    (dict(credible_mass=1.0), "credible_mass must"), (dict(tail_tol=0.0), "tail_tol must be a positive length"),
    (dict(max_steps=2.5), "max_steps must be a whole number")])
def test_bad_settings_name_the_key(bad, message):
    with pytest.raises(SearchError, match=message):
        rule(**bad)
