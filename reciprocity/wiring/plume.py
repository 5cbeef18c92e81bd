"""The ``plume`` world kind of scenario files: parameters, world, the walker platform.

Parameters (all optional except ``bounds`` and ``source``)::

    bounds: [x0, x1, y0, y1]      # search area (length unit)
    source: [x, y]                # or "drawn": otto's protocol (below)
    sources: [[x, y], ...]        # or several true sources, instead of source (below)
    strengths: [R1, R2, ...]      # their release rates (per unit time; default: each rate)
    max_sources: 4                # the task's public bound on the number of sources
    rate: 2                       # release rate R (per unit time)
    a: 1                          # sensor radius
    D: 1                          # diffusivity
    tau: 400                      # patch lifetime
    V: 0.5                        # wind speed (>= 0)
    wind_direction: 0             # degrees the wind blows toward (form "wind")
    form: wind                    # wind | isotropic (see reciprocity.worlds.plume)
    dt: 1                         # time step: hits per step are Poisson(R(r|r0) dt)
    found_radius: 3               # the search ends when an observer is this close
    motion: turn                  # turn | grid | reach
    step: 1                       # distance per step (turn, reach) or cell size (grid)
    max_turn: 3                   # turn: largest heading change per step, degrees
    n_turns: 7                    # turn: number of evenly spaced heading changes
    moves: 4                      # grid: 4 or 8 neighbours
    max_hits: null                # hit counts >= max_hits are one outcome (otto); "auto"
    initial_hit: random           # drawn source: the forced first hit (>= 1), or a count
    mismatch: {rate_factor: 1.5}  # truth differs from the nominal model
    sensors: [{}, {gain: 0}]      # observer k's sensor fault (truth; no strategy is told):
                                  # gain, false_rate (hits per unit time), fails_at (time)
    sensor: directional           # isotropic (default) | directional: eq. (14) of
    sense: toward                 # papers/001, read "toward" (its words) or "printed"

``source: drawn`` is otto's protocol (Loisy & Eloy 2022): the observer starts at the
centre cell of the grid after a forced first hit ``h0 >= 1`` (drawn as otto draws it,
over an unbounded plane, unless ``initial_hit`` is a count); the source is then drawn
from the posterior of a uniform prior over the other cells given that hit, so that the
strategy's Bayesian belief is exact. The strategy is told ``h0`` (never the source).

``sources`` (1 to MAX_SOURCES distinct points in the area) places several sources that
release independently: the hit rate is the sum of their rates. ``strengths`` are those
release rates themselves, in the unit of ``rate`` (which stays the nominal rate the
strategy is told, as a poisson world's ``strength``); the mismatch's ``rate_factor``
scales each. ``max_sources`` (default 1 with ``source``, MAX_SOURCES with ``sources``)
is the bound a strategy is told; it never learns the sources, their number or strengths.
"""

from __future__ import annotations

import numpy as np
from scipy.special import k0

from ..errors import SearchError
from ..scenarios import WorldKind, check_keys, register_world
from ..validation import MAX_AGENTS, MAX_CELLS, MAX_COORD, Bound, point, starts_in_box, whole
from ..models.directional import SENSES
from ..worlds.plume import FORMS, PlumeMismatch, PlumeParams, PlumeWorld, SensorFault, plume_length
from .sources import source_list, source_strengths

__all__ = ["PLUME", "PLUME_KEYS", "hit_probabilities", "otto_max_hits", "otto_initial_hit_probabilities"]

#: Parameters of a ``plume`` scenario.
PLUME_KEYS = ("bounds", "source", "rate", "a", "D", "tau", "V", "wind_direction", "form", "dt",
              "found_radius", "motion", "step", "max_turn", "n_turns", "moves", "max_hits",
              "initial_hit", "mismatch", "sensors", "sources", "strengths", "max_sources", "sensor", "sense")
MOTIONS = ("turn", "grid", "reach")
#: Sensors of a plume world: without direction, or eq. (14) of papers/001.
SENSORS = ("isotropic", "directional")


def hit_probabilities(mu: np.ndarray, max_hits: int | None, kmax: int) -> np.ndarray:
    """``P(h | mu)`` for ``h = 0..K``, shape (K+1, *mu.shape): Poisson, with counts
    ``>= max_hits`` lumped into the last outcome when `max_hits` is given (otto's
    ``Nhits - 1``), else cut at ``kmax``."""
    mu = np.asarray(mu, dtype=float)
    top = kmax if max_hits is None else max_hits
    k = np.arange(top + 1).reshape((-1,) + (1,) * mu.ndim)
    from scipy.stats import poisson      # here: scipy.stats costs 0.4 s that listing scenarios never needs
    p = poisson.pmf(k, mu[None])
    if max_hits is not None:
        p[-1] = np.maximum(0.0, 1.0 - p[:-1].sum(axis=0))
    return p


