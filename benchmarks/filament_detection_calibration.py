"""The measurement behind :class:`reciprocity.models.detection.DetectionModel`'s defaults.

Runs the ``farrell`` scenario's filament plume (source (20, 0), threshold 0.3, 10 Hz)
for 2 plumes × 300 s, reads the detector at fixed points 3 m upwind to 50 m downwind and
0–20 m crosswind of the source, and prints the fraction of 1-s periods with at least one
detection, the fraction of single readings that detect (their ratio shows how correlated
the ten readings of a second are), the spread of the wind direction at one point, and
the model's least-squares fit to the per-period fractions.

    PYTHONPATH=. nice python benchmarks/filament_detection_calibration.py   # ~30 s CPU
"""

import numpy as np
from scipy.optimize import least_squares

from reciprocity.worlds.filament import FilamentParams, FilamentPlume

p = FilamentParams(threshold=0.3, source=(20.0, 0.0))
ds = np.array([-3, -1, 0, 1, 2, 4, 7, 10, 15, 20, 25, 30, 40, 50])
cs = np.array([0, 1, 2, 3, 5, 7, 10, 15, 20])
D, C = np.meshgrid(ds, cs, indexing="ij")
pts = np.r_[np.c_[20 + D.ravel(), C.ravel()], np.c_[20 + D.ravel(), -C.ravel()]]
per_period, per_reading, n_periods, n_readings, winds = np.zeros(len(pts)), np.zeros(len(pts)), 0, 0, []
for seed in range(2):
    plume = FilamentPlume(p, np.random.default_rng(seed))
    plume.advance_to(120)
    for _ in range(300):
        hit = np.zeros(len(pts), bool)
        for _ in range(10):
            plume.step()
            det = plume.concentration(pts) > p.threshold
            hit |= det
            per_reading += det
            n_readings += 1
        per_period += hit
        n_periods += 1
        winds.append(plume.wind(np.array([[50.0, 0.0]]))[0])
n = D.size
P = ((per_period[:n] + per_period[n:]) / (2 * n_periods)).reshape(D.shape)
R = ((per_reading[:n] + per_reading[n:]) / (2 * n_readings)).reshape(D.shape)
w = np.array(winds)
print("wind direction spread at (50, 0):", round(float(np.arctan2(w[:, 1], w[:, 0]).std()), 3), "rad")
ok = P > 0.05
print("per-reading / per-period detection fraction where > 0.05: median",
      round(float(np.median(R[ok] / P[ok])), 3), "range", np.round(np.percentile(R[ok] / P[ok], [10, 90]), 3))


def model(th, d, c):
    s0, s, A, b, pmax, ell = th
    sig = np.sqrt(s0 ** 2 + (s * np.maximum(d, 0)) ** 2)
    peak = np.minimum(pmax, A * sig ** (-b)) * np.where(d < 0, np.exp(d / ell), 1)
    return peak * np.exp(-0.5 * c ** 2 / sig ** 2)


fit = least_squares(lambda th: (model(th, D, C) - P).ravel(), [1.0, 0.4, 1.0, 0.7, 0.95, 1.0],
                    bounds=([0.1, 0.05, 0.1, 0, 0.3, 0.1], [10, 2, 10, 3, 1, 10]))
print("sigma0, spread per m, A, b, p_max, upwind length:", np.round(fit.x, 3),
      "RMS residual", round(float(np.sqrt(np.mean(fit.fun ** 2))), 3))
