"""Plume strategies on hand-built beliefs (as otto's tests), shared by the plume tests."""

import numpy as np

from reciprocity.scenarios import load_scenario
from reciprocity.strategies import STRATEGIES
from reciprocity.strategies.base import SearchContext


def hand_built(name, points, weights, *, at=(9.5, 9.5), grid=True, heading=np.pi / 2, **params):
    """Strategy `name` started on ``otto-2d`` (or ``song-100``) with its particle belief
    replaced by `points` (m, 2) carrying `weights` (m,)."""
    sc = load_scenario("otto-2d" if grid else "song-100")
    nom = dict(sc.build_world(0).nominal(), initial_hit=None)
    s = STRATEGIES[name](**params)
    s.start(SearchContext("plume", nom, np.array([[at[0], at[1], heading]]), np.random.default_rng(0)))
    b = s.belief
    b.x = np.asarray(points, float)
    b.M = len(b.x)
    b.logw = np.log(np.asarray(weights, float))
    b.loglik = np.zeros(b.M)
    b._normalise()
    return s
