"""The maps of Farrell et al.'s Figs. 5–8 from a plume record: the source's plume map,
a detection's source map, the odour path under eq. (18)'s flow, the detection path."""

import numpy as np

from reciprocity.beliefs.farrell_maps import CELLS, farrell_maps
from reciprocity.wiring.filament import filament_params
from reciprocity.scenarios import load_scenario
from reciprocity.worlds.filament_figures import farrell_record

RECORD = farrell_record(filament_params(load_scenario("farrell").params), seed=3)


def test_the_maps_are_distributions_over_the_papers_cells():
    maps = farrell_maps(RECORD)
    grid = maps["grid"]
    assert (grid.m, grid.n) == CELLS and grid.to_paper(maps["source_cell"]) == 488
    second, cell, beta = maps["detect"]
    assert second == RECORD["detection"][0] and cell == int(grid.index(RECORD["position"][second])[0])
    for m in (maps["alpha"], beta, maps["uniform_alpha"]):
        assert m.shape == (grid.N,) and (m >= 0).all() and m.sum() > 0


def test_the_odour_path_goes_downwind_then_up_and_the_detection_path_ends_where_asked():
    maps = farrell_maps(RECORD)
    grid, mlop, mldp = maps["grid"], maps["mlop"], maps["mldp"]
    assert mlop[0] == maps["source_cell"] and mlop[-1] == grid.from_paper(388)
    i, j = grid.ij(mlop)
    assert (np.diff(i[:31]) >= 0).all() and (np.diff(j[30:]) >= 0).all()     # along x for 30 s, then along y
    assert mldp[0] == grid.from_paper(388) and mldp[-1] == grid.from_paper(471)


def test_a_record_without_a_detection_has_no_detection_map():
    maps = farrell_maps({**RECORD, "detection": None})
    assert maps["detect"] is None and np.array_equal(maps["alpha"], farrell_maps(RECORD)["alpha"])
