"""Reciprocity in wind for a team (``team-reciprocity-wind``): one shared belief, every
observer reading each round."""

import numpy as np

from reciprocity.api import run
from reciprocity.scenarios import from_dict
from test_flow_world import MODEL_H, SCENARIO, SEED  # the duct of the flow-world tests


def _team(**over):
    return from_dict(dict(SCENARIO, start=[[52, 8, 90], [52, 32, 270]], **over), "duct-wind")


def test_a_team_of_two_shares_one_belief_and_finds_the_source():
    a, b = (run(_team(max_steps=30), "team-reciprocity-wind", seed=SEED, agents=2, params={"h": MODEL_H})
            for _ in range(2))
    s = a.summary
    assert s["success"] and s["converged"] and s["n_agents"] == 2
    # every round both observers read: twice the rounds in readings
    assert s["n_measurements"] == 2 * s["steps"]
    assert {r["agent"] for r in a.trace} == {0, 1}
    assert s["n_measurements"] == b.summary["n_measurements"]
    assert all(np.array_equal(x["points"], y["points"]) for x, y in zip(a.trace, b.trace))


def test_a_team_round_spreads_its_observers():
    """Within a round the observers read at least `reach` apart (not the same plume twice)."""
    episode = run(_team(max_steps=8), "team-reciprocity-wind", seed=SEED, agents=2,
                  params={"h": MODEL_H, "reach": 10.0, "credible_mass": 0.999})
    points = {}
    for r in episode.trace:
        points.setdefault(r["time"], {})[r["agent"]] = np.asarray(r["points"], dtype=float).reshape(-1, 2)[-1]
    later = [p for round_, p in points.items() if round_ > 1 and len(p) == 2]
    assert later and all(np.hypot(*(p[0] - p[1])) >= 10.0 - 1e-9 for p in later)


def test_max_steps_counts_rounds():
    episode = run(_team(max_steps=3), "team-reciprocity-wind", seed=SEED, agents=2,
                  params={"h": MODEL_H, "max_steps": 3, "credible_mass": 0.999})
    s = episode.summary
    assert s["steps"] == 3 and s["n_measurements"] == 6 and "max_steps = 3 rounds" in s["stop_reason"]
