"""The plume runs Farrell, Pang & Li (2003) draw their Figs. 5–8 from (truth): a vehicle
measuring a time-varying filament plume, and a plume under the uniform flow of eq. (18).

:func:`farrell_record` simulates them and returns arrays only: what the vehicle measured
(its track, the flow it read each second, its detections) and snapshots of the plume for
drawing. The maps themselves are the belief's side's
(:func:`reciprocity.beliefs.farrell_maps.farrell_maps`), the drawing
:func:`reciprocity.viz.hmm.farrell_figures`'s.
"""

from __future__ import annotations

import numpy as np

from .filament import FilamentParams, FilamentPlume

__all__ = ["VEHICLE_SECONDS", "UNIFORM_SECONDS", "farrell_record", "uniform_flow"]

#: Seconds the vehicle measures the time-varying plume (Figs. 5 and 6).
VEHICLE_SECONDS = 65
#: Seconds of the uniform flow of eq. (18) (Figs. 7 and 8).
UNIFORM_SECONDS = 48
#: The vehicle's start (m): the paper's start C_64 is near the top of the region.
START = (60.0, 45.0)
#: The vehicle drives down (−y) at 1 m/s and stops at this y (m).
STOP_Y = -20.0
#: A detection is recorded for Fig. 6 only after this many whole seconds.
DETECT_AFTER = 20


def uniform_flow(t: int) -> np.ndarray:
    """The flow of eq. (18) during second `t` (m/s): 1 m/s along x for t < 30 s, then along y."""
    return np.array([1.0, 0.0]) if t < 30 else np.array([0.0, 1.0])


def farrell_record(params: FilamentParams, seed: int = 3) -> dict:
    """Simulate the plumes of the paper's Figs. 5–8.

    A vehicle starts at :data:`START` in a plume of `params` spun up for ``spinup`` s and
    drives down at 1 m/s for :data:`VEHICLE_SECONDS` s, reading the flow and the detector
    ``sampling_rate`` times a second; then a second plume, without meander, is blown by
    the uniform flow of eq. (18) (:func:`uniform_flow`) from t = 0 for
    :data:`UNIFORM_SECONDS` s.

    Parameters
    ----------
    params : FilamentParams
        The plume (e.g. the ``farrell`` scenario's).
    seed : int
        Seeds both plumes' random streams.

    Returns
    -------
    dict
        ``region`` (m) and ``readings`` (per second); ``track`` (the vehicle's positions
        after each reading, (k, 2), m); per second ``flow`` (the mean flow read, (S, 2),
        m/s), ``hit`` (any detection, (S,)) and ``position`` (at the second's end, (S, 2),
        m); ``detection`` (``(second, plume snapshot)`` at the first detecting second after
        :data:`DETECT_AFTER`, or None); ``plume`` (the snapshot at the end);
        ``uniform_flow`` ((48, 2), m/s) and ``uniform`` (snapshots at 44 s and 48 s, by
        second). A snapshot is :meth:`FilamentPlume.snapshot`'s.
    """
    p = params
    readings = int(round(p.sampling_rate))
    plume = FilamentPlume(p, np.random.default_rng(seed))
    plume.advance_to(p.spinup)
    pos = np.array(START)
    track, flow, hit, position, detection = [], [], [], [], None
    for second in range(VEHICLE_SECONDS):
        winds, detected = [], False
        for _ in range(readings):
            plume.step()
            pos = pos + np.array([0.0, -1.0]) / p.sampling_rate if pos[1] > STOP_Y else pos
            track.append(pos.copy())
            winds.append(plume.wind(pos[None])[0])
            detected |= plume.concentration(pos[None])[0] > p.threshold
        flow.append(np.mean(winds, axis=0))
        hit.append(bool(detected))
        position.append(pos.copy())
        if detected and detection is None and second > DETECT_AFTER:
            detection = (second, plume.snapshot())
    out = dict(region=tuple(p.region), readings=readings, track=np.array(track), flow=np.array(flow),
               hit=np.array(hit), position=np.array(position), detection=detection, plume=plume.snapshot())
    return {**out, **_uniform(p, seed)}


def _uniform(p: FilamentParams, seed: int) -> dict:
    """The plume without meander under the flow of eq. (18): the flow and snapshots at 44 s and 48 s."""
    still = {**p.__dict__, "wind_sigma": 0.0, "wind_modes": 0, "spinup": 0.0}
    plume = FilamentPlume(FilamentParams(**still), np.random.default_rng(seed))
    flows, snaps = [], {}
    for k in range(UNIFORM_SECONDS):
        u = uniform_flow(k)
        plume.p = FilamentParams(**{**plume.p.__dict__, "wind_mean": tuple(u)})
        plume.advance_to(k + 1.0)
        flows.append(u)
        if k + 1 in (44, UNIFORM_SECONDS):
            snaps[k + 1] = plume.snapshot()
    return dict(uniform_flow=np.array(flows), uniform=snaps)