def otto_max_hits(p: PlumeParams, spacing: float, dt: float) -> int:
    """otto's automatic hit cap: ``ceil(μ(Δx) + sqrt(μ(Δx)))`` (its ``Nhits - 1``)."""
    mu = p.rate * dt * k0(spacing / p.length) / np.log(p.length / p.a)
    return int(np.ceil(mu + np.sqrt(mu)))


def otto_initial_hit_probabilities(p: PlumeParams, spacing: float, dt: float, max_hits: int) -> np.ndarray:
    """otto's law of the forced first hit ``h >= 1`` (index h), summed over distance shells
    of an unbounded plane (``r = 1 .. 1000 λ/Δx`` cells, shell area ``2πr``)."""
    r = np.arange(1, int(1000 * p.length / spacing)) * spacing
    mu = p.rate * dt * k0(r / p.length) / np.log(p.length / p.a)
    ph = hit_probabilities(mu, max_hits, max_hits) * (2 * np.pi * r)
    out = ph.sum(axis=1)
    out[0] = 0.0
    return out / out.sum()


#: Bounds of the numeric parameters (the world's length and time units): within them the
#: expected hits per step stay countable and one episode within memory.
BOUNDS = {
    "rate": Bound(1e-9, 1e6), "a": Bound(1e-6, 1e4), "D": Bound(1e-9, 1e6), "tau": Bound(1e-6, 1e6),
    "dt": Bound(1e-6, 1e4), "found_radius": Bound(1e-6, MAX_COORD), "step": Bound(1e-6, MAX_COORD),
    "V": Bound(0, 1e4), "wind_direction": Bound(-360, 360, unit="degrees"),
    "max_turn": Bound(1e-6, 180, unit="degrees"),
}
#: Most expected hits per step at the sensor radius (Poisson sampling needs a finite mean).
MAX_HITS_PER_STEP = 1e6


def _check(params: dict) -> dict:
    check_keys(params, PLUME_KEYS, "plume world parameter")
    out = dict(params)
    b = params.get("bounds")
    if isinstance(b, (list, tuple)) and len(b) == 2 and all(isinstance(v, (list, tuple)) for v in b):
        b = [*b[0], *b[1]]                    # ((x0, x1), (y0, y1)), as validated before
    r = point(b, "plume bounds", size=4) if isinstance(b, (list, tuple)) else None
    if r is None or not (r[1] > r[0] and r[3] > r[2]):
        raise SearchError(f"plume bounds must be [x0, x1, y0, y1], numbers within ±{MAX_COORD:g} with x1 > x0 "
                          f"and y1 > y0; got {b!r}")
    x0, x1, y0, y1 = (float(v) for v in r)
    out["bounds"] = ((x0, x1), (y0, y1))
    defaults = dict(rate=1.0, a=1.0, D=1.0, tau=400.0, dt=1.0, found_radius=1.0, step=1.0, V=0.0,
                    wind_direction=270.0, max_turn=3.0)
    for key, bound in BOUNDS.items():
        out[key] = float(bound.check(params.get(key, defaults[key]), f"plume {key}"))
    if out["rate"] * out["dt"] > MAX_HITS_PER_STEP:
        raise SearchError(f"plume rate × dt must be at most {MAX_HITS_PER_STEP:g} expected releases per step; "
                          f"got {out['rate'] * out['dt']:g}")
    cells = ((x1 - x0) / out["step"] + 1) * ((y1 - y0) / out["step"] + 1)
    if params.get("motion", "turn") == "grid" and cells > MAX_CELLS:
        raise SearchError(f"plume grid of {cells:.3g} cells (bounds / step) is larger than {MAX_CELLS}; "
                          "raise step or shrink bounds")
    form = params.get("form", "wind")
    if form not in FORMS:
        raise SearchError(f"plume form must be one of {', '.join(FORMS)}; got {form!r}")
    lam = plume_length(out["D"], out["tau"], out["V"])
    if lam <= out["a"]:
        raise SearchError(f"the plume length λ = {lam:.3g} must exceed the sensor radius a = {out['a']:g}; "
                          "raise D or tau, or lower V or a")
    motion = params.get("motion", "turn")
    if motion not in MOTIONS:
        raise SearchError(f"plume motion must be one of {', '.join(MOTIONS)}; got {motion!r}")
    out["n_turns"] = whole(params.get("n_turns", 7), "plume n_turns", 1, 360)
    moves = params.get("moves", 4)
    if moves not in (4, 8):
        raise SearchError(f"plume moves must be 4 or 8; got {moves!r}")
    sensor = params.get("sensor", "isotropic")
    if sensor not in SENSORS:
        raise SearchError(f"plume sensor must be one of {', '.join(SENSORS)}; got {sensor!r}")
    if params.get("sense") is not None and sensor != "directional":
        raise SearchError("plume sense applies only with sensor: directional")
    if sensor == "directional":                 # keys added only then: other worlds stay as they were
        out["sense"] = params.get("sense") or "toward"
        if out["sense"] not in SENSES:
            raise SearchError(f"plume sense must be one of {', '.join(SENSES)}; got {out['sense']!r}")
    sources = _sources(params, out["bounds"])
    src = params.get("source") if sources is None else sources[0]
    if src == "drawn":
        if motion != "grid":
            raise SearchError("source: drawn (otto's protocol) needs motion: grid")
        h0 = params.get("initial_hit", "random")
        if h0 != "random" and (isinstance(h0, bool) or not isinstance(h0, int) or not 1 <= h0 <= 1000):
            raise SearchError(f"plume initial_hit must be 'random' or a count from 1 to 1000; got {h0!r}")
    else:
        if not isinstance(src, (list, tuple)):
            raise SearchError(f"plume source must be [x, y] or 'drawn'; got {src!r}")
        s = point(src, "plume source")
        if not (x0 <= s[0] <= x1 and y0 <= s[1] <= y1):
            raise SearchError(f"plume source {src!r} is outside the area [{x0:g}, {x1:g}] x [{y0:g}, {y1:g}]")
        out["source"] = s.tolist()
        if "initial_hit" in params:
            raise SearchError("plume initial_hit applies only with source: drawn")
    out.update(_several(params, sources, out))
    mh = params.get("max_hits")
    if mh not in (None, "auto") and (isinstance(mh, bool) or not isinstance(mh, int) or not 1 <= mh <= 1000):
        raise SearchError(f"plume max_hits must be null, 'auto' or a count from 1 to 1000; got {mh!r}")
    m = params.get("mismatch") or {}
    if isinstance(m, PlumeMismatch):
        m = m.as_dict()
    if not isinstance(m, dict):
        raise SearchError(f"plume mismatch must be a mapping of options; got {m!r}")
    out["mismatch"] = PlumeMismatch.from_dict(m)
    sensors = params.get("sensors") or []
    if not isinstance(sensors, (list, tuple)) or len(sensors) > MAX_AGENTS:
        raise SearchError(f"plume sensors must be a list with one mapping per observer (at most {MAX_AGENTS}); "
                          f"got {sensors!r}")
    out["sensors"] = tuple(f if isinstance(f, SensorFault) else SensorFault.from_dict(f, f"plume sensors[{k}]")
                           for k, f in enumerate(sensors))
    return out


