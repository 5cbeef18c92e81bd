"""The quantities of Farrell et al.'s Figs. 5–8 measured on our maps, against what the
paper's Sect. V and captions state: the cells it names, the odour path's ends and turn,
the detection path's ends, the maps' maxima and spreads in the frame of the flow."""

from math import comb

import numpy as np
import pytest

from reciprocity.beliefs.farrell_maps import CELLS, farrell_maps
from reciprocity.beliefs.farrell_measures import (farrell_measures, map_shape, odour_distribution, paper_ij,
                                                  path_summary)
from reciprocity.models.hmm import CellGrid
from reciprocity.scenarios import load_scenario
from reciprocity.wiring.filament import filament_params
from reciprocity.worlds.filament_figures import farrell_record, uniform_flow

GRID = CellGrid((0.0, 100.0, -50.0, 50.0), *CELLS)


@pytest.fixture(scope="module")
def measured():
    record = farrell_record(filament_params(load_scenario("farrell").params), seed=3)
    maps = farrell_maps(record)
    return record, maps, farrell_measures(record, maps)


def test_the_papers_cell_numbers_are_its_columns_and_rows_from_the_top():
    # Sect. V: C488 is i = 8, j = 13 and holds (20, 0); C64 is i = 24, j = 2, at the top edge
    assert paper_ij(488, GRID) == (8, 13) and paper_ij(64, GRID) == (24, 2)
    assert [paper_ij(k, GRID) for k in (388, 471, 619)] == [(28, 10), (31, 12), (19, 16)]
    assert all(i + (j - 1) * GRID.m == k for k in range(1, GRID.N + 1) for i, j in [paper_ij(k, GRID)])
    centres = GRID.centres()
    assert np.allclose(centres[GRID.from_paper(488)], (18.75, 0.0))       # x 17.5-20 m, y -2-2 m
    assert np.allclose(centres[GRID.from_paper(64)], (58.75, 44.0))       # y 42-46 m: the top edge


def test_map_shape_measures_along_and_across_the_flow():
    a, b = GRID.from_paper(488), GRID.from_paper(490)                      # 5 m apart along x
    values = np.zeros(GRID.N)
    values[a], values[b] = 2.0, 1.0
    s = map_shape(values, GRID, a, (3.0, 0.0))
    assert (s.peak, s.peak_offset, s.runner_up, s.runner_up_offset) == (488, (0.0, 0.0), 490, (5.0, 0.0))
    assert s.mean == pytest.approx((5 / 3, 0.0)) and s.sd == pytest.approx((np.sqrt(50) / 3, 0.0))
    assert s.extent90 == pytest.approx((5.0, 0.0)) and s.extent50 == pytest.approx((5.0, 0.0))
    assert s.band_mass == pytest.approx((1.0, 0.0, 0.0)) and s.band_sd_across[0] == pytest.approx(0.0)
    turned = map_shape(values, GRID, a, (0.0, -1.0), sense=-1)            # flow -y: x is to its left
    assert turned.sd == pytest.approx((0.0, np.sqrt(50) / 3)) and turned.runner_up_offset == pytest.approx((0, 5))


def test_path_summary_counts_moves_and_length():
    cells = [GRID.from_paper(k) for k in (488, 488, 489, 449, 449)]       # stay, +x, then up a row
    p = path_summary(cells, GRID)
    assert (p.start, p.end, p.steps, p.distinct, p.x_moves, p.y_moves) == (488, 449, 4, 3, (2,), (3,))
    assert p.length == pytest.approx(2.5 + 4.0)


def test_fig7_the_odour_path_runs_from_c488_at_0_s_to_c388_at_44_s_along_x_then_y(measured):
    mlop = measured[2]["fig7"]
    assert (mlop.start, mlop.end, mlop.steps) == (488, 388, 44)
    # eq. (18): 20 columns along x, all by 30 s, then 3 rows up (+y lowers the paper's j)
    assert len(mlop.x_moves) == 20 and max(mlop.x_moves) <= 30
    assert len(mlop.y_moves) == 3 and min(mlop.y_moves) > 30
    assert [paper_ij(c, GRID)[1] for c in mlop.cells[:31]] == [13] * 31
    assert {paper_ij(c, GRID)[0] for c in mlop.cells[30:]} == {28}
    assert mlop.distinct == 24 and mlop.length == pytest.approx(20 * 2.5 + 3 * 4.0)


def test_fig7_the_end_is_reached_with_the_binomial_probability_and_only_if_rows_count_down(measured):
    prob, rank, mode = measured[2]["fig7_arrival"]
    along = comb(30, 20) * 0.4 ** 20 * 0.6 ** 10                          # ε_x = 1 m/s · 1 s / 2.5 m
    up = comb(14, 3) * 0.25 ** 3 * 0.75 ** 11                             # ε_y = 1 m/s · 1 s / 4 m
    assert prob == pytest.approx(along * up, rel=1e-9)
    assert mode == 380 and paper_ij(mode, GRID) == (20, 10) and rank > 1   # the modes, 12 columns and 3 rows
    reach = odour_distribution(GRID, [uniform_flow(t) for t in range(44)], GRID.from_paper(488))
    assert reach[27 + 9 * GRID.m] == 0.0                                   # (28, 10) counted from the bottom


def test_fig8_the_detection_path_joins_c388_to_c471_in_25_steps_apart_from_the_odour_path(measured):
    m = measured[2]
    assert (m["fig8"].start, m["fig8"].end, m["fig8"].steps) == (388, 471, 25)
    assert m["fig8_shared"] == (388,)
    assert (m["fig8_text"].start, m["fig8_text"].end, m["fig8_text"].steps) == (388, 488, 25)
    assert m["fig8_free"].end == 488                                       # the best end is the source's cell


def test_fig5_the_plume_map_peaks_at_the_source_and_is_narrower_across_than_along(measured):
    s = measured[2]["fig5"]
    assert s.peak == 488 and s.runner_up == 489                            # then the downflow neighbour
    assert s.runner_up_offset[0] > 2.0 and abs(s.runner_up_offset[1]) < 1.0
    assert s.mean[0] > 20.0 and s.sd[1] < 0.5 * s.sd[0] and s.extent90[1] < 0.5 * s.extent90[0]
    assert s.band_sd_across[0] < s.band_sd_across[1] < s.band_sd_across[2]  # widens downflow


def test_fig6_the_detection_map_lies_upflow_of_the_vehicle_and_is_narrower_across(measured):
    record, maps, m = measured
    t, cell, s = m["fig6"]
    assert t == record["detection"][0] + 1 and cell == GRID.to_paper(maps["detect"][1])
    assert s.peak == cell and s.runner_up_offset[0] < -2.0 and abs(s.runner_up_offset[1]) < 2.0
    assert s.mean[0] < -15.0                                               # its mass lies upflow
    assert s.sd[1] < 0.5 * s.sd[0] and s.extent90[1] < 0.5 * s.extent90[0]
    assert s.band_sd_across[0] < s.band_sd_across[1] < s.band_sd_across[2]  # widens upflow


def test_a_record_without_a_detection_has_no_fig6(measured):
    record, maps, _ = measured
    assert farrell_measures(record, {**maps, "detect": None})["fig6"] is None
