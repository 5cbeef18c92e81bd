"""Figures of hidden-Markov plume mapping (Farrell, Pang & Li 2003, Figs. 5–8) and of
searches in the filament plume.

Each map panel follows the paper's layout: the region's cells shaded in grey by the
map's value (darker = larger), a regular grid of arrows giving the flow at the time of
the map, the plume's filaments as a grey patchy trail, the corner coordinates written
in the corners, and a dashed rectangle marking the search area of interest.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from ..beliefs.hmm import HMMSourceMap, plume_map  # noqa: E402
from ..models.hmm import CellGrid, backtrack, transition, viterbi  # noqa: E402
from ..worlds.filament import FilamentParams, FilamentPlume  # noqa: E402

__all__ = ["draw_map", "farrell_figures", "plot_search"]


def draw_map(ax, grid: CellGrid, values: np.ndarray | None, *, plume: FilamentPlume | None = None,
             wind=None, cells=None, track=None, title: str = "", search_area=None) -> None:
    """One map panel in the paper's layout.

    Parameters
    ----------
    ax : matplotlib Axes
    grid : CellGrid
    values : ndarray (N,) or None
        The map (grey scale, normalised to its maximum).
    plume : FilamentPlume, optional
        Draws its filaments (grey discs, radius one puff σ).
    wind : callable or array (2,), optional
        ``wind(points) -> (n, 2)`` or a uniform flow; drawn on a 10 × 10 grid of arrows.
    cells : array of int, optional
        A cell path, drawn as dark rectangles (MLOP, MLDP).
    track : ndarray (k, 2), optional
        The vehicle's path (arrows along it).
    search_area : tuple, optional
        ``(x0, x1, y0, y1)`` of the dashed rectangle.
    """
    x0, x1, y0, y1 = grid.region
    if values is not None:
        v = np.asarray(values, dtype=float).reshape(grid.n, grid.m)
        v = v / v.max() if v.max() > 0 else v
        ax.imshow(v, origin="lower", extent=(x0, x1, y0, y1), cmap="Greys", vmin=0, vmax=1.15,
                  interpolation="nearest", aspect="equal")
    if plume is not None:
        c, age = plume.filaments
        inside = (c[:, 0] > x0) & (c[:, 0] < x1) & (c[:, 1] > y0) & (c[:, 1] < y1)
        r = np.sqrt(plume.sigma2(age[inside]))
        ax.scatter(c[inside, 0], c[inside, 1], s=(3 * r) ** 2 * 4, c="0.45", alpha=0.35, linewidths=0)
    if cells is not None:
        lx, ly = grid.L
        cen = grid.centres()[np.asarray(cells)]
        for k, p in enumerate(cen):
            shade = 0.15 + 0.6 * k / max(len(cen) - 1, 1)
            ax.add_patch(plt.Rectangle((p[0] - lx / 2, p[1] - ly / 2), lx, ly, color=str(shade), alpha=0.9))
    if wind is not None:
        gx, gy = np.meshgrid(np.linspace(x0 + 5, x1 - 5, 10), np.linspace(y0 + 5, y1 - 5, 10))
        pts = np.c_[gx.ravel(), gy.ravel()]
        u = wind(pts) if callable(wind) else np.tile(np.asarray(wind, dtype=float), (len(pts), 1))
        ax.quiver(pts[:, 0], pts[:, 1], u[:, 0], u[:, 1], angles="xy", scale_units="xy", scale=0.25,
                  width=0.003, color="0.2")
    if track is not None and len(track) > 1:
        t = np.asarray(track)
        step = max(1, len(t) // 40)
        d = np.diff(t[::step], axis=0)
        ax.quiver(t[:-1:step][:len(d), 0], t[:-1:step][:len(d), 1], d[:, 0], d[:, 1], angles="xy",
                  scale_units="xy", scale=1, width=0.005, color="k")
    if search_area is not None:
        a0, a1, b0, b1 = search_area
        ax.plot([a0, a1, a1, a0, a0], [b0, b0, b1, b1, b0], "k--", lw=0.8)
    for (x, y, ha, va) in ((x0, y0, "left", "bottom"), (x1, y0, "right", "bottom"),
                           (x0, y1, "left", "top"), (x1, y1, "right", "top")):
        ax.text(x, y, f"({x:g},{y:g})", ha=ha, va=va, fontsize=6)
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_xticks([])
    ax.set_yticks([])
    ax.set_title(title, fontsize=8)


def farrell_figures(out, *, seed: int = 3, params: FilamentParams | None = None) -> list[Path]:
    """The paper's Figs. 5–8 from one function: the plume map α(65, 0) for a source in
    the true source's cell (Fig. 5), the map β̄_k for one detection in C_k after a
    vehicle path from the top of the region (Fig. 6), and, under the uniform flow of
    eq. (18) (1 m/s along x for t ≤ 30 s, then along y), the most likely odour path
    from C_488 (paper numbering) at t = 0 to C_388 at t = 44 s (Fig. 7) and the
    25-step most likely detection path between C_388 and C_471 at t = 48 s (Fig. 8).

    `params` default to the ``farrell`` scenario's. Writes ``farrell_fig5_8.png``
    (the four panels) in `out`; returns the paths.
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    if params is None:
        from ..scenarios import load_scenario
        from ..kinds.filament import filament_params
        params = filament_params(load_scenario("farrell").params)
    p = params
    grid = CellGrid(p.region, 40, 25)
    rng = np.random.default_rng(seed)
    src = grid.from_paper(488)                           # the source's cell in the paper
    fig, axes = plt.subplots(2, 2, figsize=(10, 10))
    area = (10.0, 90.0, -40.0, 40.0)

    # Fig. 5 and 6: the simulated, time-varying flow measured along a vehicle path
    plume = FilamentPlume(p, rng)
    plume.advance_to(p.spinup)
    belief = HMMSourceMap(grid, readings=int(round(p.sampling_rate)))
    ts, track = [], []
    pos = np.array([60.0, 45.0])                          # the paper's start C_64 is near the top
    detect = None
    for second in range(65):
        winds, hit = [], False
        for _ in range(int(round(p.sampling_rate))):
            plume.step()
            pos = pos + np.array([0.0, -1.0]) / p.sampling_rate if pos[1] > -20 else pos
            track.append(pos.copy())
            winds.append(plume.wind(pos[None])[0])
            hit |= plume.concentration(pos[None])[0] > p.threshold
        u = np.mean(winds, axis=0)
        ts.append(transition(grid, u, 1.0))
        belief.advance(u, hit, pos)
        if hit and detect is None and second > 20:
            k = int(grid.index(pos)[0])
            detect = (second, k, belief.beta(k), plume_snapshot(plume))
    pi = np.eye(grid.N)[src]
    draw_map(axes[0, 0], grid, plume_map(pi, ts), plume=plume, wind=plume.wind, search_area=area,
             title=f"Fig. 5: plume map α(65, 0), source in C{grid.to_paper(src)}")
    if detect is not None:
        t_d, k_d, beta_d, snap = detect
        draw_map(axes[0, 1], grid, beta_d, plume=snap, wind=snap.wind, search_area=area,
                 track=np.array(track[:(t_d + 1) * int(round(p.sampling_rate))]),
                 title=f"Fig. 6: β̄ for a detection in C{grid.to_paper(k_d)} at t = {t_d + 1} s")
    else:
        axes[0, 1].set_title("Fig. 6: no detection on this path", fontsize=8)

    # Figs. 7 and 8: the uniform flow of eq. (18)
    uniform = FilamentPlume(FilamentParams(**{**p.__dict__, "wind_sigma": 0.0, "wind_modes": 0,
                                              "spinup": 0.0}), np.random.default_rng(seed))
    flows = [np.array([1.0, 0.0]) if t < 30 else np.array([0.0, 1.0]) for t in range(48)]
    trs = []
    for k, u in enumerate(flows):
        uniform.p = FilamentParams(**{**uniform.p.__dict__, "wind_mean": tuple(u)})
        uniform.advance_to(k + 1.0)
        trs.append(transition(grid, u, 1.0))
        if k == 43:
            snap44 = plume_snapshot(uniform)
    end7 = grid.from_paper(388)
    _, psi = viterbi(np.eye(grid.N)[src], [t.bar() for t in trs[:44]])
    mlop = backtrack(psi, end7)
    draw_map(axes[1, 0], grid, None, plume=snap44, wind=(0.0, 1.0), cells=mlop, search_area=area,
             title="Fig. 7: most likely odour path C488(0) → C388(44)")
    m8 = HMMSourceMap(grid, readings=1)
    m8.pi = np.eye(grid.N)[src]
    for t in trs:
        t.superpose(m8.psi, m8.n + 1, m8._buf)
        m8.psi, m8._buf = m8._buf, m8.psi
        m8.n += 1
    mldp = m8.mldp(grid.from_paper(388), 25, end=grid.from_paper(471))
    draw_map(axes[1, 1], grid, m8.alpha(), plume=uniform, wind=(0.0, 1.0), cells=mldp, search_area=area,
             title="Fig. 8: 25-step most likely detection path C388 → C471 (t = 48 s)")
    fig.tight_layout()
    path = out / "farrell_fig5_8.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return [path]


