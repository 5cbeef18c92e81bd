"""The filament plume (Farrell et al. 2002): mass, diffusion law, puff closed form,
divergence-free wind, reproducibility, bad input."""

import time
from dataclasses import replace

import numpy as np
import pytest

from reciprocity.api import check, execute
from reciprocity.errors import SearchError
from reciprocity.scenarios import load_scenario
from reciprocity.worlds.filament import FilamentParams, FilamentPlume, puff_concentration


def _plume(seed=0, **kw):
    base = dict(wind_sigma=0.0, wind_modes=0, spinup=0.0)
    base.update(kw)
    return FilamentPlume(FilamentParams(**base), np.random.default_rng(seed))


def test_released_mass_is_conserved():
    pl = _plume(release_rate=10.0, wind_mean=(3.0, 0.0), wind_sigma=0.3, wind_modes=4)
    pl.advance_to(60.0)
    alive = int(pl.alive.sum())
    assert pl.n_released == int(np.floor(10.0 * pl.time + 1e-9))
    assert alive + pl.n_dropped == pl.n_released
    assert pl.n_dropped > 0                     # some filaments left through the far edge


def test_concentration_integrates_to_the_mass_in_the_region():
    pl = _plume(release_rate=5.0, puff_mass=2.0)
    pl.advance_to(8.0)                          # all filaments within 10 m of the source
    x, y = np.meshgrid(np.arange(15.0, 35.0, 0.05), np.arange(-6.0, 6.0, 0.05))
    c = pl.concentration(np.c_[x.ravel(), y.ravel()])
    total = c.sum() * 0.05 ** 2
    assert total == pytest.approx(2.0 * pl.alive.sum(), rel=1e-3)


def test_one_puff_matches_its_closed_form():
    pl = _plume(release_rate=0.5, puff_sigma0=0.3, puff_diffusivity=0.02, centre_diffusivity=0.0)
    pl.advance_to(3.0)                          # one filament, released at t = 2 s
    centres, ages = pl.filaments
    assert len(centres) == 1 and ages[0] == pytest.approx(1.0)
    s2 = 0.3 ** 2 + 2 * 0.02 * ages[0]
    for d in (0.0, 0.2, 0.7):
        got = pl.concentration(centres + [[0.0, d]])[0]
        assert got == pytest.approx(1.0 / (2 * np.pi * s2) * np.exp(-d * d / (2 * s2)), rel=1e-12)
    assert puff_concentration(np.array(0.0), np.array(1.0), 2 * np.pi) == pytest.approx(1.0)


def test_mean_plume_width_follows_the_diffusion_law():
    """Uniform wind: the crosswind variance of the mean plume at age τ is
    σ0² + 2 (D_puff + D_centre) τ; the centres' part is χ²₁-distributed per filament."""
    D, Dc, s0 = 0.01, 0.1, 0.2
    pl = _plume(seed=3, release_rate=10.0, puff_sigma0=s0, puff_diffusivity=D, centre_diffusivity=Dc)
    pl.advance_to(70.0)
    c, age = pl.filaments
    sel = (age > 30) & (age < 60)
    y = c[sel, 1]
    law = s0 ** 2 + 2 * (D + Dc) * age[sel]
    ratio = (y ** 2 + pl.sigma2(age[sel])) / law
    frac = (2 * Dc * age[sel] / law).mean()
    margin = 4 * np.sqrt(2.0) * frac / np.sqrt(sel.sum())
    assert abs(ratio.mean() - 1.0) < margin
    # downwind position follows the mean wind
    assert np.allclose(c[sel, 0], 20.0 + 1.0 * age[sel], atol=6 * np.sqrt(2 * Dc * 60))


def test_wind_is_divergence_free_and_smooth():
    pl = _plume(wind_sigma=0.5, wind_modes=4)
    pl.advance_to(30.0)
    p = np.array([[37.0, 12.0], [70.0, -30.0]])
    h = 1e-4
    du = (pl.wind(p + [h, 0])[:, 0] - pl.wind(p - [h, 0])[:, 0]) / (2 * h)
    dv = (pl.wind(p + [0, h])[:, 1] - pl.wind(p - [0, h])[:, 1]) / (2 * h)
    assert np.allclose(du + dv, 0.0, atol=1e-8)
    assert not np.allclose(pl.wind(p)[0], pl.wind(p)[1])      # spatially varying


def test_same_seed_same_plume_and_readings():
    sc = load_scenario("farrell")
    a, b = sc.build_world(1), sc.build_world(1)
    a.reset(np.random.default_rng(5))
    b.reset(np.random.default_rng(5))
    pts = [(30.0, 0.5), (45.0, -2.0), (60.0, 3.0)]
    ra = [a.read(np.array(p), time=0.1 * k, dwell=0.1, rng=None) for k, p in enumerate(pts)]
    rb = [b.read(np.array(p), time=0.1 * k, dwell=0.1, rng=None) for k, p in enumerate(pts)]
    assert ra == rb
    assert ra[0].kind == "detection" and len(ra[0].data["wind"]) == 2


@pytest.mark.benchmark
def test_plume_runs_100_times_faster_than_real_time():
    """100 s of plume in under 1 s of this process's CPU time (the work it does; a busy
    machine slows the wall clock, not this count), in whole steps of the sampling period."""
    sc = load_scenario("farrell")
    w = sc.build_world(0)
    w.reset(np.random.default_rng(0))
    start, t0 = w.plume.time, time.process_time()
    w.plume.advance_to(start + 100.0)
    assert time.process_time() - t0 < 1.0
    assert w.plume.time == pytest.approx(start + 100.0, abs=w.plume.dt)


@pytest.mark.parametrize("over, words", [
    ({"release_rate": 0}, "release_rate"), ({"release_rate": -2}, "release_rate"),
    ({"threshold": 0}, "threshold"), ({"sampling_rate": -1}, "sampling_rate"),
    ({"cells": [0, 25]}, "cells"), ({"cells": [40, 2.5]}, "cells"),
    ({"source": [120, 0]}, "outside the region"), ({"wind_modes": 7}, "wind_modes"),
])
def test_bad_input_is_one_line(over, words):
    with pytest.raises(SearchError) as e:
        check("farrell", "random-walk", world=over)
    assert words in str(e.value) and "\n" not in str(e.value)


def test_start_in_the_source_cell_is_refused():
    with pytest.raises(SearchError, match="source's cell"):
        execute("farrell", "random-walk", world={"start": [20.5, 1.0]}, params={"n_steps": 2})


def test_the_figure_record_is_the_truth_at_the_end_and_changes_no_episode(tmp_path):
    from reciprocity.api import run
    from reciprocity.viz.hmm import plot_search, search_map_figure
    sc = replace(load_scenario("farrell"), max_steps=30)
    plain, ep = run(sc, "hmm", seed=2), run(sc, "hmm", seed=2, figures=True)
    assert ep.summary == {**plain.summary, "wall_time_s": ep.summary["wall_time_s"]}
    truth = ep.truth
    assert truth["region"] == (0.0, 100.0, -50.0, 50.0) and truth["cells"] == (40, 25)
    assert truth["source"].tolist() == ep.summary["source"]
    assert truth["plume"]["filaments"].shape == (len(truth["plume"]["radii"]), 2)
    assert ep.belief["source_map"].shape == (40 * 25,) and np.isclose(ep.belief["source_map"].sum(), 1.0)
    assert len(search_map_figure(ep).axes) == 1
    assert plot_search(ep, tmp_path / "hmm.png").stat().st_size > 10_000
    with pytest.raises(SearchError, match="figures=True"):
        search_map_figure(plain)