def _sources(params: dict, bounds: tuple) -> list | None:
    """The ``sources`` key as a list of distinct points in `bounds`, or None."""
    (x0, x1), (y0, y1) = bounds

    def place(value, key: str) -> np.ndarray:
        q = point(value, key)
        if not (x0 <= q[0] <= x1 and y0 <= q[1] <= y1):
            raise SearchError(f"{key} {value!r} is outside the area [{x0:g}, {x1:g}] x [{y0:g}, {y1:g}]")
        return q

    pts = source_list(params, place, prefix="plume ", single="rate")
    return None if pts is None else [q.tolist() for q in pts]


def _several(params: dict, sources: list | None, out: dict) -> dict:
    """``sources``, ``strengths`` (release rates, per unit time) and ``max_sources``,
    checked against the nominal rate and time step in `out`."""
    checked = source_strengths(params, sources, out["rate"], lambda c, key: float(BOUNDS["rate"].check(c, key)),
                               prefix="plume ", each="release rate")
    strengths = checked["strengths"]
    if strengths is not None and sum(strengths) * out["dt"] > MAX_HITS_PER_STEP:
        raise SearchError(f"plume strengths {strengths!r} × dt must sum to at most {MAX_HITS_PER_STEP:g} expected "
                          f"releases per step; got {sum(strengths) * out['dt']:g}")
    return checked


def _params(params: dict) -> PlumeParams:
    return PlumeParams(params["rate"], params["a"], params["D"], params["tau"], params["V"],
                       params["wind_direction"], params.get("form", "wind"))


def _grid_space(params: dict):
    from ..spaces import GridSpace
    return GridSpace(params["bounds"], params["step"], connectivity=params.get("moves", 4))