def plume_snapshot(plume: FilamentPlume) -> FilamentPlume:
    """A frozen copy of the plume's filaments and wind (for drawing a past instant)."""
    snap = FilamentPlume.__new__(FilamentPlume)
    snap.__dict__.update({k: (v.copy() if isinstance(v, np.ndarray) else v) for k, v in plume.__dict__.items()})
    return snap


def plot_search(episode, strategy, world, path) -> Path:
    """The vehicle's track over the final source map (``hmm``) or over the plume
    (other strategies), with the source and the estimate."""
    tr = episode.trace
    track = np.array([r["pose"][:2] for r in tr])
    hits = np.array([r["readings"][0] > 0 for r in tr])
    fig, ax = plt.subplots(figsize=(6, 6))
    grid = CellGrid(world.p.region, *world.cells)
    values = strategy.belief.weights() if hasattr(strategy, "belief") else None
    draw_map(ax, grid, values, plume=world.plume, wind=world.plume.wind,
             title=f"{episode.summary['strategy']}: {episode.summary['stop_reason']}")
    ax.plot(track[:, 0], track[:, 1], "-", color="tab:blue", lw=1)
    ax.plot(track[hits, 0], track[hits, 1], ".", color="tab:red", ms=3)
    ax.plot(*world.source, "r*", ms=12)
    if episode.summary["estimate"] is not None:
        ax.plot(*episode.summary["estimate"], "gx", ms=10, mew=2)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return Path(path)
