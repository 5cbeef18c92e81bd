"""The plumes of Farrell et al.'s Figs. 5–8, simulated on the truth's side: what the
vehicle measured, the plume snapshots, the uniform flow of eq. (18), reproducibility."""

import numpy as np

from reciprocity.wiring.filament import filament_params
from reciprocity.scenarios import load_scenario
from reciprocity.worlds.filament import ARROWS
from reciprocity.worlds.filament_figures import (DETECT_AFTER, UNIFORM_SECONDS, VEHICLE_SECONDS, farrell_record,
                                                 uniform_flow)

PARAMS = filament_params(load_scenario("farrell").params)


def test_the_record_holds_what_the_vehicle_measured_each_second():
    rec = farrell_record(PARAMS, seed=3)
    n = rec["readings"]
    assert n == 10 and rec["region"] == PARAMS.region
    assert rec["track"].shape == (VEHICLE_SECONDS * n, 2)
    assert rec["flow"].shape == rec["position"].shape == (VEHICLE_SECONDS, 2) and rec["hit"].shape == (VEHICLE_SECONDS,)
    assert np.array_equal(rec["position"], rec["track"][n - 1::n])          # where each second ended
    assert np.allclose(rec["track"][:, 0], 60.0) and rec["track"][:, 1].min() >= -20.0 - 0.1
    second, snap = rec["detection"]                                         # the first detection after 20 s
    assert second > DETECT_AFTER and rec["hit"][second] and not rec["hit"][DETECT_AFTER + 1:second].any()
    for s in (snap, rec["plume"]):
        assert s["filaments"].shape == (len(s["radii"]), 2) and (s["radii"] >= PARAMS.puff_sigma0).all()
        assert s["wind"][0].shape == s["wind"][1].shape == (ARROWS ** 2, 2)


def test_the_uniform_flow_blows_along_x_then_along_y():
    rec = farrell_record(PARAMS, seed=3)
    assert rec["uniform_flow"].shape == (UNIFORM_SECONDS, 2)
    assert rec["uniform_flow"].tolist() == [uniform_flow(t).tolist() for t in range(UNIFORM_SECONDS)]
    assert sorted(rec["uniform"]) == [44, UNIFORM_SECONDS]
    for snap in rec["uniform"].values():                        # no meander: the wind is the flow itself
        assert np.array_equal(snap["wind"][1], np.tile([0.0, 1.0], (ARROWS ** 2, 1)))


def test_the_same_seed_gives_the_same_plumes():
    a, b, c = farrell_record(PARAMS, seed=3), farrell_record(PARAMS, seed=3), farrell_record(PARAMS, seed=4)
    assert np.array_equal(a["plume"]["filaments"], b["plume"]["filaments"])
    assert np.array_equal(a["flow"], b["flow"]) and not np.array_equal(a["flow"], c["flow"])