def _build(params: dict, rng: np.random.Generator) -> PlumeWorld:
    p = _params(params)
    motion = params.get("motion", "turn")
    grid = params["step"] if motion == "grid" else None
    max_hits = params.get("max_hits")
    if max_hits == "auto":
        max_hits = otto_max_hits(p, params["step"], params["dt"])
    n_turns = params.get("n_turns", 7)
    # the one conversion of the turns: written in degrees, used in radians (the heading changes
    # a walker may choose, in the order strategies try them)
    turns = np.radians(np.linspace(-params["max_turn"], params["max_turn"], n_turns))
    extra = dict(motion=motion, step=params["step"], dt=params["dt"], max_turn=params["max_turn"],
                 n_turns=n_turns, turns=tuple(float(t) for t in turns), moves=params.get("moves", 4), max_hits=max_hits,
                 initial_hit=None)
    if params.get("sense") is not None:
        extra["sense"] = params["sense"]           # the directional sensor: public, as the model
    if motion == "grid":
        extra["space"] = _grid_space(params)       # the places and moves (otto's grid)
    else:
        extra["max_step"] = params["step"]         # longest move in the plane
    source = params["source"]
    if source == "drawn":
        space = _grid_space(params)
        (x0, x1), (y0, y1) = params["bounds"]
        centre = space.points[space.nearest([(x0 + x1) / 2, (y0 + y1) / 2])]
        cap = max_hits if max_hits is not None else otto_max_hits(p, params["step"], params["dt"])
        h0 = params.get("initial_hit", "random")
        if h0 == "random":
            h0 = int(rng.choice(cap + 1, p=otto_initial_hit_probabilities(p, params["step"], params["dt"], cap)))
        mu = (p.rate * params["dt"] * k0(np.maximum(np.hypot(*(space.points - centre).T), p.a) / p.length)
              / np.log(p.length / p.a))
        prior = hit_probabilities(mu, cap, cap)[min(h0, cap)]
        prior[np.hypot(*(space.points - centre).T) < 1e-9] = 0.0
        source = space.points[rng.choice(len(prior), p=prior / prior.sum())]
        extra["initial_hit"] = int(h0)
        extra["first_hit_at"] = centre.tolist()
    return PlumeWorld(params["bounds"], source, p, mismatch=params["mismatch"],
                      found_radius=params["found_radius"], grid=grid, nominal_extra=extra,
                      sensors=params.get("sensors", ()), sources=params.get("sources"),
                      strengths=params.get("strengths"), max_sources=params.get("max_sources"),
                      sense=params.get("sense"))


def _default_start(world: PlumeWorld, rng: np.random.Generator) -> np.ndarray:
    if "first_hit_at" in world._extra:
        x, y = world._extra["first_hit_at"]
        return np.array([x, y, 0.0])
    (x0, x1), (y0, y1) = world.bounds
    return np.array([x1 - 0.1 * (x1 - x0), y0 + 0.1 * (y1 - y0), np.pi / 2])


def _walker(world: PlumeWorld, scenario, options: dict):
    from ..platforms.walker import WalkerPlatform
    unknown = set(options) - {"slip"}
    if unknown:
        raise SearchError(f"unknown walker option(s) {', '.join(sorted(unknown))}; choose from slip")
    starts = scenario.starts
    if starts is not None:
        d = np.hypot(*(np.asarray(starts)[:, None, :2] - world.sources[None]).transpose(2, 0, 1))
        if np.any(d <= world.found_radius):
            on = world.sources[np.argwhere(d <= world.found_radius)[0, 1]]
            raise SearchError(f"a start is on the source ({on[0]:g}, {on[1]:g}) (within found_radius "
                              f"{world.found_radius:g}); start farther away")
        if "first_hit_at" in world._extra and np.any(np.hypot(*(starts[:, :2] - world._extra["first_hit_at"]).T) > 1e-6):
            raise SearchError("source: drawn needs the start at the centre cell "
                              f"{world._extra['first_hit_at']} (otto's protocol)")
    slip = float(options.get("slip", 0.0))
    nom = world.nominal()
    if nom["motion"] == "grid":
        return WalkerPlatform(_grid_space(dict(bounds=world.bounds, step=nom["step"], moves=nom["moves"])),
                              slip=slip, dt=nom["dt"])
    reach = nom["step"] * (np.sqrt(2.0) if nom["motion"] == "reach" else 1.0)
    return WalkerPlatform(None, slip=slip, max_step=reach * (1 + 1e-9), dt=nom["dt"])


def _check_start(params: dict, starts: np.ndarray) -> None:
    (x0, x1), (y0, y1) = params["bounds"]
    starts_in_box(starts, (x0, x1, y0, y1), "plume bounds")


def _check_observers(params: dict, n: int) -> None:
    """A sensor fault must belong to an observer of the run: a faulty entry beyond the
    `n` observers would leave the world matched while the summary said otherwise."""
    idle = [k for k, f in enumerate(params.get("sensors", ())) if k >= n and not f.healthy]
    if idle:
        raise SearchError(f"plume sensors[{idle[0]}] is a fault of observer {idle[0] + 1}, but the run has "
                          f"{n} observer(s); run with at least {idle[-1] + 1} agents or drop the entry")


PLUME = register_world(WorldKind("plume", _check, _build, {"walker": _walker}, _default_start, _check_start,
                                 _check_observers))
